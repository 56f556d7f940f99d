#!/usr/bin/env bash
# The main job: a complete virtual triaxial test on the ROS rig.
#
#   launch_equiv_scripts/run_triaxial.sh [PROTOCOL.yaml]
#   launch_equiv_scripts/run_triaxial.sh --resume OUTDIR   continue a killed test
#   OUT=output/mine SERVO_NODE=py_servo_controller.py launch_equiv_scripts/run_triaxial.sh
#   RECORD=0 ...   no rosbag recording (and no bag plots), e.g. to time the rig alone
#   RIG_ARGS="nodelets:=false ..."   extra protocol_rig.launch arguments
#   VT_NETNS=0 ... do not run the rig in its own network namespace
#   SNAPSHOTS=0 ...   no specimen snapshots (and no specimen picture)
#   VT_SKIP_BUILD=1 ...  skip the package check and the build (already done)
#   PLOTS=0 ...    no plots and no specimen picture at the end (the data only)
#
# --resume OUTDIR: the test in OUTDIR was killed (kill -9, power loss): go on
# from its last checkpoint inside a stage (OUTDIR/results.h5.checkpoint.h5,
# written every output.checkpoint_seconds (default 60) wall seconds or
# output.checkpoint_ticks ticks) with the protocol it names (unchanged, else
# refused), into the same results.h5 (samples after the checkpoint are
# dropped and computed again). The killed run's bags (rig_*.bag.active) are
# reindexed (rosbag reindex) and kept as rig_*.bag; the resumed run records
# into rig_rN_*.bag, its ticks continuing from the checkpoint's tick + 1.
# The finished test equals an uninterrupted one bit for bit (results series,
# summary numbers, the ticks' messages).
#
# Default protocol: config/protocols/drained_100kPa_adaptive.yaml (the
# shipped dense 1000-sphere sample, servo consolidation at 100 kPa, a
# quasi-static drained shear to 5 % axial strain at the adaptive rate of the
# rate controller node, time step from the contacts). The fast, NOT
# quasi-static variant: config/protocols/drained_100kPa.yaml (eps' = 1e-5).
#
# What it does: installs what is missing and builds (lib/ensure_built.sh);
# then runs the rig in a network namespace of its own that holds only the
# loopback interface (`unshare -n`, or `unshare -rn` when not root; ROS 1
# has no authentication, and roscpp listens on every interface); picks a
# free master port on 127.0.0.1; sets ROS_HOME under the output folder;
# starts roscore, the rig (protocol_rig.launch: dem_node, servo controller,
# test_protocol_node) and the recorder of every topic (bag_recorder, in the
# rig's process); runs the protocol through the run_test action
# (scripts/run_test_client.py, progress printed); supervises every process
# it started; stops them all at the end; makes the plots. One output folder
# (${OUT:-output/default}) holds:
#   rig_*.bag         every rig topic (split at 512 MB and at every checkpoint)
#   results.h5        sample-tick time series + summary attributes
#   results.h5.checkpoint.h5  the last checkpoint of a running test (--resume; removed at the end)
#   summary.json      the test summary (also printed last)
#   plots/            bag_report.py: q-eps_a, eps_v-eps_a, q-p, e-log p,
#                     I_mom and kinetic energy; rig_series.csv
#   results_*.png     plot_results.py of results.h5
#   specimen/         VTK snapshots of the specimen (dem_node ~snapshot_dir: at
#                     the load, at every stage end, every output.snapshot_interval
#                     steps); open specimen/*.pvd in ParaView
#   specimen_section.png  section through the cell before and after the test
#                     (scripts/specimen_section.py)
#   ros_home/         ROS logs of this run (rig.log: roslaunch and the nodes)
#
# Faults (README "When things go wrong"): no wait is unbounded. A process of
# the rig that dies is noticed within seconds (the client probes the action
# server's process every second; the protocol node probes dem_node and the
# servo; this script watches roscore, roslaunch and roslaunch's "process has
# died" lines); the summary then says "interrupted" and names what died.
# Ctrl-C (SIGINT or SIGTERM): the test is cancelled (verdict "preempted"),
# the rig stopped gently (the bag is closed), the plots of what was recorded
# made; a second Ctrl-C kills every process started here at once.
# Exit codes: 0 completed; 1 the test ended with another verdict (unstable,
# step_limit, aborted, failed; see summary.json); 2 bad input, or the
# master/rig did not start; 3 a process of the rig died (verdict
# "interrupted", naming it); 130 interrupted by Ctrl-C (verdict "preempted").
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
repo="$(pwd)"

