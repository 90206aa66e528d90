#!/usr/bin/env bash
# Break it: plant one of the bugs below in a copy of the pool, and watch the checks catch it.
#
#   pool/break-it/run.sh lost-wakeup            sleep.rs: a sleeper registers after it looks
#   pool/break-it/run.sh early-latch            worker.rs: the latch opens before the bookkeeping
#   pool/break-it/run.sh waiter-does-not-help   batch.rs: a waiting worker just sleeps
#
#   pool/break-it/run.sh --check [NAME…]        what CI runs (.ci/run): plants each bug (default:
#                                               every *.patch here) and requires that the test its
#                                               patch names on its `caught-by:` line fails
#
# Your checkout is not touched: the patch is applied to a copy in a temporary folder. Builds go
# to target/break-it*, so only the first run compiles the dependencies (about a minute).
# NAME alone prints what the loom models say, then what the stress tests say; exits 0 if the
# bug was caught, 1 if every check passed (then the checks have a hole: please report it).
# --check runs only the catching test of each patch (a minute or so each) and exits 1 if a
# patch no longer applies or its test passes.
#
# A patch opens with a few lines of text (ignored by `patch` and `git apply`), one of them
#   caught-by: loom|stress lib|TESTFILE TEST_NAME
# e.g. `caught-by: stress contract a_waiting_worker_returns_as_soon_as_its_batch_is_done`: the stress build
# (real threads) of `pool/tests/contract.rs`, or the loom build (`--cfg loom`) of the crate's
# own models (`lib`) or of `pool/tests/TESTFILE.rs`.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
usage="usage: pool/break-it/run.sh NAME | --check [NAME…]   (NAME: $(cd "$root/pool/break-it" && ls *.patch | sed 's/\.patch$//' | tr '\n' ' '))"
# Every wait of a stress test gives up after this many seconds (pool::deadline).
export RAYPOOL_TEST_DEADLINE=${RAYPOOL_TEST_DEADLINE:-15}

# Copies the pool into a new temporary folder and plants bug $1 there; prints the folder.
plant() {
    local bug=$1 work
    [ -f "$root/pool/break-it/$bug.patch" ] || { echo "no such bug: $bug ($usage)" >&2; exit 2; }
    work=$(mktemp -d)
    cp -r "$root/pool" "$work/pool"
    cp "$root/Cargo.lock" "$work/pool/Cargo.lock"
    (cd "$work" && patch -s -p1 <"$root/pool/break-it/$bug.patch") ||
        { echo "$bug.patch no longer applies to pool/: regenerate it against the code it breaks" >&2; exit 1; }
    echo "$work"
}

# cargo test on the planted copy in folder $1, as build $2 (loom or stress); the rest: cargo's
# arguments.
planted_test() {
    local work=$1 kind=$2
    shift 2
    if [ "$kind" = loom ]; then
        RUSTFLAGS="--cfg loom" LOOM_MAX_PREEMPTIONS=3 LOOM_LOCATION=1 CARGO_TARGET_DIR="$root/target/break-it-loom" \
            cargo test --manifest-path "$work/pool/Cargo.toml" --release "$@"
    else
        CARGO_TARGET_DIR="$root/target/break-it" cargo test --manifest-path "$work/pool/Cargo.toml" --release "$@"
    fi
}

if [ "${1:-}" = --check ]; then
    shift
    bugs=("$@")
    [ ${#bugs[@]} -gt 0 ] || bugs=($(cd "$root/pool/break-it" && ls *.patch | sed 's/\.patch$//'))
    failed=()
    for bug in "${bugs[@]}"; do
        start=$SECONDS
        read -r kind target test < <(sed -n 's/^caught-by: //p' "$root/pool/break-it/$bug.patch")
        [ -n "${test:-}" ] || { echo "$bug.patch has no 'caught-by: KIND TARGET TEST' line" >&2; exit 2; }
        work=$(plant "$bug")
        if [ "$target" = lib ]; then which=(--lib); else which=(--test "$target"); fi
        # Build first, so that a build error is not mistaken for a catch.
        planted_test "$work" "$kind" "${which[@]}" --no-run >"$work/build.log" 2>&1 ||
            { cat "$work/build.log" >&2; echo "$bug: the planted copy does not build" >&2; rm -rf "$work"; exit 1; }
        if planted_test "$work" "$kind" "${which[@]}" -- --exact "$test" >"$work/test.log" 2>&1; then
            echo "$bug: NOT caught: $kind $target $test passed with the bug planted"
            failed+=("$bug")
        elif grep -q "$test.*FAILED\|FAILED.*$test\|^    $test$" "$work/test.log"; then
            echo "$bug: caught by $kind $target $test ($((SECONDS - start)) s, build included):"
            grep -E "FAILED|^deadlock|panicked at|never happened|^  left|^ right" "$work/test.log" | head -6 | sed 's/^/    /'
        else
            echo "$bug: the run failed, but not by $test failing:"
            tail -20 "$work/test.log" | sed 's/^/    /'
            failed+=("$bug")
        fi
        rm -rf "$work"
    done
    [ ${#failed[@]} -eq 0 ] || { echo "not caught as their patches say: ${failed[*]}" >&2; exit 1; }
    exit 0
fi

bug=${1:?$usage}
work=$(plant "$bug")
trap 'rm -rf "$work"' EXIT
echo "== planted: $bug =="
sed -n '/^[-+][^-+]/p' "$root/pool/break-it/$bug.patch"
caught=()

echo
echo "== loom: every interleaving of the small models (LOOM_MAX_PREEMPTIONS=3) =="
if planted_test "$work" loom --lib --test loom --no-fail-fast >"$work/loom.log" 2>&1; then :; else caught+=(loom); fi
grep -E "^test |^deadlock|panicked at|^assertion|^  left|^ right|never|^test result" "$work/loom.log" || true

echo
echo "== stress tests on real threads (deadline $RAYPOOL_TEST_DEADLINE s a step) =="
if planted_test "$work" stress --test races --test contract --no-fail-fast >"$work/stress.log" 2>&1; then :; else caught+=(stress); fi
grep -E "^test .*FAILED|panicked at|never happened|lost wake|did not wake|^assertion|^  left|^ right|^test result" "$work/stress.log" || true

echo
if [ ${#caught[@]} -gt 0 ]; then echo "caught by: ${caught[*]}"; else echo "NOT caught"; exit 1; fi
