#!/usr/bin/env bash
# A real single-node Slurm cluster on loopback for the Slurm executor's tests (docs/slurm-test-cluster.md):
# munged, slurmctld and slurmd started directly (no systemd, no service scripts), all state (slurm.conf,
# munge key and socket, pid files, spool, logs) under one directory, ${MOCAP_SLURM_DIR:-/tmp/mocaplabel-slurm};
# nothing is written to /etc/slurm or /etc/munge. ctest's fixture "slurm" (tests/slurm) starts and stops it.
#   slurm-cluster.sh install   install the missing Debian packages (munge slurmctld slurmd slurm-client)
#   slurm-cluster.sh start     install if needed, start the daemons, wait for the node to be idle, print
#                              `export SLURM_CONF=...` (use: eval "$(scripts/slurm-cluster.sh start)");
#                              a no-op when already up; after a crash (stale pid files) cleans up and restarts
#   slurm-cluster.sh stop      cancel the cluster's jobs, stop the three daemons; succeeds when nothing runs
#   slurm-cluster.sh status    one line and exit 0 when up, exit 1 when not
#   slurm-cluster.sh env       print `export SLURM_CONF=...`
# Ports: MOCAP_SLURM_CTLD_PORT (default 16817) and MOCAP_SLURM_SLURMD_PORT (16818).
# As root (CI) the daemons and the jobs run as root; otherwise SlurmUser/SlurmdUser are the current user,
# which runs jobs of that user only (untested: installing the packages needs root or sudo anyway).
set -euo pipefail

dir=${MOCAP_SLURM_DIR:-/tmp/mocaplabel-slurm}
ctld_port=${MOCAP_SLURM_CTLD_PORT:-16817}
slurmd_port=${MOCAP_SLURM_SLURMD_PORT:-16818}
start_timeout=${MOCAP_SLURM_START_TIMEOUT:-30}
packages=(munge slurmctld slurmd slurm-client)

conf=$dir/slurm.conf
munge_dir=$dir/munge
munge_key=$munge_dir/munge.key
munge_socket=$munge_dir/munge.socket.2
node=$(hostname -s 2>/dev/null || uname -n | cut -d. -f1)
export SLURM_CONF=$conf

log() { echo "slurm-cluster: $*" >&2; }
die() { log "$*"; exit 1; }

