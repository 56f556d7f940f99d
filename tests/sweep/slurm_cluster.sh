# shellcheck shell=bash
# A one-node Slurm cluster on this machine for tests and benchmarks, started
# and stopped by the caller (source this file):
#   vt_slurm_start DIR    munged, slurmctld and slurmd with every file in DIR
#                         (munge key and socket, slurm.conf, state, spool,
#                         logs); ports: a free pair on 127.0.0.1; node = this
#                         host with 2 CPUs; no cgroups (proctrack/linuxproc,
#                         task/none); exports SLURM_CONF; waits until the node
#                         is idle.
#   vt_slurm_stop         kills the daemons by the PIDs vt_slurm_start started
#                         (and the watchdog), waits for them.
# A watchdog kills the daemons when the shell that started them is gone, so
# nothing survives a killed test. Needs root (SlurmUser=root) and Debian's
# slurm-wlm and munge (VT_DEB_PACKAGES).

VT_SLURM_PIDS=()
VT_SLURM_DIR=""

vt_slurm_log() { echo "[slurm] $*" >&2; }

vt_slurm_free_ports() {
  /usr/bin/python3 - <<'PY'
import socket
socks = []
for _ in range(2):
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    socks.append(s)
print(" ".join(str(s.getsockname()[1]) for s in socks))
PY
}

vt_slurm_start() {
  local dir="$1" node
  node="$(hostname -s)"
  VT_SLURM_DIR="${dir}"
  mkdir -p "${dir}/state" "${dir}/spool" "${dir}/munge"
  chmod 700 "${dir}" "${dir}/munge"
  head -c 1024 /dev/urandom > "${dir}/munge/munge.key"
  chmod 400 "${dir}/munge/munge.key"
  local sock="${dir}/munge/munge.socket"
  munged --foreground --force --socket="${sock}" --key-file="${dir}/munge/munge.key" \
    --pid-file="${dir}/munge/munged.pid" --log-file="${dir}/munge/munged.log" \
    --seed-file="${dir}/munge/munged.seed" 2> "${dir}/munge/munged.stderr" &
  VT_SLURM_PIDS+=("$!")
  local i
  for ((i = 0; i < 100; i++)); do
    munge -S "${sock}" -n 2>/dev/null | unmunge -S "${sock}" >/dev/null 2>&1 && break
    sleep 0.1
  done
  ((i < 100)) || { vt_slurm_log "munged did not start: $(cat "${dir}/munge/munged.stderr" "${dir}/munge/munged.log" 2>/dev/null | tail -3)"; return 1; }
  local ports
  read -r -a ports <<< "$(vt_slurm_free_ports)"
  cat > "${dir}/slurm.conf" <<CONF
ClusterName=vtsweep
SlurmctldHost=${node}(127.0.0.1)
SlurmctldPort=${ports[0]}
SlurmdPort=${ports[1]}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=${sock}
StateSaveLocation=${dir}/state
SlurmdSpoolDir=${dir}/spool
SlurmctldPidFile=${dir}/slurmctld.pid
SlurmdPidFile=${dir}/slurmd.pid
SlurmctldLogFile=${dir}/slurmctld.log
SlurmdLogFile=${dir}/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
SwitchType=switch/none
MpiDefault=none
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MinJobAge=600
MaxArraySize=10001
NodeName=${node} NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=vt Nodes=${node} Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="${dir}/slurm.conf"
  slurmctld -D -i -f "${SLURM_CONF}" > "${dir}/slurmctld.stderr" 2>&1 &
  VT_SLURM_PIDS+=("$!")
  slurmd -D -f "${SLURM_CONF}" -N "${node}" > "${dir}/slurmd.stderr" 2>&1 &
  VT_SLURM_PIDS+=("$!")
  # watchdog: the daemons die with the shell that started them
  local owner=$$
  ( trap '' HUP; while kill -0 "${owner}" 2>/dev/null; do sleep 1; done
    kill -9 "${VT_SLURM_PIDS[@]}" 2>/dev/null; vt_slurm_kill_steps "${dir}" ) >/dev/null 2>&1 &
  VT_SLURM_WATCHDOG=$!
  for ((i = 0; i < 300; i++)); do
    [[ "$(sinfo -h -n "${node}" -o %T 2>/dev/null)" == idle ]] && break
    sleep 0.1
  done
  if ((i == 300)); then
    vt_slurm_log "node ${node} not idle after 30 s: $(sinfo -h -o '%T %E' 2>&1 | head -2)"
    tail -5 "${dir}/slurmctld.log" "${dir}/slurmd.log" >&2 2>/dev/null
    return 1
  fi
  vt_slurm_log "cluster up: node ${node} (2 CPUs), ports ${ports[*]}, pids ${VT_SLURM_PIDS[*]}"
}

# slurmstepd (one per running job step) detaches from slurmd: find ours by
# their open files in the cluster's folder and kill them.
vt_slurm_kill_steps() {
  local dir="$1" pid
  for pid in $(pgrep -x slurmstepd 2>/dev/null); do
    if ls -l "/proc/${pid}/fd" 2>/dev/null | grep -q -- "${dir}/"; then kill -9 "${pid}" 2>/dev/null || true; fi
  done
  return 0
}

vt_slurm_stop() {
  local pid
  if [[ -n "${VT_SLURM_DIR}" && -n "${SLURM_CONF:-}" ]]; then
    scancel --user=root >/dev/null 2>&1 || true
    for _ in $(seq 50); do [[ -z "$(squeue -h 2>/dev/null)" ]] && break; sleep 0.2; done
  fi
  for pid in "${VT_SLURM_PIDS[@]}"; do
    kill -TERM "${pid}" 2>/dev/null || true
  done
  for pid in "${VT_SLURM_PIDS[@]}"; do
    for _ in $(seq 50); do kill -0 "${pid}" 2>/dev/null || break; sleep 0.1; done
    kill -9 "${pid}" 2>/dev/null || true
    wait "${pid}" 2>/dev/null || true
  done
  if [[ -n "${VT_SLURM_DIR}" ]]; then vt_slurm_kill_steps "${VT_SLURM_DIR}"; fi
  if [[ -n "${VT_SLURM_WATCHDOG:-}" ]]; then
    kill "${VT_SLURM_WATCHDOG}" 2>/dev/null || true
    wait "${VT_SLURM_WATCHDOG}" 2>/dev/null || true
  fi
  VT_SLURM_PIDS=()
  VT_SLURM_WATCHDOG=""
  return 0
}
