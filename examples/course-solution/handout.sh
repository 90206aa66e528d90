#!/usr/bin/env bash
# The students' copy of raypool: this working tree's files (tracked, or new and not ignored)
# without what students must not see or cannot build: this folder (the solutions, the cheats,
# the kit's check), raypool's own test of the kit (tests/course.rs, which includes the
# solutions) and .ci/ (which runs that check). Students work in OUT/examples/course, whose
# README.md is theirs. Usage: examples/course-solution/handout.sh OUT_DIR (new or empty)
set -euo pipefail
out=${1:?usage: examples/course-solution/handout.sh OUT_DIR}
repo=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out"
if [ -n "$(ls -A "$out")" ]; then
    echo "handout.sh: $out is not empty: give a new or empty folder" >&2
    exit 2
fi
cd "$repo"
git ls-files -co --exclude-standard --deduplicate \
    | grep -v -e '^examples/course-solution/' -e '^tests/course\.rs$' -e '^\.ci/' \
    | while IFS= read -r f; do [ -e "$f" ] && printf '%s\0' "$f"; done \
    | tar --null -T - -cf - | tar -xf - -C "$out"
echo "handout.sh: the students' copy is in $out (they start in $out/examples/course)" >&2
