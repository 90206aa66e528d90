#!/usr/bin/env bash
# The pictures of results/renders.md: every scene of the second book's world, rendered by the
# release binary on this machine, with its summary line. Usage: benches/renders.sh [threads]
set -euo pipefail
cd "$(dirname "$0")/.."
threads=${1:-2}
bin=target/release/raypool
out=results/renders
mkdir -p "$out"
{
  echo "| scene | size | spp | time | rays | Mrays/s | picture |"
  echo "|---|---|---|---|---|---|---|"
  for spec in cornell:300:256 cornell-smoke:300:256 next-week:300:256 quads:300:64 perlin:400:64 bouncing:400:64 mesh:400:64; do
    IFS=: read -r scene width spp <<<"$spec"
    line=$("$bin" render --scene "$scene" --width "$width" --spp "$spp" --threads "$threads" --out "$out/$scene.png" 2>&1 | tail -1)
    # e.g. "300x300, 256 spp, depth 50, mode steal, threads 2: 14.2 s, 123 rays, 9.1 Mrays/s -> …"
    size=${line%%,*}
    time=$(sed -E 's/.*: ([0-9.]+ s), .*/\1/' <<<"$line")
    rays=$(sed -E 's/.*s, ([0-9]+) rays.*/\1/' <<<"$line")
    rate=$(sed -E 's/.* ([0-9.]+) Mrays\/s.*/\1/' <<<"$line")
    echo "| \`$scene\` | $size | $spp | $time | $rays | $rate | ![$scene](renders/$scene.png) |"
  done
} > "$out/table.md"
cat "$out/table.md"
