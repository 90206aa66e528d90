#!/usr/bin/env bash
# Break it: plant one of the bugs below in a copy of the pool, and watch the checks catch it.
#
#   pool/break-it/run.sh lost-wakeup            sleep.rs: a sleeper registers after it looks
#   pool/break-it/run.sh early-latch            worker.rs: the latch opens before the bookkeeping
#   pool/break-it/run.sh waiter-does-not-help   batch.rs: a waiting worker just sleeps
#
# Your checkout is not touched: the patch is applied to a copy in a temporary folder. Builds go
# to target/break-it*, so only the first run compiles the dependencies (about a minute).
# Prints what the loom models say, then what the stress tests say; exits 0 if the bug was
# caught, 1 if every check passed (then the checks have a hole: please report it).
set -euo pipefail
bug=${1:?usage: pool/break-it/run.sh lost-wakeup|early-latch|waiter-does-not-help}
root=$(cd "$(dirname "$0")/../.." && pwd)
[ -f "$root/pool/break-it/$bug.patch" ] || { echo "no such bug: $bug (see pool/break-it/*.patch)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp -r "$root/pool" "$work/pool"
cp "$root/Cargo.lock" "$work/pool/Cargo.lock"
(cd "$work" && patch -s -p1 <"$root/pool/break-it/$bug.patch")
echo "== planted: $bug =="
sed -n '/^[-+][^-+]/p' "$root/pool/break-it/$bug.patch"
manifest=(--manifest-path "$work/pool/Cargo.toml" --release)
caught=()

echo
echo "== loom: every interleaving of the small models (LOOM_MAX_PREEMPTIONS=3) =="
if RUSTFLAGS="--cfg loom" LOOM_MAX_PREEMPTIONS=3 LOOM_LOCATION=1 CARGO_TARGET_DIR="$root/target/break-it-loom" \
    cargo test "${manifest[@]}" --lib --test loom --no-fail-fast >"$work/loom.log" 2>&1; then :; else caught+=(loom); fi
grep -E "^test |^deadlock|panicked at|^assertion|^  left|^ right|never|^test result" "$work/loom.log" || true

echo
echo "== stress tests on real threads (deadline ${POOL_TEST_DEADLINE:=15} s a step) =="
export POOL_TEST_DEADLINE
if CARGO_TARGET_DIR="$root/target/break-it" \
    cargo test "${manifest[@]}" --test races --test contract --no-fail-fast >"$work/stress.log" 2>&1; then :; else caught+=(stress); fi
grep -E "^test .*FAILED|panicked at|never happened|lost wake|did not wake|^assertion|^  left|^ right|^test result" "$work/stress.log" || true

echo
if [ ${#caught[@]} -gt 0 ]; then echo "caught by: ${caught[*]}"; else echo "NOT caught"; exit 1; fi
