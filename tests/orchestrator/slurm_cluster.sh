#!/usr/bin/env bash
# Starts (or stops) a real single-node Slurm cluster on this machine for the Slurm executor tests.
# usage: slurm_cluster.sh start|stop STATE_DIR
# Prints "skip: REASON" and exits 0 where Slurm cannot run (not root, packages missing), so the
# tests can skip with that reason.
set -uo pipefail
action=$1
state=$2
conf=$state/slurm.conf
stop() {
  for d in slurmd slurmctld; do
    [ -f "$state/$d.pid" ] && kill "$(cat "$state/$d.pid")" 2>/dev/null
  done
  for _ in $(seq 1 50); do
    pgrep -f "$conf" >/dev/null || break
    sleep 0.1
  done
  rm -f "$state"/*.pid
}
stop  # a cluster left over by an earlier run of this script
[ "$action" = stop ] && exit 0
rm -rf "$state" && mkdir -p "$state"
[ "$(id -u)" -eq 0 ] || { echo "skip: the Slurm tests start slurmctld/slurmd and need root"; exit 0; }
for tool in slurmctld slurmd munged sbatch squeue sacct scancel; do
  command -v "$tool" >/dev/null || [ -x "/usr/sbin/$tool" ] || { echo "skip: $tool is not installed (apt-get install slurm-wlm munge)"; exit 0; }
done
mkdir -p "$state/spool" "$state/ctld" /run/munge /var/log/munge /var/lib/munge /etc/munge
chown -R munge:munge /run/munge /var/log/munge /var/lib/munge /etc/munge 2>/dev/null
if [ ! -s /etc/munge/munge.key ]; then
  dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
  chown munge:munge /etc/munge/munge.key && chmod 400 /etc/munge/munge.key
fi
pgrep -x munged >/dev/null || su -s /bin/sh munge -c /usr/sbin/munged || /usr/sbin/munged --force
host=$(hostname -s)
cat > "$conf" <<CONF
ClusterName=podiumtest
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/spool
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
SlurmctldLogFile=$state/slurmctld.log
SlurmdLogFile=$state/slurmd.log
SlurmctldPort=6917
SlurmdPort=6918
ReturnToService=2
MinJobAge=600
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$state/jobcomp.txt
KillWait=2
InactiveLimit=0
MpiDefault=none
NodeName=$host CPUs=2 RealMemory=4000 State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=60 State=UP
CONF
export SLURM_CONF=$conf
/usr/sbin/slurmctld -f "$conf" || { echo "skip: slurmctld did not start: $(tail -3 "$state/slurmctld.log" 2>/dev/null)"; exit 0; }
/usr/sbin/slurmd -f "$conf" || { echo "skip: slurmd did not start: $(tail -3 "$state/slurmd.log" 2>/dev/null)"; exit 0; }
for _ in $(seq 1 60); do
  sinfo -h -o '%T' 2>/dev/null | grep -q -E '^(idle|mixed|allocated)' && { echo "ready: SLURM_CONF=$conf"; exit 0; }
  sleep 0.5
done
echo "skip: the Slurm node did not become idle: $(sinfo 2>&1 | tail -2)"
