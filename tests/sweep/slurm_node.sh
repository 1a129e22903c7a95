#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# A real single-node Slurm cluster on this machine, private to one folder (docs/sweeps.md,
# "Trying the Slurm route on one machine"): its own munge key and socket, slurm.conf, state and
# spool folders, logs and ports, so that it neither needs nor touches /etc/slurm, the system's
# munged or a running cluster. Debian's slurm-wlm and munge (scripts/setup.sh installs them).
# Runs as root (slurmd starts the jobs as their submitter).
#
#   slurm_node.sh start DIR [CPUS]  start munged, slurmctld and slurmd; wait until the node is
#                                   idle; print the line to eval: SLURM_CONF=DIR/slurm.conf
#   slurm_node.sh stop DIR          stop the three daemons started in DIR
#
# Exit status: 0 done; 1 a daemon did not start or the node did not come up (its log is
# printed); 2 usage.
set -eu

usage() {
    echo "usage: $0 start DIR [CPUS] | stop DIR" >&2
    exit 2
}
[ $# -ge 2 ] || usage
cmd=$1
dir=$2
cpus=${3:-$(nproc)}

stop_pid() { # pidfile: TERM, then KILL after 10 s
    [ -f "$1" ] || return 0
    pid=$(cat "$1" 2>/dev/null || true)
    [ -n "$pid" ] || return 0
    kill "$pid" 2>/dev/null || return 0
    i=0
    while kill -0 "$pid" 2>/dev/null && [ $i -lt 100 ]; do
        sleep 0.1
        i=$((i + 1))
    done
    kill -9 "$pid" 2>/dev/null || true
    rm -f "$1"
}

case $cmd in
stop)
    # Cancel what is left in the queue first and wait for it to drain (at most 60 s: the
    # tasks get SIGTERM, then SIGKILL after KillWait), so that no job outlives the cluster.
    if [ -f "$dir/slurmctld.pid" ] && [ -f "$dir/slurm.conf" ]; then
        export SLURM_CONF="$dir/slurm.conf"
        jobs=$(squeue --noheader --format %A 2>/dev/null || true)
        [ -z "$jobs" ] || scancel $jobs 2>/dev/null || true
        i=0
        while [ -n "$(squeue --noheader --format %A 2>/dev/null || true)" ] && [ $i -lt 600 ]; do
            sleep 0.1
            i=$((i + 1))
        done
    fi
    stop_pid "$dir/slurmd.pid"
    stop_pid "$dir/slurmctld.pid"
    stop_pid "$dir/munged.pid"
    exit 0
    ;;
start) ;;
*) usage ;;
esac

for exe in munged mungekey slurmctld slurmd sinfo; do
    command -v "$exe" >/dev/null 2>&1 || {
        echo "$0: $exe not found (Debian: apt-get install slurm-wlm munge)" >&2
        exit 1
    }
done
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
mkdir -p "$dir/state" "$dir/spool"
chmod 0700 "$dir"

# Ports: two free ones from the kernel's ephemeral range (bound and released by Python), so
# that a second cluster or a system slurmctld on 6817/6818 does not clash.
ports=$(/usr/bin/python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s:
    x.bind(("127.0.0.1", 0))
print(" ".join(str(x.getsockname()[1]) for x in s))
')
set -- $ports
ctl_port=$1
node_port=$2
node=$(hostname -s)

[ -f "$dir/munge.key" ] || mungekey --create --keyfile="$dir/munge.key" >/dev/null
chmod 0600 "$dir/munge.key"
# --force: munged refuses root and a key outside /etc/munge otherwise; the folder is 0700.
munged --force --socket="$dir/munge.socket" --key-file="$dir/munge.key" \
    --pid-file="$dir/munged.pid" --log-file="$dir/munged.log" --seed-file="$dir/munged.seed"

mem=$(awk '/^MemTotal:/ { print int($2 / 1024 / 2) }' /proc/meminfo)
cat >"$dir/slurm.conf" <<EOF
# A single-node cluster for cdpr's tests (tests/sweep/slurm_node.sh).
ClusterName=cdpr-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctl_port
SlurmdPort=$node_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
KillWait=30
MinJobAge=60
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$dir/slurm.conf"

slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF" -N "$node"

# Up when the node reports idle (at most 30 s: the daemons answer in about a second).
i=0
while [ $i -lt 300 ]; do
    state=$(sinfo -h -n "$node" -o %t 2>/dev/null || true)
    [ "$state" = idle ] && {
        echo "SLURM_CONF=$SLURM_CONF"
        exit 0
    }
    sleep 0.1
    i=$((i + 1))
done
echo "$0: the node did not come up (state '${state:-none}'); the logs:" >&2
for f in munged slurmctld slurmd; do
    echo "--- $dir/$f.log" >&2
    tail -n 20 "$dir/$f.log" >&2 2>/dev/null || true
done
exit 1
