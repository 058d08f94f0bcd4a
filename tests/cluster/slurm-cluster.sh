#!/usr/bin/env bash
# slurm-cluster.sh - throw-away single-node SLURM cluster (munge auth, no
# accounting, no cgroups, no systemd) for CI.
#
#   slurm-cluster.sh start <dir>   install (if root and missing), configure, start, wait idle
#   slurm-cluster.sh stop  <dir>   cancel jobs, stop daemons by PID file, wait for exit
#   slurm-cluster.sh status <dir>  exit 0 if all three daemons of <dir> are alive
#   slurm-cluster.sh env <dir>     print "export SLURM_CONF=..." (eval it)
#
# Everything (config, munge key+socket, state, spool, logs, PID files) lives
# under <dir>, except the symlink /etc/slurm/slurm.conf -> <dir>/etc/slurm.conf
# (removed again by stop). Clients (sbatch, squeue, sinfo, snakemake) find the
# cluster through that link or through
#   export SLURM_CONF=<dir>/etc/slurm.conf
# Exit codes: 0 ok, 1 error, 2 usage, 77 cannot run here (not root / install failed).
#
# Environment knobs:
#   SLURM_CLUSTER_TIMEOUT   seconds to wait for daemons / idle node (default 60)
#   SLURM_CLUSTER_CTLD_PORT SlurmctldPort (default: 6817, or next free port)
#   SLURM_CLUSTER_SLURMD_PORT SlurmdPort (default: 6818, or next free port)
#   SLURM_CLUSTER_SMOKE=0   skip the 'sbatch --wrap hostname' check at the end of start (~3 s)
#   SLURM_CLUSTER_NO_ETC_LINK=1  do not symlink /etc/slurm/slurm.conf -> <dir>/etc/slurm.conf
#                           (needed for srun inside snakemake jobs; one cluster at a time)
set -euo pipefail

