#!/usr/bin/env bash
# A one-node Slurm cluster on this machine (Debian 12's Slurm 22.05 and MUNGE), for trying and testing
# kessler-mpi and `kesslerd --mpi-launcher "srun ..."` without a cluster. Not for production: root runs
# every daemon, no cgroups, no accounting. Run as root.
#   deploy/slurm-single-node.sh         # install if needed, write /etc/slurm/slurm.conf, start the daemons
#   deploy/slurm-single-node.sh stop    # stop them
# With it up, `ctest -R kesslerd_srun_launcher` runs tests/mpi/daemon_mpi.sh with "srun -n 2 --mpi=pmix".
set -euo pipefail

stop_daemons() {
  local name
  for name in slurmd slurmctld munged; do
    pkill -x "$name" || true
    for _ in $(seq 1 100); do
      pgrep -x "$name" >/dev/null || break
      sleep 0.1
    done
  done
}

case "${1:-}" in
  "") ;;
  stop)
    stop_daemons
    exit 0
    ;;
  *)
    echo "slurm-single-node: unknown argument '$1' (none starts the cluster, 'stop' stops it)" >&2
    exit 2
    ;;
esac

if ! command -v slurmctld >/dev/null 2>&1 || ! command -v munged >/dev/null 2>&1; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm munge
fi

host=$(hostname -s)
cpus=$(nproc)
memory_mb=$(awk '/MemTotal/ { print int($2 / 1024 * 0.8) }' /proc/meminfo)
mkdir -p /etc/slurm /var/spool/slurmd /var/spool/slurmctld /run/munge
rm -f /var/spool/slurmctld/clustername
# Processes tracked through /proc and no task plugin: containers rarely delegate cgroups. pmix is the
# MPI wire-up that Debian's OpenMPI and Slurm share.
cat >/etc/slurm/slurm.conf <<EOF
ClusterName=kessler-single-node
SlurmctldHost=$host
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=pmix
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
SlurmUser=root
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmdSpoolDir=/var/spool/slurmd
StateSaveLocation=/var/spool/slurmctld
SlurmctldLogFile=/var/log/slurmctld.log
SlurmdLogFile=/var/log/slurmd.log
JobAcctGatherType=jobacct_gather/none
NodeName=$host CPUs=$cpus RealMemory=$memory_mb State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=YES
EOF

stop_daemons
chown munge:munge /run/munge
chown -R munge:munge /var/log/munge
runuser -u munge -- /usr/sbin/munged
/usr/sbin/slurmctld -c  # a fresh state: no jobs or cluster name kept from before
/usr/sbin/slurmd
for _ in $(seq 1 50); do
  if sinfo -h -o %t 2>/dev/null | grep -qE '^(idle|mix|alloc)'; then
    sinfo
    exit 0
  fi
  sleep 0.2
done
echo "slurm-single-node: the node did not come up; see /var/log/slurmctld.log and /var/log/slurmd.log" >&2
exit 1
