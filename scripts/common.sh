# Shared by scripts/demo, scripts/test, scripts/bench, scripts/simulate and scripts/evaluate.
# Installs the Debian packages the project needs (only when something is missing), makes a catkin
# workspace under build/ that links to this repository, and builds it in Release.
set -euo pipefail

SCL_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SCL_WS="${SCL_WS:-$SCL_ROOT/build/ws}"
# Debian's ROS tools need Debian's python3, not a pyenv one earlier on PATH.
export PATH="/usr/bin:/bin:$PATH"

SCL_PACKAGES=(
  build-essential cmake pkg-config catkin python3-catkin-pkg
  ros-base-dev libnodeletlib-dev libnodelet-dev libnodeletlib-tools rosbash
  libpcl-conversions-dev libpcl-dev libflann-dev libeigen3-dev liblz4-dev
  libtf2-ros-dev libtf2-eigen-dev libvisualization-msgs-dev libnav-msgs-dev libgeometry-msgs-dev
  libstd-msgs-dev libsensor-msgs-dev libdiagnostic-updater-dev
  ros-message-generation ros-message-runtime librostest-dev python3-rostest python3-roslaunch
  python3-rosbag librosbag-dev python3-rosmaster rosout libgtest-dev
  python3-numpy python3-matplotlib python3-yaml libyaml-cpp-dev rviz
)
# Only the demo needs these (RViz under a virtual display, and a screenshot of it).
SCL_DEMO_PACKAGES=(xvfb xauth x11-apps imagemagick python3-rospy python3-geometry-msgs python3-visualization-msgs python3-std-msgs python3-tf2-ros)

scl_log() { echo "[scan_context_loop] $*" >&2; }

scl_install_deps() {
  local missing=()
  local pkg
  for pkg in "${SCL_PACKAGES[@]}" "$@"; do
    if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$pkg")
    fi
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  scl_log "installing ${#missing[@]} Debian packages: ${missing[*]}"
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# The workspace's package folder holds a link to each top-level entry of the repository except build/
# (a link to the whole repository would contain the workspace itself, and ROS tools that walk the
# package with links followed would never finish).
scl_make_workspace() {
  local pkg="$SCL_WS/src/scan_context_loop"
  mkdir -p "$SCL_WS/src"
  if [ -L "$pkg" ]; then rm -f "$pkg"; fi
  mkdir -p "$pkg"
  local entry name
  for entry in "$SCL_ROOT"/* "$SCL_ROOT"/.ci; do
    name="$(basename "$entry")"
    [ "$name" = "build" ] && continue
    [ -e "$entry" ] || continue
    [ -L "$pkg/$name" ] || ln -s "$entry" "$pkg/$name"
  done
  # Drop links to entries that no longer exist.
  for entry in "$pkg"/*; do
    [ -L "$entry" ] && [ ! -e "$entry" ] && rm -f "$entry"
  done
  return 0
}

scl_build() {
  scl_install_deps
  scl_make_workspace
  scl_log "building in $SCL_WS (Release)"
  (
    cd "$SCL_WS"
    catkin_make -DCMAKE_BUILD_TYPE=Release -DCATKIN_ENABLE_TESTING=ON "$@" >"$SCL_WS/build.log" 2>&1 || {
      tail -n 60 "$SCL_WS/build.log" >&2
      scl_log "build failed, full log: $SCL_WS/build.log"
      exit 1
    }
  )
}

# Sources the workspace so rosrun/roslaunch/rostest find the package.
scl_source_ws() {
  set +u
  # shellcheck disable=SC1091
  source "$SCL_WS/devel/setup.bash"
  set -u
}

scl_bin() { echo "$SCL_WS/devel/lib/scan_context_loop/$1"; }

SCL_SHARED_DATA="${SCL_SHARED_DATA:-$SCL_ROOT/../shared/data}"
export SCL_SHARED_DATA