PROG=${0##*/}
TIMEOUT=${SLURM_CLUSTER_TIMEOUT:-60}

die()  { echo "$PROG: error: $*" >&2; exit 1; }
skip() { echo "$PROG: skip: $*" >&2; exit 77; }
log()  { echo "$PROG: $*" >&2; }
usage() { echo "usage: $PROG start|stop|status|env <dir>" >&2; exit 2; }

[ $# -eq 2 ] || usage
CMD=$1
DIR=$(realpath -m -- "$2")

ETC=$DIR/etc; STATE=$DIR/state; SPOOL=$DIR/spool; LOGD=$DIR/log; RUN=$DIR/run
MUNGE=$DIR/munge
CONF=$ETC/slurm.conf
MUNGE_SOCK=$MUNGE/munge.socket.2
PID_MUNGE=$MUNGE/munged.pid
PID_CTLD=$RUN/slurmctld.pid
PID_SLURMD=$RUN/slurmd.pid

# ---------------------------------------------------------------- helpers
# pid from file, only if that process is alive and its command matches $2
live_pid() {
  local f=$1 name=$2 pid
  [ -s "$f" ] || return 1
  pid=$(tr -dc '0-9' <"$f")
  [ -n "$pid" ] && [ -d "/proc/$pid" ] || return 1
  is_zombie "$pid" && return 1
  tr '\0' ' ' <"/proc/$pid/cmdline" 2>/dev/null | grep -q -- "$name" || return 1
  echo "$pid"
}

is_zombie() { grep -q '^State:[[:space:]]*Z' "/proc/$1/status" 2>/dev/null; }
running_pids() {  # non-zombie pids with exact command name $1
  local p out=""
  for p in $(pgrep -x "$1" 2>/dev/null || true); do is_zombie "$p" || out="$out$p "; done
  echo "${out% }"
}

port_in_use() { (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
free_port() {  # first port >= $1 nobody listens on, skipping $2
  local p=$1
  while port_in_use "$p" || [ "$p" = "${2:-}" ]; do p=$((p + 1)); done
  echo "$p"
}

wait_until() {  # wait_until <seconds> <description> <command...>
  local t=$1 what=$2; shift 2
  local end=$((SECONDS + t))
  until "$@"; do
    [ $SECONDS -lt $end ] || { log "timeout after ${t}s waiting for $what"; return 1; }
    sleep 0.2
  done
}

show_logs() {
  local f
  for f in "$MUNGE/munged.log" "$LOGD/slurmctld.log" "$LOGD/slurmd.log"; do
    [ -f "$f" ] && { echo "---- tail $f" >&2; tail -n 15 "$f" >&2; }
  done
  return 0
}

ensure_installed() {
  local need=0 c
  for c in munged munge slurmctld slurmd sbatch squeue sinfo scontrol srun; do
    command -v "$c" >/dev/null 2>&1 || need=1
  done
  [ $need -eq 0 ] && return 0
  [ "$(id -u)" -eq 0 ] || skip "slurm/munge not installed and not root (cannot apt-get install)"
  command -v apt-get >/dev/null 2>&1 || skip "slurm/munge not installed and no apt-get"
  log "installing slurmctld slurmd slurm-client munge with apt-get ..."
  export DEBIAN_FRONTEND=noninteractive
  if ! { apt-get update -qq >"$DIR/apt.log" 2>&1 &&
         apt-get install -y -qq --no-install-recommends \
           slurmctld slurmd slurm-client munge >>"$DIR/apt.log" 2>&1; }; then
    skip "apt-get install of slurm/munge failed (see $DIR/apt.log)"
  fi
  for c in munged munge slurmctld slurmd sbatch squeue sinfo scontrol srun; do
    command -v "$c" >/dev/null 2>&1 || skip "$c still missing after apt-get install"
  done
}

# ---------------------------------------------------------------- stop
stop_pid() {  # stop_pid <pidfile> <name>
  local pid i
  pid=$(live_pid "$1" "$2") || { rm -f "$1"; return 0; }
  kill -TERM "$pid" 2>/dev/null || true
  for i in $(seq 1 100); do           # up to 20 s
    [ -d "/proc/$pid" ] || break
    is_zombie "$pid" && break    # exited, just not reaped yet
    sleep 0.2
  done
  if [ -d "/proc/$pid" ] && ! is_zombie "$pid"; then
    log "$2 (pid $pid) did not exit on SIGTERM, sending SIGKILL"
    kill -KILL "$pid" 2>/dev/null || true
    sleep 0.5
  fi
  rm -f "$1"
}

kill_our_stepds() {
  # slurmstepd daemons of this cluster keep our slurmd log open: find them by that
  local p
  for p in $(running_pids slurmstepd); do
    if ls -l "/proc/$p/fd" 2>/dev/null | grep -q -- "$DIR/"; then
      kill -KILL "$p" 2>/dev/null || true
    fi
  done
}

do_stop() {
  [ -d "$DIR" ] || { log "nothing to stop in $DIR"; return 0; }
  if live_pid "$PID_CTLD" slurmctld >/dev/null && [ -f "$CONF" ]; then
    # cancel whatever is still queued/running so no job processes are left
    local jobs
    jobs=$(SLURM_CONF=$CONF timeout 10 squeue -h -o %i 2>/dev/null || true)
    if [ -n "$jobs" ]; then
      SLURM_CONF=$CONF timeout 10 scancel $jobs 2>/dev/null || true
      local end=$((SECONDS + 10))
      while [ $SECONDS -lt $end ] &&
            [ -n "$(SLURM_CONF=$CONF timeout 5 squeue -h -t R,CG,PD -o %i 2>/dev/null)" ]; do
        sleep 0.5
      done
    fi
  fi
  stop_pid "$PID_SLURMD" slurmd
  kill_our_stepds
  stop_pid "$PID_CTLD" slurmctld
  stop_pid "$PID_MUNGE" munged
  unlink_etc_conf
  log "stopped cluster in $DIR"
}

# ---------------------------------------------------------------- start
write_config() {
  local host cluster ctld_port slurmd_port node cpus mem defmem
  host=$(hostname -s)
  # unique per start; the state dir is wiped on every start, so no clash
  cluster="c$(printf '%s' "$DIR" | md5sum | cut -c1-6)$(date +%s | tail -c 6)"
  ctld_port=${SLURM_CLUSTER_CTLD_PORT:-$(free_port 6817)}
  slurmd_port=${SLURM_CLUSTER_SLURMD_PORT:-$(free_port 6818 "$ctld_port")}
  # e.g. "NodeName=vm CPUs=2 Boards=1 SocketsPerBoard=1 CoresPerSocket=2 ThreadsPerCore=1 RealMemory=24105"
  node=$(slurmd -C | head -n1)
  case $node in NodeName=*) ;; *) die "unexpected 'slurmd -C' output: $node" ;; esac
  node=$(printf '%s\n' "$node" | sed -e "s/^NodeName=[^ ]*/NodeName=$host/")
  cpus=$(printf '%s\n' "$node" | sed -n 's/.* CPUs=\([0-9]*\).*/\1/p')
  mem=$(printf '%s\n' "$node" | sed -n 's/.*RealMemory=\([0-9]*\).*/\1/p')
  [ -n "$cpus" ] && [ -n "$mem" ] || die "cannot parse CPUs/RealMemory from: $node"
  # jobs without --mem get this per CPU instead of the whole node
  defmem=$((mem / cpus))

  cat >"$CONF" <<EOF
# generated by $PROG for $DIR
ClusterName=$cluster
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$MUNGE_SOCK
StateSaveLocation=$STATE
SlurmdSpoolDir=$SPOOL/slurmd-%n
SlurmctldPidFile=$PID_CTLD
SlurmdPidFile=$PID_SLURMD
SlurmctldLogFile=$LOGD/slurmctld.log
SlurmdLogFile=$LOGD/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
# default batch_sched_delay=3 makes every job wait ~3 s for the periodic scheduler
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
DefMemPerCPU=$defmem
ReturnToService=2
# keep finished jobs visible to squeue (snakemake --slurm-status-command squeue)
MinJobAge=600
SlurmctldTimeout=30
SlurmdTimeout=60
InactiveLimit=0
KillWait=5
Waittime=0
$node NodeAddr=127.0.0.1 NodeHostname=$host State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  printf 'export SLURM_CONF=%s\n' "$CONF" >"$DIR/env.sh"
}

# snakemake-executor-plugin-slurm-jobstep strips every SLURM_* variable (so
# SLURM_CONF too) before its nested 'srun' inside the job; that srun then only
# finds the config at the compiled-in default path. So point that path at ours.
ETC_LINK=/etc/slurm/slurm.conf
check_etc_link() {
  [ "${SLURM_CLUSTER_NO_ETC_LINK:-0}" = 1 ] && return 0
  if [ -e "$ETC_LINK" ] && [ ! -L "$ETC_LINK" ]; then
    die "$ETC_LINK is a real file (another SLURM setup?); refusing to replace it. Set SLURM_CLUSTER_NO_ETC_LINK=1 to skip (srun inside snakemake jobs will then fail)"
  fi
  if [ -L "$ETC_LINK" ]; then   # one cluster at a time: the link is global
    local other
    other=$(readlink "$ETC_LINK"); other=${other%/etc/slurm.conf}
    if [ "$other" != "$DIR" ] && live_pid "$other/run/slurmctld.pid" slurmctld >/dev/null; then
      die "cluster in $other is still running (and owns $ETC_LINK); stop it first"
    fi
  fi
}
link_etc_conf() {
  [ "${SLURM_CLUSTER_NO_ETC_LINK:-0}" = 1 ] && return 0
  check_etc_link
  mkdir -p "${ETC_LINK%/*}"
  ln -sfn "$CONF" "$ETC_LINK"
}
unlink_etc_conf() {
  if [ -L "$ETC_LINK" ] && [ "$(readlink "$ETC_LINK")" = "$CONF" ]; then rm -f "$ETC_LINK"; fi
}

start_munge() {
  local key=$MUNGE/munge.key
  install -d -m 0755 -o munge -g munge "$MUNGE"   # socket dir must be o+x
  # own key per cluster; root clients talk to our socket only
  if [ ! -s "$key" ]; then
    if command -v mungekey >/dev/null 2>&1; then
      mungekey --create --keyfile="$key" >/dev/null
    else
      dd if=/dev/urandom of="$key" bs=1024 count=1 status=none
    fi
  fi
  chown munge:munge "$key"; chmod 0400 "$key"
  rm -f "$MUNGE_SOCK" "$MUNGE_SOCK.lock" "$PID_MUNGE"
  runuser -u munge -- munged \
    --socket="$MUNGE_SOCK" --key-file="$key" --pid-file="$PID_MUNGE" \
    --log-file="$MUNGE/munged.log" --seed-file="$MUNGE/munged.seed" \
    || { show_logs; die "munged failed to start"; }
  wait_until "$TIMEOUT" "munged socket" test -S "$MUNGE_SOCK" || { show_logs; die "munged not up"; }
  munge -S "$MUNGE_SOCK" -n | unmunge -S "$MUNGE_SOCK" >/dev/null \
    || { show_logs; die "munge/unmunge round trip failed"; }
}

node_idle() {
  local st
  st=$(SLURM_CONF=$CONF sinfo -h -N -o %T 2>/dev/null | head -n1) || return 1
  [ "$st" = idle ]
}

smoke_test() {  # one 'sbatch --wrap hostname' must reach COMPLETED
  local id st out=$DIR/log/smoke-%j.out
  id=$(sbatch --parsable -o "$out" -t 1 --mem=10 --wrap hostname) || { show_logs; die "sbatch failed"; }
  id=${id%%;*}
  job_done() {
    st=$(squeue -h -t all -j "$id" -o %T 2>/dev/null | head -n1)
    case $st in COMPLETED|FAILED|CANCELLED|TIMEOUT|NODE_FAIL|OUT_OF_MEMORY|BOOT_FAIL) return 0 ;; esac
    return 1
  }
  wait_until "$TIMEOUT" "smoke job $id" job_done || { squeue -t all >&2; show_logs; die "smoke job $id did not finish"; }
  [ "$st" = COMPLETED ] || { show_logs; die "smoke job $id ended $st"; }
  log "smoke job $id COMPLETED on $(cat "${out/\%j/$id}" 2>/dev/null)"
}

do_start() {
  [ "$(id -u)" -eq 0 ] || skip "must be root (munged runs as user munge, slurmd as root)"
  mkdir -p "$DIR"; chmod 0755 "$DIR"
  ensure_installed
  id munge >/dev/null 2>&1 || skip "user 'munge' missing (munge package broken?)"

  if live_pid "$PID_CTLD" slurmctld >/dev/null || live_pid "$PID_SLURMD" slurmd >/dev/null ||
     live_pid "$PID_MUNGE" munged >/dev/null; then
    if live_pid "$PID_CTLD" slurmctld >/dev/null && live_pid "$PID_SLURMD" slurmd >/dev/null &&
       live_pid "$PID_MUNGE" munged >/dev/null && node_idle; then
      log "cluster in $DIR already running"; echo "export SLURM_CONF=$CONF"; return 0
    fi
    log "partial cluster found in $DIR, restarting it"; do_stop
  fi
  check_etc_link
  # a foreign slurmd on this host would answer on our node name
  local others
  others=$(running_pids slurmd)
  [ -z "$others" ] || log "warning: another slurmd is running on this host (pid $others)"

  # from here on, a failed start must not leave daemons behind
  trap 'rc=$?; if [ $rc -ne 0 ]; then log "start failed (exit $rc), cleaning up"; do_stop || true; fi' EXIT

  # fresh state every start: no clash with an old ClusterName, no old jobs
  rm -rf "$STATE" "$SPOOL" "$RUN"
  mkdir -p "$ETC" "$STATE" "$SPOOL" "$LOGD" "$RUN"
  chmod 0755 "$ETC" "$STATE" "$SPOOL" "$LOGD" "$RUN"
  : >"$LOGD/slurmctld.log"; : >"$LOGD/slurmd.log"
  write_config

  link_etc_conf
  start_munge
  export SLURM_CONF=$CONF
  slurmctld -f "$CONF" || { show_logs; die "slurmctld failed to start"; }
  wait_until "$TIMEOUT" "slurmctld" sh -c "scontrol ping 2>/dev/null | grep -q UP" \
    || { show_logs; die "slurmctld does not answer"; }
  slurmd -f "$CONF" -N "$(hostname -s)" || { show_logs; die "slurmd failed to start"; }
  wait_until "$TIMEOUT" "node idle" node_idle || {
    SLURM_CONF=$CONF sinfo -N -l >&2 || true
    SLURM_CONF=$CONF scontrol show node >&2 || true
    show_logs; die "node did not become idle within ${TIMEOUT}s"; }
  if [ "${SLURM_CLUSTER_SMOKE:-1}" != 0 ]; then smoke_test; fi
  trap - EXIT
  log "cluster $(sed -n 's/^ClusterName=//p' "$CONF") up in $DIR"
  echo "export SLURM_CONF=$CONF"
}

do_status() {
  live_pid "$PID_MUNGE" munged >/dev/null && live_pid "$PID_CTLD" slurmctld >/dev/null &&
    live_pid "$PID_SLURMD" slurmd >/dev/null
}

case $CMD in
  start)  do_start ;;
  stop)   do_stop ;;
  status) do_status ;;
  env)    echo "export SLURM_CONF=$CONF" ;;
  *)      usage ;;
esac
