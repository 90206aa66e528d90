#!/usr/bin/env bash
# The pool's per-job overhead before and after a change, paired in one run: alternates two
# builds of `cargo bench --bench pool` (overhead group only) and prints, per queue, the median
# of the paired ratios of Criterion's median times (before ÷ after; above 1 = after is faster).
# rayon's row is a control: its code is the same in both builds, so its ratios show the noise.
#
#   git worktree add ../before <old-commit> && (cd ../before && cargo bench --bench pool --no-run)
#   cargo bench --bench pool --no-run
#   benches/pool-paired.sh ../before/target/release/deps/pool-HASH target/release/deps/pool-HASH 4
#
# Usage: pool-paired.sh BEFORE_BENCH_BINARY AFTER_BENCH_BINARY [PAIRS=4]
set -euo pipefail
before=$(realpath "$1") after=$(realpath "$2") pairs=${3:-4}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
# Criterion's middle estimate for overhead/NAME, in ms, from one run's output.
median_ms() {
  awk -v name="overhead/$2" '$1 == name && $2 == "time:" { v = $5; u = $6 }
    END { if (u == "µs") v /= 1000; if (u == "s") v *= 1000; print v }' "$1"
}
for i in $(seq "$pairs"); do
  for side in before after; do
    mkdir -p "$scratch/$side"
    bin=$before; [ "$side" = after ] && bin=$after
    (cd "$scratch/$side" && "$bin" --bench overhead/ >"$scratch/$side/run$i.log" 2>&1)
  done
  for name in Shared Locked Stealing rayon; do
    b=$(median_ms "$scratch/before/run$i.log" "$name") a=$(median_ms "$scratch/after/run$i.log" "$name")
    echo "$name $b $a" | awk '{ printf "pair %d %-8s before %7.3f ms  after %7.3f ms  ratio %.3f\n", '"$i"', $1, $2, $3, $2 / $3 }'
  done
done | tee "$scratch/pairs.txt"
for name in Shared Locked Stealing rayon; do
  awk -v n="$name" '$3 == n { print $NF }' "$scratch/pairs.txt" | sort -n | awk -v n="$name" '{ r[NR] = $1 } END {
    m = (NR % 2) ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2
    printf "%-8s median of %d paired ratios (before / after): %.3f (min %.3f, max %.3f)\n", n, NR, m, r[1], r[NR] }'
done