if [[ -z "${VT_IN_NETNS:-}" ]]; then
  # shellcheck source=SCRIPTDIR/lib/ensure_built.sh
  source launch_equiv_scripts/lib/ensure_built.sh
  # VT_SKIP_BUILD=1: the caller has built everything (the fault tests).
  if [[ "${VT_SKIP_BUILD:-0}" == 1 ]]; then vt_use_system_path; else vt_ensure_built all; fi
  # The rest runs in a network namespace holding only loopback (the build
  # above may need the network; the rig must not be reachable from it).
  if [[ "${VT_NETNS:-1}" != 0 ]]; then
    ns=(unshare -n)
    [[ "$(id -u)" -ne 0 ]] && ns=(unshare -rn)
    if "${ns[@]}" /bin/sh -c 'ip link set lo up' 2>/dev/null; then
      exec "${ns[@]}" env VT_IN_NETNS=1 /bin/bash -c 'ip link set lo up && exec "$@"' bash "${repo}/launch_equiv_scripts/run_triaxial.sh" "$@"
    fi
    echo "[rig] warning: cannot create a network namespace (${ns[*]} refused); the rig's roscpp" \
         "sockets listen on every interface of this host (README: When things go wrong)" >&2
  fi
fi
export VT_IN_NETNS="${VT_IN_NETNS:-0}"
PATH="/usr/bin:${PATH}"

checkpoint=""
if [[ "${1:-}" == --resume ]]; then
  [[ -d "${2:-}" ]] || { echo "[rig] ERROR: --resume: no such folder: '${2:-}' (give the killed test's output folder)" >&2; exit 2; }
  out="$(cd "$2" && pwd)"
  checkpoint="${out}/results.h5.checkpoint.h5"
  [[ -f "${checkpoint}" ]] || { echo "[rig] ERROR: --resume: no checkpoint ${checkpoint} (the test finished, or it was killed before its first checkpoint: run it again)" >&2; exit 2; }
  protocol="$(/usr/bin/python3 -c 'import h5py, sys; print(h5py.File(sys.argv[1], "r")["checkpoint"].attrs["scene_path"])' "${checkpoint}" 2>/dev/null)" ||
    { echo "[rig] ERROR: --resume: ${checkpoint}: not a readable checkpoint" >&2; exit 2; }
  [[ -f "${protocol}" ]] || { echo "[rig] ERROR: --resume: the checkpoint's protocol ${protocol} is gone" >&2; exit 2; }
  /usr/bin/python3 -c '
import h5py, sys
text = h5py.File(sys.argv[1], "r")["checkpoint"].attrs["scene_text"]
text = text.decode() if isinstance(text, bytes) else text
sys.exit(0 if open(sys.argv[2]).read() == text else 1)' "${checkpoint}" "${protocol}" ||
    { echo "[rig] ERROR: --resume: ${protocol}: changed since the checkpoint (the resumed test would not be the test that was run; start it again instead)" >&2; exit 2; }
else
  protocol="$(realpath "${1:-config/protocols/drained_100kPa_adaptive.yaml}")"
  [[ -f "${protocol}" ]] || { echo "[rig] ERROR: protocol: no such file: ${protocol}" >&2; exit 2; }
  out="$(mkdir -p "${OUT:-output/default}" && cd "${OUT:-output/default}" && pwd)"
fi
servo_node="${SERVO_NODE:-servo_controller_node}"
bag_prefix="rig"
if [[ -n "${checkpoint}" ]]; then
  # Keep what the killed run recorded: its open bags reindexed (rosbag
  # reindex writes a backup *.orig.active, removed once it succeeded) and
  # closed; the resumed run records into the next free rig_rN prefix.
  for b in "${out}"/rig*.bag.active; do
    [[ -e "${b}" ]] || continue
    if (set +u; source build/devel/setup.bash >/dev/null 2>&1; rosbag reindex -q -f "${b}") >/dev/null 2>&1; then
      mv -f "${b}" "${b%.active}"
      rm -f "${b%.bag.active}.orig.bag.active" "${b%.active}.orig.active"
      echo "[rig] kept the killed run's bag ${b%.active} (reindexed)"
    else
      echo "[rig] warning: rosbag reindex ${b} failed; left as it is" >&2
    fi
  done
  n=1
  while compgen -G "${out}/rig_r${n}_*.bag*" >/dev/null; do n=$((n + 1)); done
  bag_prefix="rig_r${n}"
  rm -rf "${out}/plots" "${out}/specimen_section.png"
  echo "[rig] resuming ${protocol} from ${checkpoint}"
