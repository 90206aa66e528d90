#!/usr/bin/env bash
# Renders one image as N Slurm array tasks, then merges them in a job that starts only if
# every task succeeded. Prints the two job ids ("ARRAY MERGE").
#
#   RAYPOOL=/shared/raypool PARTS=/shared/parts \
#     examples/slurm/submit.sh N OUT.png [raypool render options…]
#
# RAYPOOL and PARTS must be on a filesystem every node sees. Site options (partition,
# account, time) go in SBATCH_* variables, e.g. SBATCH_PARTITION=short, or in the #SBATCH
# lines of render.sbatch.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 N OUT.png [raypool render options…]" >&2; exit 2; }
n=$1 out=$2
shift 2
[[ $n =~ ^[1-9][0-9]*$ ]] || { echo "$0: N must be a positive whole number, not '$n'" >&2; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
: "${RAYPOOL:?set RAYPOOL to the raypool binary (on a shared filesystem)}"
: "${PARTS:?set PARTS to a directory for the parts (on a shared filesystem)}"
mkdir -p "$PARTS"
export RAYPOOL PARTS OUT="$out"

array=$(sbatch --parsable --array="0-$((n - 1))" --output="$PARTS/render-%a.log" \
    "$here/render.sbatch" "$@")
array=${array%%;*} # "id;cluster" on multi-cluster sites
merge=$(sbatch --parsable --dependency="afterok:$array" --kill-on-invalid-dep=yes \
    --output="$PARTS/merge.log" "$here/merge.sbatch")
echo "$array ${merge%%;*}"
