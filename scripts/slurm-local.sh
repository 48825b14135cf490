#!/usr/bin/env bash
# A real single-node Slurm cluster on this machine, for the integration test and for trying
# `impactsweep slurm` by hand. Debian's slurmctld + slurmd + munge, run as root without systemd
# or cgroups; every file (configs, state, logs, PID files) lives under one state directory.
#
#   scripts/slurm-local.sh start [DIR]   install the packages if missing, start the daemons,
#                                        wait until the node is idle; prints SLURM_CONF=... and
#                                        the PIDs (also in DIR/pids)
#   scripts/slurm-local.sh stop  [DIR]   cancel this cluster's jobs, stop the daemons by PID
#   scripts/slurm-local.sh status [DIR]  which daemons are running
#
# DIR defaults to $SLURM_LOCAL_DIR or /tmp/impactsweep-slurm. Then point the Slurm commands at
# the cluster with `export SLURM_CONF=DIR/etc/slurm.conf`. With SLURM_LOCAL_OWNER=PID, a
# watchdog stops the cluster once process PID has exited (the test sets its own PID, so even a
# killed test leaves no daemons behind).
#
# Exit status: 0 ok; 3 the cluster cannot be brought up here (not root, or the packages are
# missing and cannot be installed: the test skips loudly on 3); anything else is a failure
# (the daemons started so far are stopped again).
#
# Why root: munged must run as user `munge` (started with runuser) and slurmd must run as root
# to launch jobs; with SlurmUser=root the jobs of user root are accepted and run as root.
# Ports: the first free pair from 16817 up (SLURM_LOCAL_PORT overrides), so this cluster does not
# collide with a system Slurm on 6817/6818.
set -euo pipefail

PACKAGES=(slurmctld slurmd slurm-client munge)
EXIT_UNAVAILABLE=3

SELF=$(readlink -f "$0")
cmd=${1:-}
T=${2:-${SLURM_LOCAL_DIR:-/tmp/impactsweep-slurm}}

say() { echo "slurm-local: $*" >&2; }
ts() { date +%s.%N; }
el() { awk -v a="$1" -v b="$(ts)" 'BEGIN{printf "%.1f s", b-a}'; }

have_packages() {
  command -v slurmctld >/dev/null && command -v slurmd >/dev/null &&
    command -v sbatch >/dev/null && command -v munged >/dev/null && id munge >/dev/null 2>&1
}

# Installs the packages with apt-get (update first: a fresh machine has stale or no lists).
# Returns non-zero when that is impossible here.
install_packages() {
  if have_packages; then return 0; fi
  if [ "$(id -u)" -ne 0 ]; then
    say "the Slurm packages (${PACKAGES[*]}) are missing and we are not root: cannot install them"
    return 1
  fi
  if ! command -v apt-get >/dev/null; then
    say "the Slurm packages (${PACKAGES[*]}) are missing and there is no apt-get"
    return 1
  fi
  local t0 attempt
  t0=$(ts)
  export DEBIAN_FRONTEND=noninteractive
  # Two attempts: a transient mirror hiccup should not turn into a skipped test.
  for attempt in 1 2; do
    say "installing ${PACKAGES[*]} with apt-get (attempt $attempt)"
    if apt-get -o DPkg::Lock::Timeout=300 update -qq >&2 &&
      apt-get -o DPkg::Lock::Timeout=300 install -y -qq --no-install-recommends \
        "${PACKAGES[@]}" >/dev/null; then
      break
    fi
    sleep 5
  done
  # The packages start their daemons through systemd/invoke-rc.d where it exists; we run our
  # own, so a stray system munged (if any was started) does not matter: ours has its own socket.
  if ! have_packages; then
    say "apt-get could not install ${PACKAGES[*]}"
    return 1
  fi
  say "install: $(el "$t0")"
}

port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }

