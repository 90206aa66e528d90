# Sourced by the lent-machine scripts (many-cores.sh, many-cores-more.sh): `step`, one raypool
# run under its own time limit (a lent machine's minutes are counted), its command, output and
# exit status appended to the log. Needs `raypool` (the binary) and `log` (the log's path).

step() { # step SECONDS NAME ARGS...: one raypool run, its output appended to the log
    local limit=$1 name=$2
    shift 2
    echo "== $name: raypool $* (limit ${limit} s)" | tee -a "$log"
    local start=$SECONDS
    timeout "$limit" "$raypool" "$@" >>"$log" 2>&1
    echo "== $name: exit $?, $((SECONDS - start)) s" | tee -a "$log"
}
