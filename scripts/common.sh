# Shared by scripts/demo, scripts/dev/test, scripts/measure/bench, scripts/simulate and scripts/evaluate.
# Installs the Debian packages the project needs (only when something is missing), makes a catkin
# workspace under build/ that links to this repository's packages, and builds it in Release.
set -euo pipefail

SCL_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SCL_WS="${SCL_WS:-$SCL_ROOT/build/ws}"
# Debian's ROS tools need Debian's python3, not a pyenv one earlier on PATH.
export PATH="/usr/bin:/bin:$PATH"
# No __pycache__ in the repository: the checks' Python (test/common/check_report.py, imported by the
# install-space check) would otherwise add one under test/, which counts as a change to the build's
# inputs (scl_build_fresh), and the next scl_build would run catkin_make again for nothing.
export PYTHONDONTWRITEBYTECODE=1

# What the build and the tests need outside ROS (the same names on Debian 12 and Ubuntu 20.04).
SCL_TOOL_PACKAGES=(
  build-essential cmake pkg-config ccache libpcl-dev libflann-dev libeigen3-dev liblz4-dev libceres-dev
  libgtest-dev python3-numpy python3-matplotlib python3-yaml libyaml-cpp-dev
)
# ROS 1 as Debian packages it (Debian 12's own ROS): the tools, the libraries, RViz, and the command-line
# tools a user talks to the node with, with the Python messages they load.
SCL_DEBIAN_ROS_PACKAGES=(
  catkin python3-catkin-pkg
  ros-base-dev libnodeletlib-dev libnodelet-dev libnodeletlib-tools rosbash
  libpcl-conversions-dev
  libtf2-ros-dev libtf2-eigen-dev libvisualization-msgs-dev libnav-msgs-dev libgeometry-msgs-dev
  libstd-msgs-dev libsensor-msgs-dev libdiagnostic-updater-dev
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure libstd-srvs-dev
  ros-message-generation ros-message-runtime librostest-dev python3-rostest python3-roslaunch
  python3-rosbag librosbag-dev python3-rosmaster rosout rviz
  python3-rosservice python3-rostopic python3-rosnode python3-std-srvs python3-diagnostic-msgs
  python3-rospy python3-geometry-msgs python3-visualization-msgs python3-std-msgs python3-tf2-ros
  python3-nav-msgs python3-sensor-msgs
)
SCL_PACKAGES=("${SCL_TOOL_PACKAGES[@]}" "${SCL_DEBIAN_ROS_PACKAGES[@]}")
# Only the demo needs these (RViz under a virtual display, and a screenshot of it).
SCL_DEMO_PACKAGES=(xvfb xauth x11-apps imagemagick)

# A ros.org ROS 1 (packages.ros.org's Noetic in /opt/ros/noetic, or SCL_ROS_ROOT): ROS is taken from
# there, the package's ROS dependencies are installed through rosdep from package.xml (ros-noetic-*
# packages), and only what lies outside ROS by its Ubuntu name. Debian's ROS packages would put a second
# ROS beside it, whose Python catkin packages conflict with ros.org's. SCL_DRY_RUN=1 prints the install
# commands instead of running them.
SCL_ROS_ROOT="${SCL_ROS_ROOT:-/opt/ros/noetic}"
scl_ros_org() { [ -f "$SCL_ROS_ROOT/setup.bash" ]; }
if scl_ros_org; then
  set +u
  # shellcheck disable=SC1091
  source "$SCL_ROS_ROOT/setup.bash"
  set -u
fi

scl_log() { echo "[scan_context_loop] $*" >&2; }

