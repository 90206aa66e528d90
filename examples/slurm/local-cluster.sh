#!/usr/bin/env bash
# A real single-node Slurm cluster on this machine, for trying the batch scripts (and for
# raypool's Slurm test): munged, slurmctld and slurmd from Debian's munge and slurm-wlm,
# started directly (no systemd), all state in one directory, stopped by the PIDs in their
# pid files.
#
#   examples/slurm/local-cluster.sh start DIR   # writes DIR/slurm.conf; prints `export SLURM_CONF=…`
#   examples/slurm/local-cluster.sh stop DIR    # stops the three daemons, waits until they are gone
#
# Needs root (the daemons run as root, munged as user munge) and the packages:
#   apt-get install -y slurm-wlm munge
# The node is `hostname -s` (reached at 127.0.0.1, so no name lookup is needed) with `nproc`
# CPUs; ports 6817/6818 unless SLURM_PORTS="CTLD D".
set -euo pipefail

usage() { echo "usage: $0 start|stop DIR" >&2; exit 2; }
[ $# -eq 2 ] || usage
action=$1
dir=$(mkdir -p "$2" && cd "$2" && pwd)

# Whether process $1 runs (exists and is not a zombie waiting to be reaped).
running() {
    [ -r "/proc/$1/stat" ] && ! sed 's/.*) //' "/proc/$1/stat" | grep -q '^Z'
}

# Sends TERM to the process in pid file $1, then waits (10 s, then KILL) until it is gone.
stop_pid_file() {
    local file=$1 pid
    [ -s "$file" ] || return 0
    pid=$(cat "$file")
    if running "$pid"; then
        kill -TERM "$pid" 2>/dev/null || true
        for _ in $(seq 100); do running "$pid" || break; sleep 0.1; done
        if running "$pid"; then kill -KILL "$pid" 2>/dev/null || true; fi
    fi
    rm -f "$file"
}

stop() {
    stop_pid_file "$dir/slurmd.pid"
    stop_pid_file "$dir/slurmctld.pid"
    stop_pid_file "$dir/munge/munged.pid"
}

start() {
    for tool in munged slurmctld slurmd sbatch; do
        command -v "$tool" >/dev/null || { echo "$0: $tool not found: apt-get install -y slurm-wlm munge" >&2; exit 1; }
    done
    [ "$(id -u)" -eq 0 ] || { echo "$0: must run as root (the daemons run as root and munge)" >&2; exit 1; }
    local node cpus ports ctld_port d_port
    node=$(hostname -s)
    cpus=$(nproc)
    read -r ctld_port d_port <<<"${SLURM_PORTS:-6817 6818}"

    # munge: a key (the package's, or a new one), then munged as user munge.
    if [ ! -s /etc/munge/munge.key ]; then
        mkdir -p /etc/munge
        dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=128 status=none
        chown munge:munge /etc/munge /etc/munge/munge.key
        chmod 0700 /etc/munge
        chmod 0400 /etc/munge/munge.key
    fi
    mkdir -p "$dir/munge" "$dir/ctld" "$dir/d"
    chown munge:munge "$dir/munge"
    chmod 0755 "$dir/munge"
    runuser -u munge -- munged --force \
        --socket="$dir/munge/munge.socket" \
        --pid-file="$dir/munge/munged.pid" \
        --log-file="$dir/munge/munged.log" \
        --seed-file="$dir/munge/munged.seed" \
        --key-file=/etc/munge/munge.key

    cat >"$dir/slurm.conf" <<CONF
ClusterName=raypool-local
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$dir/ctld
SlurmdSpoolDir=$dir/d
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=local Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF

    export SLURM_CONF="$dir/slurm.conf"
    slurmctld -i
    slurmd
    # Wait until the node takes jobs.
    for _ in $(seq 100); do
        if sinfo -h -o '%T' 2>/dev/null | grep -Eq '^(idle|mixed|allocated)'; then
            echo "export SLURM_CONF=$dir/slurm.conf"
            return 0
        fi
        sleep 0.2
    done
    echo "$0: the node did not come up; see $dir/slurmctld.log and $dir/slurmd.log" >&2
    stop
    exit 1
}

case $action in
start) start ;;
stop) stop ;;
*) usage ;;
esac
