#!/usr/bin/env bash
# local_slurm.sh start DIR | stop DIR
# A throw-away single-node Slurm cluster on this machine (Debian slurm-wlm + munge), everything
# under DIR: a munge key and daemon, slurmctld and slurmd with DIR/slurm.conf on free ports.
# After `start`, use the cluster with SLURM_CONF=DIR/slurm.conf (sbatch, squeue, sacct-less).
# `stop` ends the three daemons by their pid files. Exit 77 when Slurm or munge are missing.
set -euo pipefail
action="${1:?start|stop}"; dir="${2:?DIR}"
mkdir -p "$dir"; dir="$(cd "$dir" && pwd)"

stop_all() {
  for name in slurmd slurmctld munged; do
    if [[ -f "$dir/$name.pid" ]]; then
      pid="$(cat "$dir/$name.pid")"
      kill "$pid" 2>/dev/null || true
      for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
      kill -9 "$pid" 2>/dev/null || true
      rm -f "$dir/$name.pid"
    fi
  done
}

if [[ "$action" == stop ]]; then stop_all; exit 0; fi
[[ "$action" == start ]] || { echo "usage: local_slurm.sh start|stop DIR"; exit 2; }
for tool in munged mungekey slurmctld slurmd sbatch sinfo; do
  command -v "$tool" >/dev/null || [[ -x "/usr/sbin/$tool" ]] || { echo "skipped: $tool not installed (apt-get install slurm-wlm munge)"; exit 77; }
done
export PATH="$PATH:/usr/sbin"
user="$(id -un)"
host="$(hostname -s)"
cpus="$(nproc)"
free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

mkdir -p "$dir/munge" "$dir/state" "$dir/spool"
chmod 700 "$dir/munge"
mungekey --create --keyfile "$dir/munge/munge.key" --force
chmod 400 "$dir/munge/munge.key"
# --force: munged refuses to run as root or with a socket in a world-writable tree otherwise.
munged --force --key-file "$dir/munge/munge.key" --socket "$dir/munge/munge.socket" \
  --pid-file "$dir/munged.pid" --log-file "$dir/munged.log" --seed-file "$dir/munge/munge.seed"

cat >"$dir/slurm.conf" <<CONF
ClusterName=paregress
SlurmctldHost=$host(127.0.0.1)
SlurmUser=$user
SlurmdUser=$user
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
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
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
ReturnToService=2
MpiDefault=none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$dir/slurm.conf"
slurmctld -f "$SLURM_CONF" || { echo "slurmctld failed (log: $dir/slurmctld.log)"; stop_all; exit 1; }
slurmd -f "$SLURM_CONF" || { echo "slurmd failed (log: $dir/slurmd.log)"; stop_all; exit 1; }
for _ in $(seq 100); do
  if sinfo -h -o '%t' 2>/dev/null | grep -qE '^(idle|mix|alloc)'; then echo "slurm up: SLURM_CONF=$SLURM_CONF"; exit 0; fi
  sleep 0.2
done
echo "the node did not come up (logs: $dir/slurmctld.log, $dir/slurmd.log)"; sinfo || true
stop_all
exit 1