# Compiler caching: every CMake build the scripts make (the workspace, catkin build's, the sanitizers',
# the fuzzers') compiles through ccache (CMake reads CMAKE_<LANG>_COMPILER_LAUNCHER from the environment
# when it first configures a build folder). Paths under the repository are hashed relative to it
# (CCACHE_BASEDIR, CCACHE_NOHASHDIR), so a fresh clone in another folder of a machine that built before
# reuses its objects. The cache is the user's (~/.cache/ccache unless CCACHE_DIR says otherwise).
# Depend mode (CCACHE_DEPEND): on a miss, ccache takes the headers a unit read from the compiler's own
# dependency file (CMake passes -MD) instead of a preprocessor pass of its own over every header first.
# CMake reads the launcher from the environment only when it configures a build folder for the first
# time, so the scripts' builds also pass it as SCL_CCACHE_ARGS: a folder configured before keeps using it.
SCL_CCACHE_ARGS=()
scl_use_ccache() {
  command -v ccache >/dev/null 2>&1 || return 0
  export CCACHE_BASEDIR="$SCL_ROOT" CCACHE_NOHASHDIR=true CCACHE_DEPEND=true
  export CCACHE_MAXSIZE="${CCACHE_MAXSIZE:-10G}"
  export CMAKE_CXX_COMPILER_LAUNCHER=ccache CMAKE_C_COMPILER_LAUNCHER=ccache
  SCL_CCACHE_ARGS=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
}

# Installs what is missing, then turns on the compiler cache.
scl_install_deps() {
  scl_install_missing "$@"
  scl_use_ccache
}

# scl_run CMD...: runs it (as root: sudo when needed), or with SCL_DRY_RUN=1 prints it.
scl_run() {
  if [ "${SCL_DRY_RUN:-0}" = 1 ]; then
    echo "would run: $*"
    return 0
  fi
  if [ "$(id -u)" -ne 0 ] && [ "$1" != rosdep ]; then set -- sudo "$@"; fi
  "$@"
}

# The packages of the list that dpkg does not have installed.
scl_missing_packages() {
  local pkg installed
  # One dpkg-query for all of them (one call per package took seconds).
  installed=$'\n'"$(dpkg-query -W -f='${Package} ${Status}\n' "$@" 2>/dev/null || true)"$'\n'
  for pkg in "$@"; do
    [[ "$installed" == *$'\n'"$pkg install ok installed"$'\n'* ]] || echo "$pkg"
  done
}

