#!/usr/bin/env bash
# A throw-away single-node SLURM cluster on this Debian machine (controller + compute node), for
# `make test-slurm`. Every daemon listens on 127.0.0.1 only; nothing is left running after `stop`.
#
#   tests/slurm/local_slurm.sh start    # install the Debian packages if missing, configure, start, smoke test
#   tests/slurm/local_slurm.sh status   # which of this script's daemons run; sinfo
#   tests/slurm/local_slurm.sh stop     # cancel the cluster's jobs, stop exactly the daemons `start` started
#
# `start` and `stop` are idempotent (a second `start` keeps the running daemons; `stop` of a stopped
# cluster does nothing). Runs as root (apt, daemons).
#
# The cluster has no job accounting (no slurmdbd): `sacct` fails, as on a site without accounting,
# so a run through it also checks that the profile's job status queries do not depend on sacct.
# (slurmdbd 22.05 cannot be bound to one address; it would listen on every interface.)
#
# Environment: LOCAL_SLURM_STATE  PID files, spool, state and logs (default /var/lib/cdpr-local-slurm)
#
# Packages (Debian 12): munge slurmctld slurmd slurm-client, installed with --no-install-recommends
# while a policy-rc.d forbids their init scripts to start anything: this script starts and stops
# the daemons itself and records their PIDs under $LOCAL_SLURM_STATE/pids. Writes
# /etc/slurm/slurm.conf, and refuses to overwrite one it did not write.
set -euo pipefail

STATE=${LOCAL_SLURM_STATE:-/var/lib/cdpr-local-slurm}
PIDS=$STATE/pids
LOGS=$STATE/log
CLUSTER=cdprtest
PARTITION=debug
MARK="# written by cdpr tests/slurm/local_slurm.sh"
DAEMONS="slurmd slurmctld munged"   # stop order
PACKAGES="munge slurmctld slurmd slurm-client"

say() { echo "local_slurm: $*"; }
die() { echo "local_slurm: error: $*" >&2; exit 1; }

# PID recorded for daemon $1 if that process still runs and is that daemon, else nothing.
our_pid() {
  local f=$PIDS/$1.pid pid
  [ -s "$f" ] || return 1
  pid=$(cat "$f")
  [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = "$1" ] || return 1
  echo "$pid"
}

POLICY=/usr/sbin/policy-rc.d
POLICY_BACKUP=
restore_policy() {
  if [ -n "$POLICY_BACKUP" ]; then mv -f "$POLICY_BACKUP" "$POLICY"; else rm -f "$POLICY"; fi
}

install_packages() {
  local missing="" p
  for p in $PACKAGES; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
  done
  [ -z "$missing" ] && return 0
  command -v apt-get >/dev/null || die "missing packages:$missing, and no apt-get (this script needs Debian or Ubuntu)"
  say "installing$missing"
  # No init script may start a daemon while apt runs (policy-rc.d exit 101 = action forbidden);
  # an existing policy-rc.d is put back afterwards.
  if [ -e "$POLICY" ]; then POLICY_BACKUP=$(mktemp); cp -p "$POLICY" "$POLICY_BACKUP"; fi
  trap restore_policy EXIT
  printf '#!/bin/sh\n# local_slurm.sh: no daemon starts during apt\nexit 101\n' > "$POLICY"
  chmod 755 "$POLICY"
  apt-get update -q
  # shellcheck disable=SC2086
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $missing
  restore_policy
  trap - EXIT
}

check_host() {
  HOST=$(hostname -s)
  local addr
  addr=$(getent ahostsv4 "$HOST" | awk 'NR==1 {print $1}')
  case "$addr" in
    127.*) ;;
    *) die "host name '$HOST' resolves to '${addr:-nothing}', not to a loopback address; the daemons would not stay on 127.0.0.1. Add '127.0.0.1 $HOST' to /etc/hosts." ;;
  esac
  if [ -e /etc/slurm/slurm.conf ] && ! grep -qF "$MARK" /etc/slurm/slurm.conf; then
    die "/etc/slurm/slurm.conf exists and was not written by this script (a real cluster?); not touching it"
  fi
}

port_free() {  # $1 = TCP port; true if nobody listens on it (or if `ss` is missing)
  command -v ss >/dev/null || return 0
  ! ss -Hltn "sport = :$1" | grep -q .
}

write_config() {
  mkdir -p /etc/slurm "$PIDS" "$LOGS" "$STATE/slurmctld" "$STATE/slurmd"
  chown slurm:slurm "$STATE/slurmctld" "$LOGS"
  # CPUs and memory as slurmd detects them (a configured RealMemory above that drains the node)
  local cpus mem
  cpus=$(nproc)
  mem=$(slurmd -C | sed -n 's/.*RealMemory=\([0-9]*\).*/\1/p')
  cat > /etc/slurm/slurm.conf <<EOF
$MARK
ClusterName=$CLUSTER
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=6817
SlurmdPort=6818
# bind to the address the host name resolves to (checked: loopback), not to every interface
CommunicationParameters=NoCtldInAddrAny,NoInAddrAny
SlurmUser=slurm
AuthType=auth/munge
CredType=cred/munge
MpiDefault=none
# no cgroup plugins: works without systemd; memory is scheduled, not enforced
ProctrackType=proctrack/linuxproc
TaskPlugin=task/affinity
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
# jobs that ask for no memory get 1 GB per CPU, not the whole node
DefMemPerCPU=1000
ReturnToService=2
# finished jobs stay visible to squeue for 5 min (the SLURM default; squeue-based status needs >= 120 s)
MinJobAge=300
JobAcctGatherType=jobacct_gather/linux
# no slurmdbd: sacct reports "accounting storage is disabled"
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MailProg=/bin/true
SlurmctldPidFile=$PIDS/slurmctld.pid
SlurmdPidFile=$PIDS/slurmd.pid
StateSaveLocation=$STATE/slurmctld
SlurmdSpoolDir=$STATE/slurmd
SlurmctldLogFile=$LOGS/slurmctld.log
SlurmdLogFile=$LOGS/slurmd.log
NodeName=$HOST NodeAddr=127.0.0.1 NodeHostname=$HOST CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=$PARTITION Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
  chmod 644 /etc/slurm/slurm.conf
}