install_packages() {
  local missing=() p status
  for p in "${packages[@]}"; do
    status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
    [[ "$status" == "install ok installed" ]] || missing+=("$p")
  done
  [[ ${#missing[@]} -eq 0 ]] && return 0
  local sudo_cmd=()
  if [[ $(id -u) -ne 0 ]]; then
    if ! command -v sudo >/dev/null 2>&1 || ! sudo -n true 2>/dev/null; then
      die "missing Debian packages: ${missing[*]}; run as root, or with sudo, or: apt-get install ${missing[*]}"
    fi
    sudo_cmd=(sudo -n)
  fi
  log "installing ${missing[*]}"
  # The packages' maintainer scripts start munge/slurmctld/slurmd through invoke-rc.d; a policy-rc.d that
  # answers 101 ("action forbidden") keeps them from starting the system's daemons (and failing without
  # systemd). Ours only exists during the install, and only when there was none.
  local policy=/usr/sbin/policy-rc.d ours=0
  if [[ ! -e $policy ]]; then
    printf '#!/bin/sh\n# slurm-cluster.sh install: no service starts while it installs packages\nexit 101\n' \
      | "${sudo_cmd[@]}" tee "$policy" >/dev/null
    "${sudo_cmd[@]}" chmod 755 "$policy"
    ours=1
  fi
  local rc=0
  {
    "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
      "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive \
        apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  } || rc=$?
  [[ $ours -eq 1 ]] && "${sudo_cmd[@]}" rm -f "$policy"
  [[ $rc -eq 0 ]] || die "apt-get install ${missing[*]} failed (exit $rc)"
}

# Whether process PID exists and is not a zombie (PID 1 here may reap a killed daemon only seconds later).
alive() {
  local stat
  stat=$(cat "/proc/$1/stat" 2>/dev/null) || return 1
  stat=${stat##*) }
  [[ ${stat:0:1} != [ZX] ]]
}

# The pid in DAEMON's pid file when that process is alive and is DAEMON; nothing (exit 1) otherwise.
daemon_pid() {
  local name=$1 file=$dir/run/$1.pid pid
  [[ -s $file ]] || return 1
  pid=$(<"$file")
  [[ $pid =~ ^[0-9]+$ ]] && alive "$pid" || return 1
  [[ $(cat "/proc/$pid/comm" 2>/dev/null) == "$name" ]] || return 1
  echo "$pid"
}

controller_up() { scontrol ping 2>/dev/null | grep -q 'is UP'; }
node_state() { sinfo -h -N -n "$node" -o %T 2>/dev/null | head -n 1; }

# Up: the three daemons alive, the controller answering and the node usable (not down/drained).
is_up() {
  local d state
  for d in munged slurmctld slurmd; do daemon_pid "$d" >/dev/null || return 1; done
  controller_up || return 1
  state=$(node_state)
  [[ $state =~ ^(idle|mixed|allocated|completing)$ ]]
}

print_env() { printf 'export SLURM_CONF=%q\n' "$conf"; }

write_config() {
  local user ncfg
  if [[ $(id -u) -eq 0 ]]; then user=root; else user=$(id -un); fi
  # slurmd -C's first line: NodeName=<host> CPUs=.. Boards=.. SocketsPerBoard=.. CoresPerSocket=..
  # ThreadsPerCore=.. RealMemory=..; its NodeName is replaced by ours (with the loopback address).
  ncfg=$(slurmd -C 2>/dev/null | head -n 1 | sed -E 's/^NodeName=[^ ]+ *//')
  [[ $ncfg == *CPUs=* ]] || die "slurmd -C did not print a node line: $(slurmd -C 2>&1 | head -n 3)"
  cat >"$conf.tmp" <<EOF
# Written by scripts/slurm-cluster.sh (docs/slurm-test-cluster.md): one node on loopback, state in $dir.
ClusterName=mocaplabel
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$munge_socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool/slurmd
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# No systemd, no cgroups, no accounting.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SwitchType=switch/none
MpiDefault=none
MailProg=/bin/true
# Jobs share the node by CPU; memory is not a consumable (a job would otherwise take all of it).
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
# The scheduler runs on each submission and then about every second (slurmctld holds it for ~3 s after it
# starts: see the probe job below); a job whose dependency can never be met is cancelled, not left pending.
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
DependencyParameters=kill_invalid_depend
ReturnToService=2
MinJobAge=300
MaxArraySize=10001
MaxJobCount=100000
KillWait=5
InactiveLimit=0
SlurmdTimeout=300
NodeName=$node NodeAddr=127.0.0.1 $ncfg State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
  mv "$conf.tmp" "$conf"
}

start_munged() {
  mkdir -p "$munge_dir"
  chmod 755 "$munge_dir"  # munged refuses a socket directory writable by group or others
  if [[ ! -s $munge_key ]]; then
    rm -f "$munge_key"
    if command -v mungekey >/dev/null 2>&1; then
      mungekey --create --keyfile="$munge_key" >/dev/null
    else
      (umask 077 && dd if=/dev/urandom of="$munge_key" bs=1024 count=1 status=none)
    fi
  fi
  chmod 400 "$munge_key"
  rm -f "$munge_socket" "$munge_socket.lock"
  munged --key-file="$munge_key" --socket="$munge_socket" --pid-file="$dir/run/munged.pid" \
    --log-file="$dir/log/munged.log" --seed-file="$munge_dir/munged.seed" \
    || die "munged did not start: $(tail -n 5 "$dir/log/munged.log" 2>/dev/null)"
  local i
  for ((i = 0; i < 50; i++)); do
    [[ -S $munge_socket ]] && return 0
    sleep 0.1
  done
  die "munged's socket $munge_socket did not appear: $(tail -n 5 "$dir/log/munged.log" 2>/dev/null)"
}

log_tails() {
  local f
  for f in "$dir"/log/munged.log "$dir"/log/slurmctld.log "$dir"/log/slurmd.log; do
    [[ -f $f ]] || continue
    echo "--- tail $f" >&2
    tail -n 15 "$f" >&2
  done
}

stop_daemon() {
  local name=$1 pid i
  if pid=$(daemon_pid "$name"); then
    kill "$pid" 2>/dev/null || true
    for ((i = 0; i < 100; i++)); do
      alive "$pid" || break
      sleep 0.1
    done
    if alive "$pid"; then
      log "$name ($pid) did not stop on SIGTERM in 10 s; SIGKILL"
      kill -9 "$pid" 2>/dev/null || true
      sleep 0.2
    fi
  fi
  rm -f "$dir/run/$name.pid"
}

# slurmstepd processes of this cluster's jobs (slurmd passes them our SLURM_CONF in the environment) and
# everything under them: what is left of jobs when slurmctld died before it could cancel them.
our_job_processes() {
  local p
  for p in $(pgrep -x slurmstepd 2>/dev/null || true); do
    tr '\0' '\n' 2>/dev/null <"/proc/$p/environ" | grep -qxF "SLURM_CONF=$conf" && descendants "$p"
  done
  return 0
}
descendants() {
  local c
  echo "$1"
  for c in $(pgrep -P "$1" 2>/dev/null || true); do descendants "$c"; done
}

cmd_stop() {
  local i jobs
  if daemon_pid slurmctld >/dev/null && controller_up; then
    jobs=$(squeue -h -o %A 2>/dev/null | sort -u | tr '\n' ' ')
    if [[ -n ${jobs// /} ]]; then
      # shellcheck disable=SC2086
      scancel $jobs 2>/dev/null || true
      for ((i = 0; i < 50; i++)); do
        [[ -z $(squeue -h -o %A 2>/dev/null) ]] && break
        sleep 0.2
      done
    fi
  fi
  stop_daemon slurmd
  stop_daemon slurmctld
  stop_daemon munged
  local left
  left=$(our_job_processes | tr '\n' ' ')
  if [[ -n $left ]]; then
    log "killing what is left of jobs: $left"
    # shellcheck disable=SC2086
    kill -9 $left 2>/dev/null || true
  fi
  rm -f "$munge_socket" "$munge_socket.lock"
}

cmd_start() {
  if [[ -d $dir ]] && is_up; then
    print_env
    return 0
  fi
  install_packages
  # Whatever is left from an earlier run (a crashed daemon, stale pid files) goes first.
  [[ -d $dir ]] && cmd_stop
  mkdir -p "$dir"/{run,log,state,spool/slurmd}
  chmod 755 "$dir"
  write_config
  start_munged
  # -c: clear the saved job state, so every start is a fresh cluster without old jobs (job ids go on counting).
  slurmctld -c -f "$conf" || { log_tails; die "slurmctld did not start"; }
  slurmd -c -f "$conf" -N "$node" || { log_tails; die "slurmd did not start"; }
  local t0=$SECONDS state="" d
  while ((SECONDS - t0 < start_timeout)); do
    if controller_up; then
      state=$(node_state)
      [[ $state == idle ]] && break
    fi
    if ((SECONDS - t0 >= 2)); then  # a daemon that died (a port in use, a bad config) fails at once
      for d in munged slurmctld slurmd; do
        daemon_pid "$d" >/dev/null || { log_tails; die "$d exited while the cluster was starting"; }
      done
    fi
    sleep 0.2
  done
  if [[ $state != idle ]]; then
    log_tails
    die "the cluster did not come up in ${start_timeout} s (controller: $(scontrol ping 2>&1 | head -n 1); node $node: ${state:-no state})"
  fi
  # slurmctld schedules its first job only ~3 s after it started, however early the job came: a probe job
  # waits that out, so that `start` returns a cluster that runs jobs at once.
  local probe
  probe=$(sbatch --parsable --job-name=slurm-cluster-probe --output=/dev/null --chdir=/ --wrap=true 2>&1) \
    || { log_tails; die "sbatch of the probe job failed: $probe"; }
  probe=${probe%%;*}
  while [[ -n $(squeue -h -j "$probe" 2>/dev/null) ]]; do
    if ((SECONDS - t0 >= start_timeout)); then
      log_tails
      die "the probe job $probe did not run in ${start_timeout} s: $(scontrol show job "$probe" 2>&1 | grep -o 'JobState=.*')"
    fi
    sleep 0.1
  done
  [[ $(scontrol show job "$probe" 2>/dev/null) == *JobState=COMPLETED* ]] \
    || { log_tails; die "the probe job $probe did not complete: $(scontrol show job "$probe" 2>&1 | grep -o 'JobState=.*')"; }
  print_env
}

cmd_status() {
  if [[ -d $dir ]] && is_up; then
    echo "slurm: up, controller $node:$(sed -n 's/^SlurmctldPort=//p' "$conf"), node $node $(node_state), SLURM_CONF=$conf"
    return 0
  fi
  local d s=""
  for d in munged slurmctld slurmd; do
    if daemon_pid "$d" >/dev/null; then s+=" $d:running"; else s+=" $d:down"; fi
  done
  echo "slurm: not up ($dir;$s)"
  return 1
}

case ${1:-} in
  install) install_packages ;;
  start) cmd_start ;;
  stop) [[ -d $dir ]] && cmd_stop; exit 0 ;;
  status) cmd_status ;;
  env) print_env ;;
  *) echo "usage: $0 install|start|stop|status|env" >&2; exit 2 ;;
esac
