#!/usr/bin/env bash
# What benches/many-cores.sh could not fit in its lent minutes (results/cores16.md), in one
# short run on a machine with many cores:
#   1. the paper's table at one thread per CPU (`raypool bench --paper --spp 2`: the step that
#      `bench --quick` runs last, alone; 1200 × 800, scaled to the paper's 500 spp);
#   2. cornell and next-week 400 wide (measured only 240 wide before: more rows and tiles);
#   3. paths never measured past 2 threads: cornell under --light-sampling bdpt (light paths
#      splat into other pixels, merged once every tile is in) and the triangle scene `mesh`.
# Each of 2 and 3 is `raypool simulate --measure`: the model's prediction beside measured
# runs. Made for a machine lent for minutes (no Rust there): build the release binary first,
# carry it, and run
#
#   RAYPOOL=path/to/raypool benches/many-cores-more.sh OUT [THREADS]   # THREADS default 1,2,4,8,16
#
# Sized for a 16-core Xeon whose cores run about 1.1–1.7× this project's 2-core machine's
# time per thread: every step's limit together 400 s; it took 277 s there
# (results/cores16-more.md).
# MORE_SMOKE=1 runs the same steps tiny (a test on a small machine: threads 1,2, seconds).
#
# Each step runs under its own time limit (a lent machine's minutes are counted), its output
# goes to OUT/log.txt, and every table and plot lands in OUT/results.tar (one file: lent
# machines return few). RAYPOOL_COMMIT names the binary's commit where the copy has no .git.
set -uo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: RAYPOOL=BIN benches/many-cores-more.sh OUT [THREADS]}
threads=${2:-1,2,4,8,16}
raypool=${RAYPOOL:-target/release/raypool}
work=$(mktemp -d)
mkdir -p "$out"
log=$out/log.txt

# shellcheck source=benches/steps.sh
source benches/steps.sh

# Sizes: width and spp per simulate step, the paper table's spp, simulate's rounds.
if [ "${MORE_SMOKE:-0}" = 1 ]; then
    paper_spp=1 runs=1
    cornell=(--width 48 --spp 2) next_week=(--width 48 --spp 2)
    bdpt=(--width 40 --spp 2) mesh=(--width 48 --spp 2)
else
    paper_spp=2 runs=3
    cornell=(--width 400 --spp 8) next_week=(--width 400 --spp 5)
    bdpt=(--width 240 --spp 5) mesh=(--width 400 --spp 12)
fi
simulate() { # simulate SECONDS NAME SCENE ARGS...: the model beside measured runs
    local limit=$1 name=$2 scene=$3
    shift 3
    step "$limit" "$name" simulate --scene "$scene" "$@" --depth 50 --measure --runs "$runs" \
        --threads "$threads" --report "$work/$name"
}

{ lscpu; echo "nproc $(nproc)"; date -u; echo "commit ${RAYPOOL_COMMIT:-$(git rev-parse --short HEAD 2>/dev/null)}"; } >"$work/machine.txt"
cp "$work/machine.txt" "$out/machine.txt"
step 80 paper bench --paper --spp "$paper_spp" --out-dir "$work/paper"
simulate 95 cornell-400 cornell "${cornell[@]}"
simulate 90 next-week-400 next-week "${next_week[@]}"
simulate 80 cornell-bdpt cornell "${bdpt[@]}" --light-sampling bdpt
simulate 55 mesh mesh "${mesh[@]}"
tar -C "$work" -cf "$out/results.tar" .
echo "== done: $SECONDS s" | tee -a "$log"
