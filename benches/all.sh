#!/usr/bin/env bash
# Every benchmark table and plot the README cites, regenerated on this machine in one run (the
# records of one-off investigations it also cites are not: all.md lists them).
#
#   benches/all.sh [--quick] [--out-dir DIR]
#
# Writes into DIR (default: results/, the committed folder) through RAYPOOL_RESULTS, which
# every benchmark reads (src/measure/machine.rs: results_dir). Builds once per feature set, in
# an order that reuses builds: the release binary and every benchmark first (with `embree` when
# Debian's libembree-dev is installed), then the f64 builds of the two accuracy benchmarks.
# Prints a line per step and writes DIR/all.md: the machine (lscpu), the commit, each step's
# command, wall time and files; each step's own output goes to DIR/logs/STEP.log.
#
# --quick: smaller images, fewer samples, rounds and seeds (each file says so in its command
# line); about ten minutes on this project's 2-core machine. Without it, 45 minutes there.
# A step whose system package is missing (Chromium for the viewer, libembree-dev for Embree)
# is skipped and listed as skipped; every other failure stops the run.
set -euo pipefail
cd "$(dirname "$0")/.."

quick=0
out=results
while (($#)); do
    case $1 in
        --quick) quick=1 ;;
        --out-dir) out=${2:?--out-dir takes a folder}; shift ;;
        *) echo "usage: benches/all.sh [--quick] [--out-dir DIR]" >&2; exit 2 ;;
    esac
    shift
done
mkdir -p "$out/logs"
# $out stays as given, relative to the repository root (every step below runs from there), so
# the commands all.md and the logs record read the same in any clone.
export RAYPOOL_RESULTS=$out

q() { ((quick)) && printf '%s' "$1" || printf '%s' "$2"; }
bench_quick=$(q "-- --quick" "")

features=()
embree_missing=""
if [ -e /usr/include/embree3/rtcore.h ]; then
    features=(--features embree)
else
    embree_missing="libembree-dev is not installed (apt-get install -y libembree-dev)"
fi
chromium_missing=""
command -v chromium >/dev/null || chromium_missing="chromium is not installed (apt-get install -y chromium)"

cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
machine="nproc $(nproc), ${cpu:-unknown CPU}, commit $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- . ':!results' || echo +dirty), $(date -u +%Y-%m-%d)"
raypool=target/release/raypool

steps=() # "name|command|seconds|files"
total_start=$SECONDS
count=15
k=0

# run NAME FILES COMMAND...: one step, its output in logs/NAME.log.
run() {
    local name=$1 files=$2
    shift 2
    k=$((k + 1))
    printf '[%2d/%d] %-14s %s ... ' "$k" "$count" "$name" "$*"
    local start=$SECONDS
    if ! "$@" >"$out/logs/$name.log" 2>&1; then
        echo "failed after $((SECONDS - start)) s; the end of $out/logs/$name.log:"
        tail -20 "$out/logs/$name.log"
        exit 1
    fi
    echo "$((SECONDS - start)) s"
    steps+=("$name|\`$*\`|$((SECONDS - start))|$files")
}

# skip NAME WHY: a step that cannot run here.
skip() {
    k=$((k + 1))
    printf '[%2d/%d] %-14s SKIPPED: %s\n' "$k" "$count" "$1" "$2"
    steps+=("$1|skipped: $2|–|")
}


echo "benches/all.sh$(q ' --quick' '') → $out"
echo "machine: $machine"
# One build of every benchmark; it builds target/release/raypool too (benchmarks may run it).
run build "" cargo bench --no-run "${features[@]}"
run pool "pool.md" cargo bench --bench pool "${features[@]}" $bench_quick
run speedup "speedup.{md,csv,png}, timeline-*.png" cargo bench --bench speedup "${features[@]}" $bench_quick
run paper-table "paper-table.md" "$raypool" bench --paper --spp "$(q 5 50)" --out-dir "$out"
run ablation "ablation.md" cargo bench --bench ablation "${features[@]}" $bench_quick
if [ -z "$embree_missing" ]; then
    run embree "embree.md" cargo bench --bench embree "${features[@]}" $bench_quick
else
    skip embree "$embree_missing"
fi
run scaling "scaling.{md,csv,png}" "$raypool" simulate --scene final --width "$(q 400 1200)" --spp 8 --depth 50 \
    --measure --runs "$(q 3 5)" --report "$out"
# The README's picture at the book's full settings (default sampler and mode, all CPUs).
fullsize=(--scene final --width 1200 --spp "$(q 50 500)" --depth 50)
run fullsize "final.{png,md}" "$raypool" render "${fullsize[@]}" --out "$out/final.png"
{
    echo "# The README's picture: \`final\` at the book's full settings"
    echo
    echo "Command: \`raypool render ${fullsize[*]} --out final.png\` · $machine"
    echo
    echo "Its summary line: \`$(tail -1 "$out/logs/fullsize.log")\`"
} >"$out/final.md"
run bias "bias.md" cargo bench --bench bias "${features[@]}" $bench_quick
if [ -z "$chromium_missing" ]; then
    run view "view.{md,png}" cargo bench --bench view "${features[@]}"
    run view-hostile "view-hostile.md" cargo bench --bench view_hostile "${features[@]}" $bench_quick
else
    skip view "$chromium_missing"
    skip view-hostile "$chromium_missing"
fi
run error "error.{md,png}, error-f32.csv" cargo bench --bench error "${features[@]}" $bench_quick
run stability "stability.md, stability-f32.csv" cargo bench --bench stability "${features[@]}"
# The f64 builds last (one rebuild): each writes its precision's CSV, and the table reads both.
# They also leave an f64 build at target/release/raypool, so every step that runs the binary
# comes before them; the build step above put the f32 one there (cargo relinks it even when
# nothing is rebuilt), and the end of this script puts it back.
run error-f64 "error.{md,png}, error-f64.csv" cargo bench --bench error --features f64 $bench_quick
run stability-f64 "stability.md, stability-f64.csv" cargo bench --bench stability --features f64

cargo bench --no-run "${features[@]}" >/dev/null 2>&1 # target/release/raypool: f32 again

{
    echo "# The README's benchmark figures, regenerated"
    echo
    echo "Command: \`benches/all.sh$(q ' --quick' '')\` · $machine · $((SECONDS - total_start)) s in all."
    echo
    echo "| step | command | wall time (s) | writes |"
    echo "|---|---|---:|---|"
    for step in "${steps[@]}"; do
        IFS='|' read -r name command seconds files <<<"$step"
        echo "| $name | $command | $seconds | $files |"
    done
    echo
    echo "Each step's output is in \`logs/\`. Not regenerated here: the records of one-off"
    echo "investigations (\`perf.md\`, \`accumulation.md\`, \`adaptive.md\`, \`sobol-spp.md\`,"
    echo "\`tile-size.md\`, \`fullsize.md\`, \`pool-mutants.md\`, \`course/\`, \`cores16.md\` and \`cores16/\`, measured on"
    echo "a 16-core machine by \`benches/many-cores.sh\`), which name their own commands."
} >"$out/all.md"
echo "done in $((SECONDS - total_start)) s: $out/all.md"
