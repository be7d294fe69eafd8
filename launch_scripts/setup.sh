#!/usr/bin/env bash
# Installs the Debian packages nadir needs (only the missing ones), then
# configures and builds into build/. Idempotent; quick when nothing changed.
#
# Usage: setup.sh [--demo | --tests]
#   (none)   every program (processes and tools), not the tests
#   --demo   only what the demo runs: the simulator, the estimator processes,
#            nadir_log and nadir_eval, and only the packages they need
#   --tests  every program, the test suites, the benchmarks and the study
#            programs, and the packages the tests use (GoogleTest, Google
#            Benchmark, Slurm, Java for lcm-spy, node-mavlink, MkDocs,
#            Chromium, Foxglove's npm client and MCAP reader)
# A new build is configured for Ninja (every object of the chosen targets
# compiles as soon as its inputs are there: both cores stay busy) with
# line-table debug information (-g1: backtraces and sanitizer reports with
# file:line, about a third less compile time than -g); NADIR_DEBUG_INFO=full
# configures a new build with full debug information (see
# cmake/NadirHelpers.cmake).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

scope=programs
case "${1:-}" in
  "") ;;
  --demo) scope=demo ;;
  --tests) scope=tests ;;
  -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "setup: error: unknown option $1 (--demo, --tests)" >&2; exit 2 ;;
esac

# What the demo builds and runs: compilers, LCM, Eigen, OpenCV, yaml-cpp,
# CLI11, GeographicLib (every geodetic conversion), the camera and GPIO
# libraries the configure step looks for, the network namespace tools and
# matplotlib for the report's plots.
packages=(
  build-essential cmake ninja-build pkg-config git
  liblcm-dev liblcm-bin
  libeigen3-dev libopencv-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libgeographiclib-dev
  libaravis-dev libusb-1.0-0-dev libgpiod-dev
  iproute2 util-linux python3 python3-matplotlib python3-numpy
)
if [ "$scope" != demo ]; then
  # The other programs and their tools: photo import (exiv2), lcm-spy (Java,
  # jchart2d, Xvfb for a headless check), the Aravis fake camera, gpiod,
  # campaigns on Slurm, the tests and benchmarks, the documentation site,
  # systemd-analyze (the vehicle's units are verified by the tests), the
  # Foxglove bridge (websocketpp on Boost.Asio), headless Chromium (the
  # HTML report's test and screenshot), and GDAL (nadir_map: GeoTIFF reference
  # maps, orthophoto + DEM, in any CRS).
  packages+=(
    liblcm-java libexiv2-dev libgdal-dev aravis-tools aravis-tools-cli gpiod
    libwebsocketpp-dev libboost-dev chromium
    libgtest-dev libgmock-dev libbenchmark-dev
    openjdk-17-jdk-headless libjchart2d-java xvfb xauth
    python3-yaml slurm-wlm munge mkdocs systemd
  )
  # node and npm (node-mavlink, for the MAVLink bridge's tests): Debian's only
  # where none is installed -- Debian's npm conflicts with a nodesource nodejs.
  command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)
fi
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

# The test suites and benchmarks are configured once the tests are asked for;
# a build configured for them stays so (building the demo's targets from it
# still compiles only those).
configure=()
# Packages installed since the last configure (e.g. Java after the demo's
# setup) are found by configuring again.
reconfigure=$((${#missing[@]} > 0))
[ -f "$NADIR_BUILD/CMakeCache.txt" ] ||
  configure=(-G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNADIR_MODULES= -DNADIR_DEBUG_INFO="${NADIR_DEBUG_INFO:-lines}"
             -DNADIR_BUILD_TESTS=OFF)
if [ "$scope" = tests ] && ! grep -qxF "NADIR_BUILD_TESTS:BOOL=ON" "$NADIR_BUILD/CMakeCache.txt" 2>/dev/null; then
  configure+=(-DNADIR_BUILD_TESTS=ON)
fi
if ((${#configure[@]} || reconfigure)); then
  cmake -S "$NADIR_ROOT" -B "$NADIR_BUILD" "${configure[@]}" >/dev/null
fi
case "$scope" in
  demo) targets=(--target nadir_demo_programs) ;;
  programs) targets=(--target nadir_programs) ;;
  tests) targets=() ;;  # all
esac
echo "setup: building ${scope} into $NADIR_BUILD"
cmake --build "$NADIR_BUILD" -j"$(nproc)" "${targets[@]}" 2>&1 |
  { grep -vE '^\[ *[0-9]+(%\]|/[0-9]+\]) (Building|Linking|Built)' || true; }  # pipefail: a failed build stops here
if [ "$scope" = tests ]; then
  # node-mavlink from the npm registry: the independent MAVLink implementation
  # the MAVLink bridge's codec is tested against (once; tests run without network).
  "$NADIR_ROOT/tests/processes/mavlink_bridge/install_node_mavlink.sh" "$NADIR_BUILD" ||
    echo "setup: warning: node-mavlink not installed; nadir_test_mavlink_bridge_node will fail until it is" >&2
  # Foxglove's own WebSocket client, an independent MCAP reader and a JSON
  # Schema validator, for nadir_foxglove's and the MCAP export's tests.
  "$NADIR_ROOT/tests/processes/foxglove/install_node_foxglove.sh" "$NADIR_BUILD" ||
    echo "setup: warning: the Foxglove npm packages are not installed; the foxglove tests will fail until they are" >&2
fi
echo "setup: built into $NADIR_BUILD"
