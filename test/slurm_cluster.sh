#!/bin/bash
# A one-node SLURM cluster of its own, for tests and trials: slurm_cluster.sh start DIR | stop DIR.
# Its munged, slurmctld and slurmd use DIR only (config, state, sockets, logs, pid files) and ports of
# their own, so they leave any system SLURM alone. Clients need SLURM_CONF=DIR/slurm.conf. Runs as root.
set -eu
cmd=${1:?start or stop}; dir=$(realpath -m "${2:?folder}")
pids() { for f in "$dir"/slurmd.pid "$dir"/slurmctld.pid "$dir"/munge/munged.pid; do [ -f "$f" ] && cat "$f"; done; true; }
case "$cmd" in
start)
  mkdir -p "$dir" && chmod 755 "$dir"  # munged (user munge) must reach its folders
  mkdir -p "$dir"/state "$dir"/spool "$dir"/munge "$dir"/munge-socket
  chown munge:munge "$dir"/munge "$dir"/munge-socket && chmod 700 "$dir"/munge && chmod 755 "$dir"/munge-socket
  [ -f "$dir"/munge/munge.key ] || { dd if=/dev/urandom bs=1 count=1024 of="$dir"/munge/munge.key 2>/dev/null;
    chown munge:munge "$dir"/munge/munge.key; chmod 400 "$dir"/munge/munge.key; }
  runuser -u munge -- /usr/sbin/munged --socket="$dir"/munge-socket/munge.sock --key-file="$dir"/munge/munge.key \
    --pid-file="$dir"/munge/munged.pid --log-file="$dir"/munge/munged.log --seed-file="$dir"/munge/munged.seed
  host=$(hostname -s); port=${SLURM_TEST_PORT:-16817}
  cat > "$dir"/slurm.conf <<CONF
ClusterName=swarmforage
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge-socket/munge.sock
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=main Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="$dir"/slurm.conf
  /usr/sbin/slurmctld -f "$SLURM_CONF"
  /usr/sbin/slurmd -f "$SLURM_CONF"
  for _ in $(seq 1 60); do
    sinfo -h -o %t 2>/dev/null | grep -qE '^idle' && { echo "slurm_cluster: $host idle ($(nproc) CPUs), SLURM_CONF=$SLURM_CONF"; exit 0; }
    sleep 0.5
  done
  echo "slurm_cluster: the node did not come up; see $dir/slurmctld.log and $dir/slurmd.log" >&2; exit 1 ;;
stop)
  for p in $(pids); do kill "$p" 2>/dev/null || true; done
  for _ in $(seq 1 40); do alive=0; for p in $(pids); do kill -0 "$p" 2>/dev/null && alive=1; done
    [ $alive = 0 ] && exit 0; sleep 0.25; done
  for p in $(pids); do kill -9 "$p" 2>/dev/null || true; done ;;
*) echo "usage: slurm_cluster.sh start|stop DIR" >&2; exit 2 ;;
esac
