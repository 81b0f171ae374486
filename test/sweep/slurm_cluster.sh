#!/bin/bash
# A one-node SLURM cluster of its own, for tests and trials: slurm_cluster.sh start DIR | stop DIR.
# Its munged, slurmctld and slurmd use DIR only (config, state, sockets, logs, pid files) and ports of
# their own, so they leave any system SLURM alone. Clients need SLURM_CONF=DIR/slurm.conf. Runs as root.
# SLURM_SECOND_NODE="NS ADDR_HERE ADDR_THERE" makes it two nodes of one CPU each: this host (at ADDR_HERE)
# and a second slurmd, node <host>2, inside the network namespace NS (at ADDR_THERE; the caller makes NS
# and its veth pair). slurmctld is reached at ADDR_HERE from both.
set -eu
cmd=${1:?start or stop}; dir=$(realpath -m "${2:?folder}")
pids() { for f in "$dir"/slurmd*.pid "$dir"/slurmctld.pid "$dir"/munge/munged.pid; do [ -f "$f" ] && cat "$f"; done; true; }
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
  ctl=$host; nodes="NodeName=$host CPUs=$(nproc) State=UNKNOWN"; slurmd_pid=$dir/slurmd.pid; spool=$dir/spool
  if [ -n "${SLURM_SECOND_NODE:-}" ]; then
    read -r ns here there <<< "$SLURM_SECOND_NODE"
    ctl="$host($here)"; slurmd_pid=$dir/slurmd_%n.pid; spool=$dir/spool/%n
    nodes="NodeName=$host NodeAddr=$here CPUs=1 State=UNKNOWN
NodeName=${host}2 NodeAddr=$there CPUs=1 State=UNKNOWN"
    mkdir -p "$dir/spool/$host" "$dir/spool/${host}2"
  fi
  cat > "$dir"/slurm.conf <<CONF
ClusterName=swarmforage
SlurmctldHost=$ctl
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge-socket/munge.sock
StateSaveLocation=$dir/state
SlurmdSpoolDir=$spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$slurmd_pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd_%n.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
$nodes
PartitionName=main Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="$dir"/slurm.conf
  /usr/sbin/slurmctld -f "$SLURM_CONF"
  /usr/sbin/slurmd -f "$SLURM_CONF" -N "$host"
  # nsenter, not ip netns exec: that mounts a /sys of its own, without the cgroup file system slurmd needs.
  [ -z "${SLURM_SECOND_NODE:-}" ] || nsenter --net=/run/netns/"$ns" /usr/sbin/slurmd -f "$SLURM_CONF" -N "${host}2"
  want=$(grep -c '^NodeName=' "$SLURM_CONF")
  for _ in $(seq 1 120); do
    [ "$(sinfo -h -N -o %t 2>/dev/null | grep -cE '^idle')" = "$want" ] && {
      echo "slurm_cluster: $want nodes idle ($(sinfo -h -N -o '%N:%c' | tr '\n' ' ')CPUs), SLURM_CONF=$SLURM_CONF"; exit 0; }
    sleep 0.5
  done
  echo "slurm_cluster: the nodes did not come up; see $dir/slurmctld.log and $dir/slurmd_*.log" >&2; exit 1 ;;
stop)
  for p in $(pids); do kill "$p" 2>/dev/null || true; done
  for _ in $(seq 1 40); do alive=0; for p in $(pids); do kill -0 "$p" 2>/dev/null && alive=1; done
    [ $alive = 0 ] && exit 0; sleep 0.25; done
  for p in $(pids); do kill -9 "$p" 2>/dev/null || true; done ;;
*) echo "usage: slurm_cluster.sh start|stop DIR" >&2; exit 2 ;;
esac
