#!/usr/bin/env bash
# A private one-node Slurm cluster for the tests (Debian's slurm-wlm and munge, as root).
#   one_node_cluster.sh start DIR   start munged, slurmctld and slurmd with everything under
#                                   DIR; prints "export SLURM_CONF=DIR/slurm.conf"
#   one_node_cluster.sh stop DIR    stop them again, by the pids they wrote under DIR
# Non-default ports (16817/16818), its own munge key and socket: the machine's
# /etc/munge/munge.key and any running cluster are left alone. Daemons are stopped by pid.
set -euo pipefail
cmd=${1:?start|stop}; dir=$(readlink -f "${2:?DIR}")

stop_pid() {  # pid file: SIGTERM, wait up to 10 s, then SIGKILL
  local f=$1
  [ -s "$f" ] || return 0
  local pid; pid=$(cat "$f")
  kill -TERM "$pid" 2>/dev/null || return 0
  for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || return 0; sleep 0.1; done
  kill -KILL "$pid" 2>/dev/null || true
}

if [ "$cmd" = stop ]; then
  # Jobs first (their steps are children of slurmd), then the daemons.
  if [ -f "$dir/slurm.conf" ]; then SLURM_CONF=$dir/slurm.conf scancel --user=root >/dev/null 2>&1 || true; fi
  stop_pid "$dir/run/slurmd.pid"
  stop_pid "$dir/run/slurmctld.pid"
  stop_pid "$dir/munge/munged.pid"
  exit 0
fi

[ "$cmd" = start ] || { echo "usage: $0 start|stop DIR" >&2; exit 2; }
for exe in munged mungekey slurmctld slurmd sbatch sinfo; do
  command -v "$exe" >/dev/null || [ -x "/usr/sbin/$exe" ] || { echo "$exe not found (apt-get install slurm-wlm munge)" >&2; exit 3; }
done
export PATH=$PATH:/usr/sbin
mkdir -p "$dir/munge" "$dir/state" "$dir/spool" "$dir/log" "$dir/run"
chmod 700 "$dir" "$dir/munge"
[ -f "$dir/munge/munge.key" ] || mungekey --create --keyfile="$dir/munge/munge.key" >/dev/null
chmod 600 "$dir/munge/munge.key"
munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
  --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/munged.seed"

host=$(hostname -s)
cat > "$dir/slurm.conf" <<CONF
ClusterName=mpmvstest
SlurmctldHost=$host
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
ReturnToService=2
MinJobAge=600
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
slurmctld -f "$dir/slurm.conf"
slurmd -f "$dir/slurm.conf"
export SLURM_CONF=$dir/slurm.conf
for _ in $(seq 60); do
  if [[ $(sinfo -h -o %t 2>/dev/null) == *idle* ]]; then echo "export SLURM_CONF=$dir/slurm.conf"; exit 0; fi
  sleep 0.5
done
echo "one_node_cluster.sh: the node did not become idle within 30 s; logs in $dir/log" >&2
sinfo >&2 || true
exit 4
