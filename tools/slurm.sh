#!/usr/bin/env bash
# A single-node Slurm on this machine, for checking the cluster profile (profiles/slurm/):
#
#   bash tools/slurm.sh start    # install slurm-wlm + munge from apt if missing, start the daemons,
#                                # wait until `sinfo` shows the node idle (idempotent)
#   bash tools/slurm.sh status   # daemons, sinfo, squeue
#   bash tools/slurm.sh stop     # kill munged, slurmd, slurmctld by their pids
#
# Debian's packages (slurm-wlm 22.05 on Debian 12), as root; munged runs as user munge,
# slurmctld and slurmd as root (SlurmUser=root). No cgroups in a sandbox: proctrack/linuxproc
# and task/none. No accounting database (no slurmdbd): `sacct` does not work, so job status is
# read with `squeue`, and MinJobAge is long so that finished jobs stay visible to it.
# Everything lives in $SLURM_STATE (default /tmp/impactdamper-slurm): slurm.conf, logs,
# spool, pids. The clients find the configuration through SLURM_CONF=$SLURM_STATE/slurm.conf;
# when /etc/slurm/slurm.conf does not exist it is made a symlink to it (removed again by `stop`),
# so that plain `sinfo`/`squeue`/`sbatch` work too.
# Environment: SLURM_STATE, SLURM_START_TIMEOUT (s, default 60).
set -euo pipefail
# The daemons (slurmctld, slurmd, munged) and runuser live in /usr/sbin, which a Debian user's
# PATH (and PATH=/usr/bin:/bin) leaves out.
export PATH="$PATH:/usr/sbin:/sbin"

STATE="${SLURM_STATE:-/tmp/impactdamper-slurm}"
CONF="$STATE/slurm.conf"
TIMEOUT="${SLURM_START_TIMEOUT:-60}"
ETC_CONF=/etc/slurm/slurm.conf
MUNGE_RUN=/run/munge
MUNGE_PID="$MUNGE_RUN/munged.pid"
CTLD_PID="$STATE/slurmctld.pid"
SLURMD_PID="$STATE/slurmd.pid"
export SLURM_CONF="$CONF"

die() { echo "slurm.sh: $*" >&2; exit 1; }
alive() { [ -s "$1" ] && kill -0 "$(cat "$1")" 2>/dev/null; }  # alive PIDFILE

install_packages() {
  local missing=()
  command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v sinfo >/dev/null || missing+=(slurm-wlm)
  command -v munged >/dev/null || missing+=(munge)
  [ "${#missing[@]}" = 0 ] && return 0
  [ "$(id -u)" = 0 ] || die "need root to install ${missing[*]} (apt-get)"
  command -v apt-get >/dev/null || die "${missing[*]} missing and no apt-get here"
  echo "slurm.sh: installing ${missing[*]} from apt"
  local t0=$SECONDS log="$STATE/apt.log"
  mkdir -p "$STATE"
  # Lock timeouts: another apt run (tools/setup.sh) may hold the lock for a while.
  apt-get -o DPkg::Lock::Timeout=300 update -qq >"$log" 2>&1 \
    || { tail -n 20 "$log" >&2; die "apt-get update failed (log $log)"; }
  # policy-rc.d/systemd may refuse to start the services at install time: we start them ourselves.
  DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=300 install -y -qq --no-install-recommends \
    "${missing[@]}" >>"$log" 2>&1 || { tail -n 20 "$log" >&2; die "apt-get install ${missing[*]} failed (log $log)"; }
  echo "slurm.sh: installed ${missing[*]} in $((SECONDS - t0)) s"
}

