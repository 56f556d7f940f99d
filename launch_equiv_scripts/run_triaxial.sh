#!/usr/bin/env bash
# The main job: a complete virtual triaxial test on the ROS rig.
#
#   launch_equiv_scripts/run_triaxial.sh [PROTOCOL.yaml]
#   OUT=output/mine SERVO_NODE=py_servo_controller.py launch_equiv_scripts/run_triaxial.sh
#   RECORD=0 ...   no rosbag recording (and no bag plots), e.g. to time the rig alone
#   RIG_ARGS="nodelets:=false ..."   extra protocol_rig.launch arguments
#
# Default protocol: config/protocols/drained_100kPa.yaml (the shipped dense
# 1000-sphere sample, servo consolidation at 100 kPa, drained shear at
# eps' = 1e-5 to 10 % axial strain).
#
# What it does: installs what is missing and builds (lib/ensure_built.sh);
# picks a free master port and binds everything to 127.0.0.1 (ROS 1 has no
# authentication); sets ROS_HOME under the output folder; starts roscore, the
# rig (protocol_rig.launch: dem_node, servo controller, test_protocol_node)
# and the recorder of every topic (bag_recorder, in the rig's process); runs the protocol through the run_test
# action (scripts/run_test_client.py, progress printed); stops every process
# it started (also on Ctrl-C or error); makes the plots. One output folder
# (${OUT:-output/default}) holds:
#   rig_*.bag         every rig topic (split at 512 MB)
#   results.h5        sample-tick time series + summary attributes
#   summary.json      the test summary (also printed last)
#   plots/            bag_report.py: q-eps_a, eps_v-eps_a, q-p, e-log p,
#                     I_mom and kinetic energy; rig_series.csv
#   results_*.png     plot_results.py of results.h5
#   ros_home/         ROS logs of this run
# Exit code: 0 when the test completed, 1 otherwise.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
repo="$(pwd)"

# shellcheck source=SCRIPTDIR/lib/ensure_built.sh
source launch_equiv_scripts/lib/ensure_built.sh
vt_ensure_built all

protocol="$(realpath "${1:-config/protocols/drained_100kPa.yaml}")"
out="$(mkdir -p "${OUT:-output/default}" && cd "${OUT:-output/default}" && pwd)"
servo_node="${SERVO_NODE:-servo_controller_node}"
rm -rf "${out}"/rig_*.bag "${out}"/rig_*.bag.active "${out}/plots" "${out}/summary.json" "${out}/results.h5"

export PATH="/usr/bin:${PATH}"
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

pids=()
cleanup() {
  local p
  for p in "${pids[@]}"; do kill -INT "${p}" 2>/dev/null || true; done
  for _ in $(seq 1 50); do
    local alive=0
    for p in "${pids[@]}"; do kill -0 "${p}" 2>/dev/null && alive=1; done
    ((alive)) || break
    sleep 0.2
  done
  for p in "${pids[@]}"; do kill -TERM "${p}" 2>/dev/null || true; done
  pids=()
}
trap cleanup EXIT
trap 'exit 130' INT TERM

echo "[rig] master http://127.0.0.1:${port}, output ${out}"
roscore -p "${port}" >"${ROS_HOME}/roscore.log" 2>&1 &
pids+=("$!")
for _ in $(seq 1 100); do rosparam list >/dev/null 2>&1 && break; sleep 0.2; done
rosparam list >/dev/null 2>&1 || { echo "[rig] ERROR: roscore did not come up (${ROS_HOME}/roscore.log)" >&2; exit 1; }

echo "[rig] starting the rig: ${servo_node}, publish_every ${interval}, servo ${strategy} gain ${gain}"
record="${RECORD:-1}"
record_args=()
# The recorder (bag_recorder, ros/bag_recorder.h; not `rosbag record -a`,
# whose 100-message queues drop messages when it is starved of CPU for 100
# control ticks) runs inside the rig's process as a nodelet: the rig's own
# topics reach it as pointers, so recording costs the lockstep loop nothing.
[[ "${record}" != 0 ]] && record_args=(record:="${out}/rig")
roslaunch virtual_triaxial protocol_rig.launch sample:="${protocol}" output_dir:="${out}" \
  publish_every:="${interval}" servo_gain:="${gain}" servo_max_dimensionless_rate:="${max_rate}" \
  servo_strategy:="${strategy}" servo_node:="${servo_node}" "${record_args[@]}" ${RIG_ARGS:-} \
  >"${ROS_HOME}/rig.log" 2>&1 &
pids+=("$!")
if [[ "${record}" != 0 ]]; then
  # The test starts once the recorder has subscribed (it opens its file last)
  # and has polled the master once for the other topics.
  for _ in $(seq 1 150); do
    [[ -f "${out}/rig_0.bag.active" ]] && break
    sleep 0.2
  done
  [[ -f "${out}/rig_0.bag.active" ]] || echo "[rig] warning: the recorder did not start (${ROS_HOME}/rig.log)" >&2
  sleep 0.5
fi

echo "[rig] running ${protocol}"
rc=0
scripts/run_test_client.py "${protocol}" --out "${out}" || rc=$?
sleep 1  # let the recorder write the last messages
cleanup

echo "[rig] plots"
if [[ "${record}" != 0 ]]; then
  /usr/bin/python3 scripts/bag_report.py "${out}"/rig*.bag --out "${out}/plots" || echo "[rig] warning: bag_report failed" >&2
fi
if [[ -f "${out}/results.h5" ]]; then
  /usr/bin/python3 scripts/plot_results.py "${out}/results.h5" || echo "[rig] warning: plot_results failed" >&2
fi
echo "[rig] output folder: ${out} (exit code ${rc})"
[[ -f "${out}/summary.json" ]] && cat "${out}/summary.json"
exit "${rc}"
