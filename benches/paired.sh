#!/usr/bin/env bash
# Before/after in one run: alternate two raypool binaries on the same render and print the
# median of the paired ratios (before time ÷ after time; above 1 = the second is faster).
# Absolute times on a shared machine drift by 10% and more; paired ratios cancel the drift.
#
#   git worktree add ../before <old-commit> && (cd ../before && cargo build --release)
#   benches/paired.sh ../before/target/release/raypool target/release/raypool 7 final
#
# Usage: paired.sh BEFORE AFTER [PAIRS=7] [SCENE=final] [render flags...]
# Without render flags: 400 pixels wide, 8 spp, depth 50, one thread, serial.
set -euo pipefail
before=$1 after=$2 pairs=${3:-7} scene=${4:-final}
shift $(( $# < 4 ? $# : 4 ))
if (( $# == 0 )); then set -- --width 400 --spp 8 --threads 1 --mode serial; fi
flags=(--scene "$scene" "$@")
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
seconds() {
  local line
  line=$("$1" render "${flags[@]}" --out "$out/x.pfm" 2>&1) || { echo "$1: $line" >&2; exit 2; }
  grep -o '[0-9.]* s,' <<<"$line" | tr -d ' s,'
}
ratios=()
for _ in $(seq "$pairs"); do
  b=$(seconds "$before")
  a=$(seconds "$after")
  ratios+=("$(awk -v b="$b" -v a="$a" 'BEGIN { printf "%.4f", b / a }')")
  echo "before ${b} s, after ${a} s, ratio ${ratios[-1]}"
done
printf '%s\n' "${ratios[@]}" | sort -n | awk '{ r[NR] = $1 } END {
  m = (NR % 2) ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2
  printf "median of %d paired ratios (before / after): %.3f (min %.3f, max %.3f)\n", NR, m, r[1], r[NR] }'