write_conf() {
  local host cpus mem_total mem
  host=$(hostname -s)
  cpus=$(nproc)
  mem_total=$(free -m | awk '/^Mem:/ {print $2}')
  mem=$(( mem_total * 9 / 10 ))  # slurmd drains a node whose RealMemory exceeds what it finds
  mkdir -p "$STATE/spool/ctld" "$STATE/spool/d" "$STATE/log"
  cat >"$CONF.new" <<EOF
# Written by tools/slurm.sh: a single-node Slurm on $host ($cpus CPUs, $mem_total MB).
ClusterName=impactdamper
SlurmctldHost=$host(127.0.0.1)
AuthType=auth/munge
CryptoType=crypto/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$STATE/spool/ctld
SlurmdSpoolDir=$STATE/spool/d
SlurmctldPidFile=$CTLD_PID
SlurmdPidFile=$SLURMD_PID
SlurmctldLogFile=$STATE/log/slurmctld.log
SlurmdLogFile=$STATE/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# No cgroups here.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
DefMemPerCPU=1000
ReturnToService=2
# Finished jobs stay known to slurmctld (and so to squeue) for a day: the Snakemake executor
# reads job states with squeue (no accounting database for sacct).
MinJobAge=86400
InactiveLimit=0
KillWait=30
Waittime=0
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  mv "$CONF.new" "$CONF"
  if [ ! -e "$ETC_CONF" ] && [ ! -L "$ETC_CONF" ]; then
    mkdir -p "$(dirname "$ETC_CONF")"
    ln -s "$CONF" "$ETC_CONF"
  fi
}

start_munge() {
  alive "$MUNGE_PID" && return 0
  [ -s /etc/munge/munge.key ] || {
    mungekey -c -k /etc/munge/munge.key
    chown munge:munge /etc/munge/munge.key
    chmod 400 /etc/munge/munge.key
  }
  mkdir -p "$MUNGE_RUN" /var/log/munge /var/lib/munge
  chown munge:munge "$MUNGE_RUN" /var/log/munge /var/lib/munge
  chmod 755 "$MUNGE_RUN"
  rm -f "$MUNGE_RUN/munge.socket.2" "$MUNGE_RUN/munge.socket.2.lock"
  runuser -u munge -- munged --pid-file="$MUNGE_PID" --force
  munge -n | unmunge >/dev/null || die "munge does not work (see /var/log/munge/munged.log)"
}

node_state() { sinfo -h -N -o '%t' 2>/dev/null | head -n1; }

start() {
  install_packages
  if alive "$CTLD_PID" && alive "$SLURMD_PID" && [ "$(node_state)" = idle ]; then
    echo "slurm.sh: already running ($(hostname -s) idle; SLURM_CONF=$CONF)"
    return 0
  fi
  write_conf
  start_munge
  # -c: a fresh controller state (no jobs left over from an earlier run of this script)
  alive "$CTLD_PID" || slurmctld -c -f "$CONF"
  alive "$SLURMD_PID" || slurmd -f "$CONF"
  local t0=$SECONDS state=""
  while [ $((SECONDS - t0)) -lt "$TIMEOUT" ]; do
    state=$(node_state)
    case "$state" in
      idle|mix|alloc) echo "slurm.sh: $(hostname -s) $state after $((SECONDS - t0)) s (SLURM_CONF=$CONF)"; return 0 ;;
      down*|drain*|drng*|inval*) scontrol update nodename="$(hostname -s)" state=resume >/dev/null 2>&1 || true ;;
    esac
    sleep 1
  done
  die "node $(hostname -s) not idle after ${TIMEOUT} s (state '${state:-none}'); see $STATE/log/slurmctld.log and slurmd.log"
}

stop() {
  local f
  for f in "$SLURMD_PID" "$CTLD_PID" "$MUNGE_PID"; do
    if alive "$f"; then
      local pid; pid=$(cat "$f")
      kill "$pid"
      for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
      kill -0 "$pid" 2>/dev/null && kill -9 "$pid"
      echo "slurm.sh: stopped $(basename "$f" .pid) (pid $pid)"
    fi
    rm -f "$f"
  done
  if [ -L "$ETC_CONF" ] && [ "$(readlink "$ETC_CONF")" = "$CONF" ]; then rm -f "$ETC_CONF"; fi
}

status() {
  local f rc=0
  for f in "$MUNGE_PID" "$CTLD_PID" "$SLURMD_PID"; do
    if alive "$f"; then echo "$(basename "$f" .pid): running (pid $(cat "$f"))"
    else echo "$(basename "$f" .pid): not running"; rc=1; fi
  done
  if [ "$rc" = 0 ]; then
    echo "SLURM_CONF=$CONF"
    sinfo
    squeue --states=all -o '%.8i %.10P %.40j %.10T %.10M %R'
  fi
  return "$rc"
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  status) status ;;
  *) echo "usage: $0 start|stop|status" >&2; exit 2 ;;
esac
