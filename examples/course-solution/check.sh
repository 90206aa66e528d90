#!/usr/bin/env bash
# The instructor's check of the course kit, end to end, on a copy of the starter:
#   1. the untouched starter builds, and its tests fail (the todo!()s);
#   2. with the solution copied in, its tests pass and the grader gives full marks;
#   3. with each wrong scheduler of wrong/ copied in, the tests fail and the grader says why.
# Reports land in $OUT (default: a temporary folder); THREADS (default 1,2) is the grader's
# thread list. Usage: [OUT=dir] [THREADS=1,2,4] examples/course-solution/check.sh
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
out=${OUT:-$(mktemp -d)}
mkdir -p "$out"
out=$(cd "$out" && pwd) # the steps below run in the copy
threads=${THREADS:-1,2}
work=$(mktemp -d)
# The copy sits where the starter does, so that its path dependencies (../..) still resolve.
copy="$repo/examples/.course-check"
trap 'rm -rf "$work" "$copy"' EXIT
rm -rf "$copy"
cp -r "$repo/examples/course" "$copy"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$repo/target/course}"
cd "$copy"

step() { echo "== $*" >&2; }
grade() { # grade OUTFILE [ARGS…]: the copy's grader; its log is shown if it fails
    local report=$1; shift
    cargo run --release --quiet --bin grade -- --threads "$threads" --out "$report" "$@" \
        >/dev/null 2>"$work/grade.log" || { cat "$work/grade.log" >&2; exit 1; }
}
tests_fail() {
    if cargo test --release --quiet >"$work/test.log" 2>&1; then
        echo "expected the tests to fail ($1), and they passed" >&2; exit 1
    fi
    echo "   tests fail, as they should ($1):" >&2
    grep -E "panicked at|FAILED|conformance" "$work/test.log" | head -4 | sed 's/^/     /' >&2
}

step "1. the untouched starter"
cargo build --release --quiet
tests_fail "the skeleton's todo!()s"

step "2. the solution"
cp "$here/scheduler.rs" src/scheduler.rs
cp "$here/discipline.rs" src/discipline.rs
cargo test --release --quiet 2>&1 | grep "test result" | sed "s/^/   /" >&2
grade "$out/grade-solution.md"
grep -h "Score" "$out/grade-solution.md" | sed 's/^/   /' >&2

step "3. the wrong schedulers"
for wrong in "$here"/wrong/*.rs; do
    name=$(basename "$wrong" .rs)
    cp "$wrong" src/scheduler.rs
    tests_fail "$name"
    grade "$out/grade-$name.md" --part scheduler
    grep -h "Conformance\|Score" "$out/grade-$name.md" | sed 's/^/   /' >&2
done
echo "reports in $out" >&2
