#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, for tests and CI:
#   tools/slurm-local.sh start | stop | status | env
# `start` installs Debian's slurm-wlm and munge if they are missing, writes a slurm.conf into the
# state folder ${MAPM_SLURM_DIR:-/tmp/mapm-slurm} (this host as controller and only node, all its
# CPUs, partition `debug`), starts munged, slurmctld and slurmd, and waits for the node to be idle.
# Clients need SLURM_CONF: eval "$(tools/slurm-local.sh env)". No systemd and no cgroups needed.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
dir="${MAPM_SLURM_DIR:-/tmp/mapm-slurm}"
export SLURM_CONF="$dir/slurm.conf"
host="$(hostname -s)"

die() { echo "mapm slurm: $*" >&2; exit 1; }

# True when the pid file $1 names a live process called $2 (a stale pid file is not enough).
alive() {
  local pid
  pid="$(cat "$1" 2>/dev/null)" && [ -n "$pid" ] && [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = "$2" ]
}

# The node's state as sinfo prints it (idle, mix, down*, drain, ...), empty when slurmctld does not answer.
node_state() { timeout 10 sinfo -h -n "$host" -o %t 2>/dev/null | head -n1 || true; }

# True when slurmd has registered with slurmctld since the epoch second $1.
registered() {
  local t
  t="$(timeout 10 scontrol -o show node "$host" 2>/dev/null | grep -o 'SlurmdStartTime=[0-9T:-]*' | cut -d= -f2)" || true
  [ -n "$t" ] && [ "$(date -d "$t" +%s)" -ge "$1" ]
}

show_logs() {
  local f
  for f in "$dir"/munge/munged.log "$dir"/slurmctld.log "$dir"/slurmd.log; do
    [ -s "$f" ] && { echo "--- last lines of $f" >&2; tail -n 15 "$f" >&2; }
  done
  return 0
}

write_conf() {
  local cpus mem
  cpus="$(nproc)"
  # Leave 512 MiB (or a quarter, on a small machine) to the system; slurmd drains a node that
  # reports less memory than RealMemory.
  mem="$(free -m | awk '/^Mem:/ { m = $2 - 512; if (m < $2 * 3 / 4) m = int($2 * 3 / 4); print m }')"
  mkdir -p "$dir/state" "$dir/spool"
  cat >"$SLURM_CONF.tmp" <<EOF
# Written by tools/slurm-local.sh: a one-node test cluster; rewritten on each start.
ClusterName=mapm
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
# linuxproc tracks a job's processes through their parent pids, so neither cgroups nor systemd
# (both absent from containers and CI runners) are needed; task/none binds no CPUs for the same reason.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
SchedulerType=sched/backfill
# Schedule at once on submit and on each job's end (the defaults wait up to 3 s, which is most of
# a short test's time); a one-node cluster has no load to spare the scheduler.
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
# Hand out single cores, so that array tasks of 1 CPU each share the node instead of queueing.
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobCompType=jobcomp/none
MailProg=/bin/true
AccountingStorageType=accounting_storage/none
# A node that was down (e.g. after a stop) comes back by itself once its slurmd registers.
ReturnToService=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  mv "$SLURM_CONF.tmp" "$SLURM_CONF"
}

start_munge() {
  # A munged that already answers (ours, or one the package's init script started) will do.
  if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then return 0; fi
  mkdir -p /etc/munge /run/munge /var/lib/munge /var/log/munge
  if [ ! -s /etc/munge/munge.key ]; then
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 status=none
  fi
  chown munge:munge /etc/munge/munge.key /run/munge /var/lib/munge /var/log/munge
  chmod 0400 /etc/munge/munge.key
  # As the munge user, which owns the key; munged would refuse a key owned by someone else.
  runuser -u munge -- munged --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" \
    || { show_logs; die "munged did not start"; }
  local i
  for i in $(seq 50); do
    munge -n 2>/dev/null | unmunge >/dev/null 2>&1 && return 0
    sleep 0.2
  done
  show_logs; die "munged started but does not answer"
}

start() {
  if ! command -v sbatch >/dev/null || ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null \
     || ! command -v munged >/dev/null; then
    source "$here/setup.sh"
    mapm_apt_install slurm-wlm munge
  fi
  mkdir -p "$dir/munge"
  chown munge:munge "$dir/munge"  # munged, as the munge user, writes its pid and log files here
  start_munge
  # Rewrite the config only while no daemon reads it.
  alive "$dir/slurmctld.pid" slurmctld || alive "$dir/slurmd.pid" slurmd || write_conf
  alive "$dir/slurmctld.pid" slurmctld || slurmctld -f "$SLURM_CONF" || { show_logs; die "slurmctld did not start"; }
  local since=0 i state=""
  if ! alive "$dir/slurmd.pid" slurmd; then
    since="$(date +%s)"
    slurmd -f "$SLURM_CONF" || { show_logs; die "slurmd did not start"; }
  fi
  # slurmctld shows the node state it saved at its last stop until slurmd registers, so wait for both;
  # give up at once when a daemon has died (after 2 s, once both have surely written their pid files).
  for i in $(seq 150); do
    [ "$i" -le 10 ] || { alive "$dir/slurmctld.pid" slurmctld && alive "$dir/slurmd.pid" slurmd; } || break
    state="$(node_state)"
    case "$state" in
      idle|mix|alloc) registered "$since" && alive "$dir/slurmd.pid" slurmd && return 0 ;;
      down*|drain*|drng*) scontrol update nodename="$host" state=resume >/dev/null 2>&1 || true ;;
    esac
    sleep 0.2
  done
  show_logs
  die "no idle node $host with a live, registered slurmd (node state: ${state:-no answer from slurmctld})"
}

# Sends TERM to the daemon in pid file $1 (named $2), waits up to 10 s, then KILL.
stop_daemon() {
  alive "$1" "$2" || { rm -f "$1"; return 0; }
  local pid i
  pid="$(cat "$1")"
  kill "$pid" 2>/dev/null || true
  for i in $(seq 50); do
    alive "$1" "$2" || { rm -f "$1"; return 0; }
    sleep 0.2
  done
  kill -9 "$pid" 2>/dev/null || true
  rm -f "$1"
}

case "${1:-}" in
  start) start; echo "mapm slurm: running ($SLURM_CONF)" >&2 ;;
  stop)
    stop_daemon "$dir/slurmd.pid" slurmd
    stop_daemon "$dir/slurmctld.pid" slurmctld
    stop_daemon "$dir/munge/munged.pid" munged ;;
  status)
    alive "$dir/slurmctld.pid" slurmctld || die "not running (no slurmctld for $SLURM_CONF)"
    sinfo || die "slurmctld does not answer" ;;
  env) echo "export SLURM_CONF=$SLURM_CONF" ;;
  *) die "usage: tools/slurm-local.sh start|stop|status|env" ;;
esac