start_munge() {
  if [ ! -s /etc/munge/munge.key ]; then
    mungekey --create --force
  fi
  chown munge:munge /etc/munge/munge.key
  chmod 400 /etc/munge/munge.key
  mkdir -p /run/munge
  chown munge:munge /run/munge
  if ! our_pid munged >/dev/null; then
    if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
      say "a munged not started by this script is running; using it (it will not be stopped)"
    else
      runuser -u munge -- /usr/sbin/munged
      sleep 1
      cp /run/munge/munged.pid "$PIDS/munged.pid"
    fi
  fi
  munge -n | unmunge >/dev/null || die "munge does not work"
}

start_slurm() {
  if ! our_pid slurmctld >/dev/null; then
    port_free 6817 || die "TCP port 6817 (slurmctld) is in use by another process"
    /usr/sbin/slurmctld
  fi
  if ! our_pid slurmd >/dev/null; then
    port_free 6818 || die "TCP port 6818 (slurmd) is in use by another process"
    /usr/sbin/slurmd
  fi
  local _
  for _ in $(seq 30); do
    sinfo -h -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)' && break
    sleep 1
  done
  scontrol update nodename="$HOST" state=resume >/dev/null 2>&1 || true
  sinfo -h -o '%T' | grep -qE '^(idle|mixed|allocated)' || { sinfo; die "the node did not come up; see $LOGS"; }
}

check_loopback_only() {
  # every TCP socket our daemons listen on must be bound to a 127.x address
  command -v ss >/dev/null || { say "ss not found; listening addresses not checked"; return 0; }
  local n pid bad=""
  for n in $DAEMONS; do
    pid=$(our_pid "$n") || continue
    bad="$bad$(ss -Hltnp | grep "pid=$pid," | awk '{print $4}' | grep -v '^127\.' || true)"
  done
  [ -z "$bad" ] || die "daemons listen on non-loopback addresses: $bad"
}

# What the cluster says about itself when a trivial job does not run: node state and reason, the
# job, the daemons' last log lines.
diagnose() {
  echo "local_slurm: --- diagnostics ---" >&2
  sinfo -N -l >&2 2>&1 || true
  sinfo -R >&2 2>&1 || true
  [ -z "${1:-}" ] || scontrol show job "$1" >&2 2>&1 || true
  local f
  for f in "$LOGS/slurmctld.log" "$LOGS/slurmd.log"; do
    [ -s "$f" ] && { echo "local_slurm: last lines of $f" >&2; tail -n 25 "$f" >&2; }
  done
  echo "local_slurm: --- end of diagnostics ---" >&2
}

# A trivial batch job must run. A node that has just registered can refuse its first job (seen
# once on a fresh CI machine): up to three tries, the node resumed between them. A cluster that
# cannot run a trivial job is this machine's problem, not the profile's: exit status 3 says so
# (test_slurm.sh passes it on), after the diagnostics.
smoke_test() {
  local out="" try
  for try in 1 2 3; do
    if out=$(timeout 120 sbatch --parsable --wait -o /dev/null --wrap 'test -n "$SLURM_JOB_ID"'); then
      say "test batch job $out completed"
      return 0
    fi
    say "test batch job ${out:-(not submitted)} did not complete (try $try of 3)"
    diagnose "$out"
    squeue -h -o %A 2>/dev/null | xargs -r scancel >/dev/null 2>&1 || true
    scontrol update nodename="$HOST" state=resume >/dev/null 2>&1 || true
    sleep 5
  done
  echo "local_slurm: error: a test batch job did not complete in three tries: the throw-away cluster does not work on this machine" >&2
  exit 3
}

start() {
  [ "$(id -u)" = 0 ] || die "run as root"
  install_packages
  check_host
  write_config
  start_munge
  start_slurm
  check_loopback_only
  smoke_test
  status
}

stop() {
  [ "$(id -u)" = 0 ] || die "run as root"
  local n pid _
  if our_pid slurmctld >/dev/null; then
    # cancel what is left of this cluster's jobs, so that no job step outlives slurmd
    squeue -h -o %A 2>/dev/null | xargs -r scancel >/dev/null 2>&1 || true
    for _ in $(seq 30); do
      [ -z "$(squeue -h -t PD,R,CG,S -o %A 2>/dev/null)" ] && break
      sleep 1
    done
  fi
  for n in $DAEMONS; do
    if pid=$(our_pid "$n"); then
      kill "$pid"
      for _ in $(seq 30); do
        kill -0 "$pid" 2>/dev/null || break
        sleep 1
      done
      if kill -0 "$pid" 2>/dev/null; then
        kill -KILL "$pid"
        say "killed $n ($pid) after 30 s"
      else
        say "stopped $n ($pid)"
      fi
    fi
    rm -f "$PIDS/$n.pid"
  done
}

status() {
  local n pid running=0
  for n in $DAEMONS; do
    if pid=$(our_pid "$n"); then
      say "$n running (pid $pid)"
      running=1
    fi
  done
  [ "$running" = 1 ] || say "no daemon of this script is running"
  if our_pid slurmctld >/dev/null; then sinfo; fi
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  status) status ;;
  *) die "usage: $0 start|stop|status" ;;
esac
