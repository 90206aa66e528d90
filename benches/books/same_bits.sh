#!/usr/bin/env bash
# Same bytes before and after a change that must not move a pixel: renders every built-in
# scene under both samplers, the lit scenes under every --light-sampling, and a few other
# settings (--accel flat, roulette, two threads, edge points off), each with the two
# binaries, and compares the images byte for byte (PFM: the float pixels themselves).
#
# Usage: benches/books/same_bits.sh OLD-RAYPOOL NEW-RAYPOOL [WIDTH=48] [SPP=8]
# Prints one line per render that differs and a count; exits 1 if any differs.
set -euo pipefail
old=$1 new=$2 width=${3:-48} spp=${4:-8}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
settings=()
for scene in $("$new" scenes | awk '{ print $1 }'); do
  for sampler in sobol independent; do settings+=("--scene $scene --sampler $sampler"); done
done
for scene in cornell cornell-smoke next-week quads; do
  for light in bsdf mixture mis bdpt; do settings+=("--scene $scene --light-sampling $light"); done
  settings+=("--scene $scene --accel flat" "--scene $scene --roulette --light-sampling bsdf"
    "--scene $scene --mode steal --threads 2" "--scene $scene --edge-spots 0 --sampler independent")
done
differ=0
for k in "${!settings[@]}"; do
  # shellcheck disable=SC2086 # each setting is a list of flags
  for bin in old new; do
    "${!bin}" render ${settings[k]} --width "$width" --spp "$spp" --out "$out/$bin-$k.pfm" > /dev/null 2>&1
  done
  if ! cmp -s "$out/old-$k.pfm" "$out/new-$k.pfm"; then
    echo "differs: ${settings[k]}"
    differ=$((differ + 1))
  fi
done
echo "${#settings[@]} renders at ${width} px, $spp spp: $differ differ"
(( differ == 0 ))
