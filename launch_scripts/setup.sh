#!/usr/bin/env bash
# Installs the Debian packages nadir needs (only the missing ones), then
# configures and builds into build/. Idempotent; quick when nothing changed.
# NADIR_DEBUG_INFO=lines (CI) configures a new build with line-table debug
# information only (see cmake/NadirHelpers.cmake).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

packages=(
  build-essential cmake pkg-config git
  liblcm-dev liblcm-bin liblcm-java
  libeigen3-dev libopencv-dev libyaml-cpp-dev libcli11-dev libexiv2-dev
  libaravis-dev aravis-tools aravis-tools-cli libusb-1.0-0-dev
  libgpiod-dev gpiod
  libgtest-dev libgmock-dev libbenchmark-dev
  openjdk-17-jdk-headless libjchart2d-java xvfb xauth
  iproute2 util-linux python3 python3-matplotlib python3-numpy
  python3-yaml slurm-wlm munge libexiv2-dev
)
# node and npm (node-mavlink, for the MAVLink bridge's tests): Debian's only
# where none is installed -- Debian's npm conflicts with a nodesource nodejs.
command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${#missing[@]} Debian package(s): ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if [ ! -f "$NADIR_BUILD/CMakeCache.txt" ]; then
  cmake -S "$NADIR_ROOT" -B "$NADIR_BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNADIR_MODULES= \
    -DNADIR_DEBUG_INFO="${NADIR_DEBUG_INFO:-full}" >/dev/null
fi
cmake --build "$NADIR_BUILD" -j"$(nproc)" 2>&1 | grep -vE '^\[ *[0-9]+%\] (Building|Linking|Built)' || true
test "${PIPESTATUS[0]}" -eq 0
# node-mavlink from the npm registry: the independent MAVLink implementation
# the MAVLink bridge's codec is tested against (once; tests run without network).
"$NADIR_ROOT/tests/processes/mavlink_bridge/install_node_mavlink.sh" "$NADIR_BUILD" ||
  echo "setup: warning: node-mavlink not installed; nadir_test_mavlink_bridge_node will fail until it is" >&2
echo "setup: built into $NADIR_BUILD"