pick_ports() {
  local p=${SLURM_LOCAL_PORT:-16817}
  for _ in $(seq 200); do
    if port_free "$p" && port_free $((p + 1)); then
      CTLD_PORT=$p
      SLURMD_PORT=$((p + 1))
      return 0
    fi
    p=$((p + 2))
  done
  say "no free port pair found from ${SLURM_LOCAL_PORT:-16817}"
  return 1
}

# Process names as /proc/PID/comm shows them, to avoid killing a recycled PID.
pidfiles() {
  echo "watchdog $T/run/watchdog.pid"
  echo "slurmd $T/run/slurmd.pid"
  echo "slurmctld $T/run/slurmctld.pid"
  echo "munged $T/munge-run/munged.pid"
}

alive() { # NAME PID
  local comm
  comm=$(cat "/proc/$2/comm" 2>/dev/null) || return 1
  case $1 in
    watchdog) [ "$comm" = bash ] && tr '\0' ' ' <"/proc/$2/cmdline" | grep -q slurm-local ;;
    *) [ "$comm" = "$1" ] ;;
  esac
}

stop_cluster() {
  [ -d "$T" ] || return 0
  # Cancel this cluster's jobs first so no slurmstepd outlives the daemons.
  if [ -f "$T/etc/slurm.conf" ] && [ -s "$T/run/slurmctld.pid" ] &&
    alive slurmctld "$(cat "$T/run/slurmctld.pid")"; then
    export SLURM_CONF="$T/etc/slurm.conf"
    if [ -n "$(squeue -h -o %i 2>/dev/null)" ]; then
      scancel --full --user="$(id -un)" 2>/dev/null || true
      for _ in $(seq 50); do
        [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break
        sleep 0.1
      done
    fi
  fi
  local name f p
  while read -r name f; do
    [ -s "$f" ] || continue
    p=$(cat "$f")
    [ "$p" = "$$" ] && { rm -f "$f"; continue; } # the watchdog, stopping the cluster itself
    if alive "$name" "$p"; then
      kill "$p" 2>/dev/null || true
      for _ in $(seq 100); do alive "$name" "$p" || break; sleep 0.1; done
      if alive "$name" "$p"; then
        say "$name ($p) did not stop on SIGTERM: SIGKILL"
        kill -9 "$p" 2>/dev/null || true
        for _ in $(seq 50); do alive "$name" "$p" || break; sleep 0.1; done
      fi
      alive "$name" "$p" && { say "$name ($p) is still running"; return 1; }
      say "stopped $name ($p)"
    fi
    rm -f "$f"
  done < <(pidfiles)
  rm -f "$T/pids"
}

status_cluster() {
  local name f any=1
  while read -r name f; do
    if [ -s "$f" ] && alive "$name" "$(cat "$f")"; then
      echo "$name $(cat "$f") running"
      any=0
    else
      echo "$name stopped"
    fi
  done < <(pidfiles)
  return $any
}

dump_logs() {
  if [ -s "$T/run/slurmctld.pid" ]; then say "--- sinfo ---"; sinfo -N >&2 2>&1 || true; fi
  local f
  for f in "$T"/log/*.log "$T"/munge-run/munged.log; do
    [ -f "$f" ] || continue
    say "--- tail $f ---"; tail -n 30 "$f" >&2
  done
}

start_cluster() {
  local t0 t1
  t0=$(ts)
  if ! install_packages; then
    say "SKIP: no Slurm here (see above)"
    exit $EXIT_UNAVAILABLE
  fi
  if [ "$(id -u)" -ne 0 ]; then
    say "SKIP: the local cluster needs root (munged runs as user munge, slurmd launches jobs)"
    exit $EXIT_UNAVAILABLE
  fi
  if [ -d "$T/run" ] && status_cluster >/dev/null; then
    say "a cluster is already running in $T: '$0 stop $T' first"
    exit 1
  fi
  # From here on, a failure stops whatever was started.
  trap 'rc=$?; if [ $rc -ne 0 ]; then dump_logs; stop_cluster || true; fi' EXIT

  pick_ports
  mkdir -p "$T"
  rm -rf "${T:?}"/{etc,state,spool,log,run,munge-etc,munge-run,munge-lib}
  mkdir -p "$T"/{etc,state,spool,log,run,munge-etc,munge-run,munge-lib}
  chmod 755 "$T" # munged (user munge) must reach its key and socket below it
  dd if=/dev/urandom of="$T/munge-etc/munge.key" bs=1024 count=1 status=none
  chown -R munge:munge "$T"/munge-etc "$T"/munge-run "$T"/munge-lib
  chmod 700 "$T"/munge-etc "$T"/munge-lib
  chmod 755 "$T"/munge-run
  chmod 400 "$T/munge-etc/munge.key"
  if ! runuser -u munge -- test -r "$T/munge-etc/munge.key"; then
    say "user munge cannot reach $T: make its parent directories traversable (chmod o+x)"
    exit 1
  fi
  local msock="$T/munge-run/munge.socket"

  cat >"$T/etc/slurm.conf" <<EOF
# Single-node Slurm written by scripts/slurm-local.sh; everything lives under $T.
ClusterName=impactsweep-local
SlurmctldHost=localhost
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
# Root runs the daemons and submits the jobs (no systemd, no slurm user needed).
SlurmUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$msock
# No cgroups in a container: track processes by their parent PID, no task binding.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
MailProg=/bin/true
# Schedule as soon as a job arrives (the default batches submissions).
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/run/slurmctld.pid
SlurmdPidFile=$T/run/slurmd.pid
SlurmctldLogFile=$T/log/slurmctld.log
SlurmdLogFile=$T/log/slurmd.log
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$(nproc)
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF="$T/etc/slurm.conf"

  t1=$(ts)
  # Each daemon forks into the background and writes its PID file.
  runuser -u munge -- /usr/sbin/munged --key-file="$T/munge-etc/munge.key" --socket="$msock" \
    --pid-file="$T/munge-run/munged.pid" --log-file="$T/munge-run/munged.log" \
    --seed-file="$T/munge-lib/munged.seed"
  munge -S "$msock" -n | unmunge -S "$msock" >/dev/null # self-test: a credential round trip
  slurmctld
  slurmd -N localhost
  local state=""
  for _ in $(seq 300); do # <= 60 s: controller answers and the node is idle
    state=$(sinfo -h -N -o %T 2>/dev/null || true)
    [ "$state" = idle ] && break
    sleep 0.2
  done
  if [ "$state" != idle ]; then
    say "the node did not become idle within 60 s (state '${state}')"
    exit 1
  fi
  if [ -n "${SLURM_LOCAL_OWNER:-}" ]; then
    # The owner (the test process) may die without stopping us (Ctrl-C, SIGKILL): then the
    # watchdog stops the cluster. It ignores the terminal's SIGINT/SIGHUP, keeps none of our
    # output pipes open, and is stopped by PID like the daemons.
    (
      trap '' INT HUP
      while kill -0 "$SLURM_LOCAL_OWNER" 2>/dev/null; do sleep 1; done
      exec "$SELF" stop "$T"
    ) </dev/null >>"$T/log/watchdog.log" 2>&1 &
    echo $! >"$T/run/watchdog.pid"
  fi
  local name f
  : >"$T/pids"
  while read -r name f; do
    if [ -s "$f" ]; then echo "$name $(cat "$f")" >>"$T/pids"; fi
  done < <(pidfiles)
  say "daemons ready: $(el "$t1") (start total $(el "$t0"))"
  trap - EXIT
  echo "SLURM_CONF=$SLURM_CONF"
  cat "$T/pids"
}

case "$cmd" in
  start) start_cluster ;;
  stop) stop_cluster ;;
  status) status_cluster ;;
  *)
    awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"
    exit 2
    ;;
esac
