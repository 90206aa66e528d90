#!/usr/bin/env bash
# The instructor's check of the course kit, end to end, on a students' handout:
#   0. handout.sh makes the handout; it holds no solution, cheat or check;
#   1. the untouched starter builds, and its tests fail (the todo!()s);
#   2. with part 1 solved only: part 1's test passes alone, `cargo test` runs it before
#      failing at part 2, and the grader names the unfinished part without a backtrace;
#   3. with both solved: the tests pass and the grader passes them (exit 0; or 3 when the
#      machine is too busy to judge, which it then says);
#   4. with each wrong scheduler of wrong/: the tests fail, the grader fails it (exit 1)
#      and says why.
# Reports land in $OUT (default: a temporary folder); THREADS (default 1,2) is the grader's
# thread list. Usage: [OUT=dir] [THREADS=1,2,4] examples/course-solution/check.sh
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
out=${OUT:-$(mktemp -d)}
mkdir -p "$out"
out=$(cd "$out" && pwd) # the steps below run in the handout
threads=${THREADS:-1,2}
work=$(mktemp -d)
# A fixed place (ignored by git), so that a second run reuses the first one's build.
handout="$repo/target/course-handout"
trap 'rm -rf "$work"' EXIT
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$repo/target/course}"

step() { echo "== $*" >&2; }
fail() { echo "check.sh: $*" >&2; exit 1; }
grade() { # grade WANTED_EXIT OUTFILE [ARGS…]: the handout's grader; its log is shown if the exit code is not wanted
    local wanted=$1 report=$2; shift 2
    local code=0
    cargo run --release --quiet --bin grade -- --threads "$threads" --out "$report" "$@" \
        >/dev/null 2>"$work/grade.log" || code=$?
    if [ "$code" = 3 ] && [ "$wanted" = 0 ]; then
        echo "   the machine was too busy to judge (exit 3); the report says so" >&2
    elif [ "$code" != "$wanted" ]; then
        cat "$work/grade.log" >&2
        fail "the grader exited with $code, expected $wanted"
    fi
    if grep -q "stack backtrace\|RUST_BACKTRACE" "$work/grade.log"; then
        cat "$work/grade.log" >&2
        fail "the grader printed a backtrace"
    fi
}
tests_fail() { # tests_fail WHY [CARGO TEST ARGS…]
    local why=$1; shift
    if cargo test --release "$@" >"$work/test.log" 2>&1; then
        fail "expected the tests to fail ($why), and they passed"
    fi
    echo "   tests fail, as they should ($why):" >&2
    grep -E "panicked at|FAILED|conformance" "$work/test.log" | head -4 | sed 's/^/     /' >&2
}

step "0. the handout"
rm -rf "$handout"
"$here/handout.sh" "$handout" 2>/dev/null
for secret in examples/course-solution tests/course.rs .ci; do
    [ ! -e "$handout/$secret" ] || fail "the handout holds $secret"
done
cd "$handout/examples/course"
[ -f README.md ] || fail "the handout has no student README"

step "1. the untouched starter"
cargo build --release --quiet
tests_fail "the skeleton's todo!()s"

step "2. part 1 solved, part 2 not"
cp "$here/scheduler.rs" src/scheduler.rs
cargo test --release --quiet --test scheduler 2>&1 | grep "test result" | sed "s/^/   part 1 alone: /" >&2
tests_fail "part 2's todo!()"
grep -q "renders_every_pixel_once_in_parallel_and_matches_serial ... ok" "$work/test.log" \
    || fail "cargo test did not run part 1's test before stopping at part 2"
grade 1 "$out/grade-part1-only.md"
grep -q "discipline" "$out/grade-part1-only.md" && grep -q "not yet implemented" "$out/grade-part1-only.md" \
    || fail "the grader did not name the unfinished part"
grep -h "Conformance" "$out/grade-part1-only.md" | sed 's/^/   /' >&2

step "3. both solved"
cp "$here/discipline.rs" src/discipline.rs
cargo test --release --quiet 2>&1 | grep "test result" | sed "s/^/   /" >&2
grade 0 "$out/grade-solution.md"
grep -h "Score" "$out/grade-solution.md" | sed 's/^/   /' >&2

step "4. the wrong schedulers"
for wrong in "$here"/wrong/*.rs; do
    name=$(basename "$wrong" .rs)
    cp "$wrong" src/scheduler.rs
    tests_fail "$name" --test scheduler
    grade 1 "$out/grade-$name.md" --part scheduler
    grep -h "Conformance\|Score" "$out/grade-$name.md" | sed 's/^/   /' >&2
done
echo "reports in $out" >&2