scl_apt_install() {
  [ $# -eq 0 ] && return 0
  scl_log "installing $# packages: $*"
  scl_run apt-get update -qq
  if [ "${SCL_DRY_RUN:-0}" = 1 ]; then
    scl_run apt-get install -y -qq --no-install-recommends "$@"
  else
    scl_run env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" >/dev/null
  fi
}

scl_install_missing() {
  if scl_ros_org; then
    scl_install_ros_org "$@"
    return
  fi
  local missing=()
  mapfile -t missing < <(scl_missing_packages "${SCL_PACKAGES[@]}" "$@")
  scl_apt_install "${missing[@]}"
}

# On a ros.org ROS: the tools outside ROS by name (the Debian ROS names asked for are left to rosdep's
# ros-noetic-* packages), then rosdep for package.xml's keys unless `rosdep check` finds them all. The
# demo's RViz is a conditional key (SCAN_CONTEXT_LOOP_DEMO=1). package.xml is read from a copy: rosdep
# would also find the workspaces' links to it under build/ and refuse the package twice.
scl_install_ros_org() {
  local wanted=() pkg missing=()
  for pkg in "${SCL_TOOL_PACKAGES[@]}" "$@"; do
    [[ " ${SCL_DEBIAN_ROS_PACKAGES[*]} " == *" $pkg "* ]] || wanted+=("$pkg")
  done
  command -v rosdep >/dev/null 2>&1 || wanted+=(python3-rosdep)
  mapfile -t missing < <(scl_missing_packages "${wanted[@]}")
  scl_apt_install "${missing[@]}"
  if [ ! -d /etc/ros/rosdep/sources.list.d ]; then
    scl_run rosdep init
  fi
  [ -d "$HOME/.ros/rosdep/sources.cache" ] || scl_run rosdep update --rosdistro noetic
  local manifest
  manifest="$(mktemp -d)"
  cp "$SCL_ROOT/package.xml" "$manifest/"
  export SCAN_CONTEXT_LOOP_DEMO=1 ROS_DISTRO="${ROS_DISTRO:-noetic}"
  if [ "${SCL_DRY_RUN:-0}" = 1 ] || ! rosdep check --from-paths "$manifest" --ignore-src -q >/dev/null 2>&1; then
    scl_log "installing package.xml's dependencies through rosdep ($SCL_ROS_ROOT)"
    scl_run rosdep install --from-paths "$manifest" --ignore-src --rosdistro "$ROS_DISTRO" -y
  fi
  rm -rf "$manifest"
}

# The repository is one catkin package (package.xml at its root). A workspace's src/scan_context_loop is
# a folder of links to the repository's entries, all but build/ (where the workspaces are) and the
# dot-files: a link to the root itself would put the workspace inside the package, and roslaunch, which
# looks for a launch file by walking the package's folder through its links, would walk round that
# loop forever.
scl_link_package() {
  local ws="$1" dir="$1/src/scan_context_loop" entry name
  mkdir -p "$ws/src"
  # A workspace made when the repository held several packages links to those too; one made before
  # this folder of links holds a single link to the root.
  for entry in "$ws"/src/*; do
    case "$(basename "$entry")" in
      scan_context_loop|CMakeLists.txt) ;;
      *) rm -rf "$entry" ;;
    esac
  done
  [ -L "$dir" ] && rm -f "$dir"
  mkdir -p "$dir"
  for entry in "$dir"/*; do  # entries the repository no longer has
    [ -L "$entry" ] && [ ! -e "$SCL_ROOT/$(basename "$entry")" ] && rm -f "$entry"
  done
  for entry in "$SCL_ROOT"/*; do
    name="$(basename "$entry")"
    [ "$name" = build ] && continue
    [ "$(readlink "$dir/$name" 2>/dev/null)" = "$entry" ] || ln -sfn "$entry" "$dir/$name"
  done
  return 0
}

scl_make_workspace() {
  scl_link_package "$SCL_WS"
}

# What the build reads from the repository: a change to any of these (a file's or a folder's mtime, so
# added and removed files count too) makes the next scl_build run catkin_make.
SCL_BUILD_INPUTS=(CMakeLists.txt cmake package.xml nodelets.xml include src tools test msg srv cfg launch config sim)

# True when TARGET ("all" for the default target) was built after the last change to the inputs: its
# stamp (or, for a tool, the "all" stamp) is newer than every input, the workspace is configured, and a
# tool's binary exists.
scl_build_fresh() {
  local target="$1" stamp inputs=() entry
  [ -f "$SCL_WS/build/Makefile" ] && [ -f "$SCL_WS/devel/setup.bash" ] || return 1
  case "$target" in
    all|tests|run_tests) ;;
    *) [ -x "$(scl_bin "$target")" ] || return 1 ;;
  esac
  for entry in "${SCL_BUILD_INPUTS[@]}"; do
    [ -e "$SCL_ROOT/$entry" ] && inputs+=("$SCL_ROOT/$entry")
  done
  for stamp in "$SCL_WS/.scl_built_$target" "$SCL_WS/.scl_built_all"; do
    [ "$stamp" = "$SCL_WS/.scl_built_all" ] && [ "$target" = tests ] && continue
    [ -f "$stamp" ] || continue
    if [ -z "$(find "${inputs[@]}" -newer "$stamp" -print -quit 2>/dev/null)" ]; then return 0; fi
  done
  return 1
}

# Extra CMake arguments for scl_build (scripts/dev/test --sanitize sets the build type and the sanitizer
# flags here, with SCL_WS pointing at a workspace of its own); empty for a normal Release build.
SCL_CMAKE_ARGS=(-DCMAKE_BUILD_TYPE=Release -DSCL_TEST_INSTALL_SPACE=ON)
SCL_BUILD_KIND="Release"

# Parallel jobs of the builds (make -j): a job per core. catkin_make's own default adds make's -l (no new
# job while the load average exceeds the number of cores), which under the build's own two compilers
# often holds a 2-core machine to one.
SCL_JOBS="${SCL_JOBS:-$(nproc)}"

# scl_catkin_make ARG...: catkin_make in the workspace with the build's CMake arguments. catkin_make runs
# CMake again whenever its arguments differ from the previous call's, so a bare `catkin_make install`
# would configure the workspace anew, and the next build again.
scl_catkin_make() {
  (cd "$SCL_WS" && catkin_make "${SCL_CMAKE_ARGS[@]}" "${SCL_CCACHE_ARGS[@]}" -DCATKIN_ENABLE_TESTING=ON "$@")
}

# scl_build [TARGET...]: builds the targets (default: all) in Release unless nothing they depend on
# changed since they were last built (scl_build_fresh); SCL_FORCE_BUILD=1 always runs catkin_make.
scl_build() {
  scl_install_deps
  scl_make_workspace
  local targets=("$@") target stale=0
  [ ${#targets[@]} -eq 0 ] && targets=(all)
  if [ "${SCL_FORCE_BUILD:-0}" = 1 ]; then
    stale=1
  else
    for target in "${targets[@]}"; do
      scl_build_fresh "$target" || { stale=1; break; }
    done
  fi
  if [ "$stale" = 0 ]; then
    scl_log "up to date in $SCL_WS (${targets[*]})"
    return 0
  fi
  scl_log "building in $SCL_WS ($SCL_BUILD_KIND): ${targets[*]}"
  # The stamp's time is the build's start, so an edit made during the build still counts as a change.
  local marker="$SCL_WS/.scl_build_started.$$"
  touch "$marker"
  (
    scl_catkin_make -j"$SCL_JOBS" "$@" >"$SCL_WS/build.log" 2>&1 || {
      tail -n 60 "$SCL_WS/build.log" >&2
      scl_log "build failed, full log: $SCL_WS/build.log"
      rm -f "$marker"
      exit 1
    }
  )
  for target in "${targets[@]}"; do
    cp -p "$marker" "$SCL_WS/.scl_built_$target"
  done
  rm -f "$marker"
}

# The demos' processes (scripts/demo, scripts/demo_bag): each started in the background goes into SCL_PIDS,
# and all are stopped when the script exits (scl_private_master sets that up).
SCL_PIDS=()
scl_kill_pids() {
  local pid
  for pid in "${SCL_PIDS[@]}"; do kill "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
}

# scl_private_master LOG: a ROS master of the script's own on a free port (ROS_MASTER_URI exported, so
# nothing else running is disturbed), its output in LOG; returns once it answers. The port is one the
# kernel hands out as free (the tests run several demos side by side: two masters must not share a port).
scl_private_master() {
  local port
  port="$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("localhost", 0)); print(s.getsockname()[1])')"
  export ROS_MASTER_URI="http://localhost:$port"
  trap scl_kill_pids EXIT
  roscore -p "${ROS_MASTER_URI##*:}" >"$1" 2>&1 &
  SCL_PIDS+=($!)
  for _ in $(seq 50); do rosnode list >/dev/null 2>&1 && break; sleep 0.2; done
}

# Sources the workspace so rosrun/roslaunch/rostest find the package.
scl_source_ws() {
  set +u
  # shellcheck disable=SC1091
  source "$SCL_WS/devel/setup.bash"
  set -u
}

# The path of a tool's binary in the workspace's devel space.
scl_bin() {
  echo "$SCL_WS/devel/lib/scan_context_loop/$1"
}

SCL_SHARED_DATA="${SCL_SHARED_DATA:-$SCL_ROOT/../shared/data}"
export SCL_SHARED_DATA