else
  rm -rf "${out}"/rig_*.bag "${out}"/rig_*.bag.active "${out}/plots" "${out}/summary.json" "${out}/results.h5" \
    "${out}/results.h5.checkpoint.h5" "${out}/specimen_section.png"
fi

export PATH
# Rig settings that must match the protocol (control.interval, control.servo).
read -r interval gain max_rate strategy < <(/usr/bin/python3 - "${protocol}" <<'EOF'
import sys, yaml
doc = yaml.safe_load(open(sys.argv[1])) or {}
c = doc.get("control") or {}
s = c.get("servo") or {}
print(int(c.get("interval", 1)), float(s.get("gain", 0.5)), float(s.get("max_dimensionless_rate", 1e-4)),
      s.get("strategy", "proportional"))
EOF
)

port="$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
export ROS_MASTER_URI="http://127.0.0.1:${port}" ROS_IP=127.0.0.1 ROS_HOME="${out}/ros_home"
unset ROS_HOSTNAME
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"
mkdir -p "${ROS_HOME}"
set +u
# shellcheck disable=SC1091
source build/devel/setup.bash
set -u
PATH="/usr/bin:${PATH}"

# Process supervision. Every process runs in a session of its own (setsid),
# so a Ctrl-C in the terminal reaches this script only, which decides: the
# first SIGINT/SIGTERM makes the client cancel the goal (verdict
# "preempted"), then the rig is stopped gently (bag closed) and the plots
# made; a second one kills every process started here at once.
pids=()         # session leaders started here: roscore, roslaunch, the client
core_pid="" launch_pid="" client_pid=""
interrupts=0
tree() {  # a process and its descendants (roslaunch starts each node in a session of its own)
  local p="$1" c
  echo "${p}"
  for c in $(ps -o pid= --ppid "${p}" 2>/dev/null); do tree "${c}"; done
}
all_started() { local p; for p in "${pids[@]}"; do tree "${p}"; done; }
stop_now() {
  local all
  all="$(all_started)"
  # shellcheck disable=SC2086
  [[ -n "${all}" ]] && kill -KILL ${all} 2>/dev/null || true
  pids=()
  return 0
}
wait_gone() {  # wait_gone SECONDS PID...: true once every PID has exited
  local limit="$1" p alive
  shift
  for _ in $(seq 1 $((limit * 10))); do
    alive=0
    for p in "$@"; do kill -0 "${p}" 2>/dev/null && alive=1; done
    ((alive)) || return 0
    sleep 0.1
  done
  return 1
}
cleanup() {  # gently: roslaunch stops the rig (the recorder closes its bag), then the master
  ((${#pids[@]})) || return 0
  local all
  all="$(all_started)"
  [[ -n "${client_pid}" ]] && kill -INT "${client_pid}" 2>/dev/null || true
  [[ -n "${launch_pid}" ]] && kill -INT "${launch_pid}" 2>/dev/null || true
  [[ -n "${core_pid}" ]] && kill -INT "${core_pid}" 2>/dev/null || true
  # roslaunch gives each node 4 s after SIGINT, then SIGTERM and 2 s more.
  wait_gone 8 ${launch_pid} ${core_pid} || true
  # shellcheck disable=SC2086
  [[ -n "${all}" ]] && kill -KILL ${all} 2>/dev/null || true
  pids=()
  return 0
}
stop_recorder() {  # the recorder alone, first: its last bag is closed before the rest of the rig stops
  # With the nodelet rig the recorder's process is the nodelet's loader; on
  # SIGINT it asks rig_manager to unload the nodelet, which closes the bag,
  # and exits. Stopped together with the others, the manager unloads all its
  # nodelets at once and has aborted at exit (boost::lock_error, once in a
  # test suite on 2026-12-05) before the recorder's bag was closed.
  [[ "${record}" != 0 && -n "${launch_pid}" ]] || return 0
  local p rec=()
  for p in $(tree "${launch_pid}"); do
    tr '\0' ' ' <"/proc/${p}/cmdline" 2>/dev/null | grep -q -- "__name:=bag_recorder " && rec+=("${p}")
  done
  ((${#rec[@]})) || return 0
  kill -INT "${rec[@]}" 2>/dev/null || true
  wait_gone 10 "${rec[@]}" || echo "[rig] warning: the recorder did not stop within 10 s" >&2
}
on_signal() {
  interrupts=$((interrupts + 1))
  if ((interrupts == 1)) && [[ -n "${client_pid}" ]] && kill -0 "${client_pid}" 2>/dev/null; then
    echo "[rig] interrupted: cancelling the test (again to stop at once)" >&2
    kill -INT "${client_pid}" 2>/dev/null || true
    return 0
  fi
  echo "[rig] interrupted: stopping every process at once" >&2
  stop_now
  exit 130
}
trap cleanup EXIT
trap on_signal INT TERM
nap() { sleep "$1" & wait $! 2>/dev/null || true; }  # a sleep that a signal cuts short
wait_for() {  # wait_for PID: its exit code (a trapped signal does not end the wait)
  local r
  while :; do
    wait "$1" 2>/dev/null && r=0 || r=$?
    kill -0 "$1" 2>/dev/null || return "${r}"
  done
}

echo "[rig] master http://127.0.0.1:${port}, output ${out}$( ((VT_IN_NETNS)) && echo ', own network namespace (loopback only)')"
setsid roscore -p "${port}" >"${ROS_HOME}/roscore.log" 2>&1 </dev/null &
core_pid=$!
pids+=("${core_pid}")
for _ in $(seq 1 100); do rosparam list >/dev/null 2>&1 && break; nap 0.2; done
rosparam list >/dev/null 2>&1 || { echo "[rig] ERROR: roscore did not come up (${ROS_HOME}/roscore.log)" >&2; exit 2; }

echo "[rig] starting the rig: ${servo_node}, publish_every ${interval}, servo ${strategy} gain ${gain}"
record="${RECORD:-1}"
record_args=()
# The recorder (bag_recorder, ros/bag_recorder.h; not `rosbag record -a`,
# whose 100-message queues drop messages when it is starved of CPU for 100
# control ticks) runs inside the rig's process as a nodelet: the rig's own
# topics reach it as pointers, so recording costs the lockstep loop nothing.
[[ "${record}" != 0 ]] && record_args=(record:="${out}/${bag_prefix}")
# Specimen snapshots (dem_node ~snapshot_dir): load, stage ends, output.snapshot_interval.
snapshot_args=()
[[ "${SNAPSHOTS:-1}" != 0 ]] && snapshot_args=(snapshot_dir:="${out}/specimen")
# Bounded shutdown: a node that ignores SIGINT gets SIGTERM after 4 s, then SIGKILL.
# shellcheck disable=SC2086
setsid roslaunch --sigint-timeout 4 --sigterm-timeout 2 virtual_triaxial protocol_rig.launch \
  sample:="${protocol}" output_dir:="${out}" \
  publish_every:="${interval}" servo_gain:="${gain}" servo_max_dimensionless_rate:="${max_rate}" \
  servo_strategy:="${strategy}" servo_node:="${servo_node}" "${snapshot_args[@]}" \
  "${record_args[@]}" ${RIG_ARGS:-} \
  >"${ROS_HOME}/rig.log" 2>&1 </dev/null &
launch_pid=$!
pids+=("${launch_pid}")
if [[ "${record}" != 0 ]]; then
  # The test starts once the recorder has subscribed (it opens its file last)
  # and has polled the master once for the other topics.
  for _ in $(seq 1 150); do
    [[ -f "${out}/${bag_prefix}_0.bag.active" ]] && break
    kill -0 "${launch_pid}" 2>/dev/null || break
    nap 0.2
  done
  [[ -f "${out}/${bag_prefix}_0.bag.active" ]] || echo "[rig] warning: the recorder did not start (${ROS_HOME}/rig.log)" >&2
  nap 0.5
fi

# What died, from roslaunch's log ("[servo-3] process has died [pid 12, exit code -9, ...").
died_nodes() {
  sed 's/\x1b\[[0-9;]*m//g' "${ROS_HOME}/rig.log" 2>/dev/null |
    grep -o '\[[^]]*\] process has died \[pid [0-9]*, exit code [-0-9]*' |
    sed -E 's/^\[(.*)-[0-9]+\] process has died \[pid ([0-9]+), exit code ([-0-9]+)/\1 (pid \2, exit code \3)/' |
    paste -sd ';' - | sed 's/;/; /g' || true
}

echo "[rig] running ${protocol}"
rc=0
client_out="${ROS_HOME}/client.out"
client_args=("${protocol}")
[[ -n "${checkpoint}" ]] && client_args=(--resume "${checkpoint}")
# The file exists before tail opens it: the background job's own
# redirection may run after tail starts, and tail then gives up on a missing
# file and the client's progress never reaches the console.
: >"${client_out}"
setsid scripts/run_test_client.py "${client_args[@]}" --out "${out}" >>"${client_out}" 2>&1 </dev/null &
client_pid=$!
pids+=("${client_pid}")
tail -n +1 -f --pid="${client_pid}" "${client_out}" &
tail_pid=$!
# Supervise: the client ends the test (its result, or its server died).
# roslaunch or the master ending, or a node dying that the protocol node
# does not turn into a verdict within RIG_GRACE seconds, end it here.
rig_down="" t_died=""
while kill -0 "${client_pid}" 2>/dev/null; do
  if [[ -z "${rig_down}" ]]; then
    kill -0 "${launch_pid}" 2>/dev/null || rig_down="roslaunch (the rig) exited"
    kill -0 "${core_pid}" 2>/dev/null || rig_down="roscore (the ROS master) exited"
    [[ -n "${rig_down}" && -z "${t_died}" ]] && t_died=${SECONDS}
  fi
  if [[ -z "${t_died}" && -n "$(died_nodes)" ]]; then
    t_died=${SECONDS}
    echo "[rig] died: $(died_nodes)" >&2
  fi
  if [[ -n "${t_died}" ]] && ((SECONDS - t_died > ${RIG_GRACE:-15})); then
    echo "[rig] no verdict ${RIG_GRACE:-15} s after that; stopping the client" >&2
    kill -INT "${client_pid}" 2>/dev/null || true
    wait_gone 10 "${client_pid}" || kill -KILL "${client_pid}" 2>/dev/null || true
    break
  fi
  nap 0.3
done
wait_for "${client_pid}" && rc=0 || rc=$?
wait_for "${tail_pid}" || true
client_pid=""
((interrupts)) && rc=130
dead="$(died_nodes)"
if ((rc == 3)) || { ((rc != 0 && rc != 1 && rc != 130)) && [[ -n "${dead}${rig_down}" ]]; }; then
  # The rig (or a node of it) died without a verdict: say what died.
  why="$(tail -n 1 "${client_out}" | /usr/bin/python3 -c 'import json,sys; print(json.loads(sys.stdin.read()).get("message",""))' 2>/dev/null || true)"
  msg="died: ${dead:-${rig_down:-unknown}}${why:+ (${why})}"
  echo "[rig] ${msg}" >&2
  /usr/bin/python3 -c '
import json, os, sys
path, msg = sys.argv[1], sys.argv[2]
try:
    doc = json.load(open(path))
except (OSError, ValueError):
    doc = {}
doc.update({"verdict": "interrupted", "failure": msg})
with open(path + ".tmp", "w") as f:
    f.write(json.dumps(doc) + "\n")
os.replace(path + ".tmp", path)
' "${out}/summary.json" "${msg}" || echo "[rig] warning: cannot write ${out}/summary.json" >&2
  rc=3
fi
# The results file is complete once the client has the result: its plots
# are made while the rig stops.
plot_pids=()
plots="${PLOTS:-1}"
if [[ "${plots}" != 0 && -f "${out}/results.h5" ]]; then
  /usr/bin/python3 scripts/plot_results.py "${out}/results.h5" &
  plot_pids+=($!)
fi
nap 0.5  # let the recorder write the last messages
t_stop=${SECONDS}
stop_recorder
cleanup
echo "[rig] rig stopped ($((SECONDS - t_stop)) s)$([[ "${plots}" != 0 ]] && echo '; plots')"
if [[ "${plots}" != 0 && "${record}" != 0 ]] && compgen -G "${out}/rig*.bag" >/dev/null; then
  /usr/bin/python3 scripts/bag_report.py "${out}"/rig*.bag --out "${out}/plots" &
  plot_pids+=($!)
fi
if [[ "${plots}" != 0 && "${SNAPSHOTS:-1}" != 0 && -f "${out}/specimen/snapshots.csv" ]]; then
  /usr/bin/python3 scripts/specimen_section.py "${out}/specimen" --out "${out}/specimen_section.png" &
  plot_pids+=($!)
fi
for p in "${plot_pids[@]}"; do
  wait_for "${p}" || echo "[rig] warning: a plot tool failed" >&2
done
echo "[rig] output folder: ${out} (exit code ${rc})"
[[ -f "${out}/summary.json" ]] && cat "${out}/summary.json"
exit "${rc}"
