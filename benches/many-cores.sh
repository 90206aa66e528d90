#!/usr/bin/env bash
# The scaling table on a machine with many cores, in one short run: the model's prediction
# beside measured runs at 1–16 threads on three cost profiles (final: cheap sky, costly glass;
# cornell: walls in every pixel, no sky; next-week: boxes, fog, a black top), plus the quick speedup
# table with the paper's shared rand(). Made for a machine lent for minutes (no Rust there):
# build the release binary first, carry it, and run
#
#   benches/many-cores.sh OUT [THREADS]        # THREADS default 1,2,4,6,…,16
#
# (results/cores16.md: about 6 minutes on a 16-core Xeon lent for 15; cornell and next-week are
# small, at fewer thread counts, to fit, and the bench's last step, the paper table, did not.)
#
# Each step runs under its own time limit (a lent machine's minutes are counted), its output
# goes to OUT/log.txt, and every table and plot lands in OUT/results.tar (one file: lent
# machines return few). RAYPOOL_COMMIT names the binary's commit where the copy has no .git.
set -uo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: benches/many-cores.sh OUT [THREADS]}
threads=${2:-1,2,4,6,8,10,12,14,16}
raypool=${RAYPOOL:-target/release/raypool}
work=$(mktemp -d)
mkdir -p "$out"
log=$out/log.txt

# shellcheck source=benches/steps.sh
source benches/steps.sh

{ lscpu; echo "nproc $(nproc)"; date -u; echo "commit ${RAYPOOL_COMMIT:-$(git rev-parse --short HEAD 2>/dev/null)}"; } >"$work/machine.txt"
cp "$work/machine.txt" "$out/machine.txt"
step 200 final simulate --scene final --width 1200 --spp 8 --depth 50 --measure --runs 5 \
    --threads "$threads" --report "$work/final"
fewer=1,2,4,8,12,16
step 95 cornell simulate --scene cornell --width 240 --spp 16 --depth 50 --measure --runs 3 \
    --threads "$fewer" --report "$work/cornell"
step 95 next-week simulate --scene next-week --width 240 --spp 16 --depth 50 --measure --runs 3 \
    --threads "$fewer" --report "$work/next-week"
step 100 bench bench --quick --scenes final,paper1 --threads "$threads" --out-dir "$work/bench"
tar -C "$work" -cf "$out/results.tar" .
