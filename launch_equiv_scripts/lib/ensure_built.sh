# shellcheck shell=bash
# launch_equiv_scripts/lib/ensure_built.sh -- sourced by the entry scripts.
#
#   source "<repo>/launch_equiv_scripts/lib/ensure_built.sh"
#   vt_ensure_built [make targets...]      # default targets: all tests
#
# vt_ensure_built does, in order:
#   a) installs the missing Debian packages (apt-get update once, only if
#      something is missing; sudo when not root);
#   b) puts /usr/bin first on PATH (a pyenv python3 lacks the ROS modules);
#   c) configures build/ with the Debian python, only if build/ is not
#      configured yet (creating build/devel/lib/python3/dist-packages first);
#   d) make -C build -j${VT_JOBS:-2} <targets>;
#   e) sources build/devel/setup.bash (with set +u around it).
# When everything is already in place it runs no apt-get and no cmake
# configure; `make` itself re-runs cmake if CMakeLists.txt or a globbed source
# folder changed.
#
# The single steps are functions too: vt_ensure_packages, vt_use_system_path,
# vt_configure, vt_build [targets...], vt_source_devel.
# VT_ROOT is the repository root, VT_BUILD_DIR its build/ folder.

VT_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
VT_BUILD_DIR="${VT_ROOT}/build"

VT_DEB_PACKAGES=(
  ros-base-dev catkin ros-message-generation python3-rospy python3-rosbag
  python3-rostest librostest-dev rosbash ros-std-srvs libhdf5-dev
  libeigen3-dev libyaml-cpp-dev python3-numpy python3-h5py python3-matplotlib
  hdf5-tools libbenchmark-dev googletest libnodeletlib-tools
  # specimen views: RViz markers (dem_node) and the VTK read-back tests
  libvisualization-msgs-dev python3-vtk9
  # process and socket tools the entry scripts and their tests use
  procps iproute2 bc util-linux
  # triax_sweep's Slurm backend: the one-node test cluster (tests/sweep/)
  slurm-wlm munge python3-yaml
  # toolchain (normally present; a bare CI image may lack it)
  cmake make g++
)

vt_log() { echo "[setup] $*" >&2; }

# (a) Debian packages ---------------------------------------------------------
vt_ensure_packages() {
  local missing=() pkg status
  for pkg in "${VT_DEB_PACKAGES[@]}"; do
    status="$(dpkg-query -W -f='${Status}' "${pkg}" 2>/dev/null || true)"
    [[ "${status}" == "install ok installed" ]] || missing+=("${pkg}")
  done
  if ((${#missing[@]} == 0)); then
    vt_log "Debian packages present"
    return 0
  fi
  vt_log "installing ${#missing[@]} missing Debian package(s): ${missing[*]}"
  local sudo=()
  if [[ "$(id -u)" -ne 0 ]]; then
    if command -v sudo >/dev/null 2>&1; then
      sudo=(sudo)
    else
      vt_log "ERROR: not root and no sudo; install by hand: apt-get install ${missing[*]}"
      return 1
    fi
  fi
  # Lock timeout: another apt run (e.g. a background install) may hold the lock.
  local apt_opts=(-y -q -o DPkg::Lock::Timeout=900)
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q \
      -o DPkg::Lock::Timeout=900 >&2 || {
    vt_log "ERROR: apt-get update failed"; return 1; }
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install \
      "${apt_opts[@]}" "${missing[@]}" >&2 || {
    vt_log "ERROR: apt-get install failed"; return 1; }
  vt_log "packages installed"
}

# (b) PATH ----------------------------------------------------------------------
vt_use_system_path() {
  case ":${PATH}:" in
    :/usr/bin:*) ;;   # already first
    *) PATH="/usr/bin:${PATH}" ;;
  esac
  export PATH
}

# (c) configure (only when build/ is not configured) ------------------------------
vt_configure() {
  if [[ -f "${VT_BUILD_DIR}/CMakeCache.txt" && -f "${VT_BUILD_DIR}/Makefile" ]]; then
    vt_log "build/ already configured"
    return 0
  fi
  vt_log "configuring ${VT_BUILD_DIR} (Release, Debian python, testing on)"
  # Must exist before the first configure, or catkin caches an environment
  # without it and Python rostests fail with "No module named ...".
  mkdir -p "${VT_BUILD_DIR}/devel/lib/python3/dist-packages"
  (cd "${VT_ROOT}" && cmake -S . -B build \
      -DCMAKE_BUILD_TYPE=Release \
      -DPYTHON_EXECUTABLE=/usr/bin/python3 \
      -DPython3_EXECUTABLE=/usr/bin/python3 \
      -DCATKIN_ENABLE_TESTING=ON >"${VT_BUILD_DIR}/configure.log" 2>&1) || {
    cat "${VT_BUILD_DIR}/configure.log" >&2
    vt_log "ERROR: cmake configure failed (log: build/configure.log)"
    # Leave no half-configured tree that the next run would mistake for done.
    rm -f "${VT_BUILD_DIR}/CMakeCache.txt"
    return 1
  }
}

# (d) build ------------------------------------------------------------------------
vt_build() {
  local targets=("$@")
  ((${#targets[@]})) || targets=(all tests)
  vt_log "building: ${targets[*]}"
  make -C "${VT_BUILD_DIR}" --no-print-directory -j"${VT_JOBS:-2}" "${targets[@]}" || {
    vt_log "ERROR: build failed (make ${targets[*]})"; return 1; }
}

# (e) ROS environment of the devel space ----------------------------------------------
vt_source_devel() {
  local setup="${VT_BUILD_DIR}/devel/setup.bash"
  if [[ ! -f "${setup}" ]]; then
    vt_log "ERROR: ${setup} missing (configure did not finish?)"
    return 1
  fi
  local had_u=0
  [[ $- == *u* ]] && had_u=1
  set +u
  # shellcheck disable=SC1090
  source "${setup}"
  ((had_u)) && set -u
  # setup.bash may have put /opt-style paths first; keep /usr/bin python first.
  vt_use_system_path
  return 0
}

vt_ensure_built() {
  vt_ensure_packages || return 1
  vt_use_system_path
  vt_configure || return 1
  vt_build "$@" || return 1
  vt_source_devel || return 1
}
