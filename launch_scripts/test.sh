#!/usr/bin/env bash
# Sets up, then runs every test suite. All tests run inside a private network
# namespace (LCM udpm and the Aravis fake camera stay on its loopback).
# Extra arguments go to ctest (e.g. -R common, -L udpm).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
"$NADIR_ROOT/launch_scripts/setup.sh"
cd "$NADIR_BUILD"
nadir_in_netns ctest --output-on-failure -j"$(nproc)" "$@"
