#!/usr/bin/env bash
# One campaign cell, exactly as table1.sh / noise_study.sh fly one case:
# simulate, replay in lockstep, evaluate (launch_scripts/eval_common.sh).
# Keeps metrics.json, series.csv and replay.json; drops the plots and, unless
# KEEP_LOGS=1, the simulator log (the seed and the config reproduce it).
# Usage: run_cell.sh PROFILE SEED CELL_DIR [nadir_sim options...] -- [nadir_replay options...]
set -euo pipefail
case "${1:-}" in -h|--help) sed -n '2,6p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;; esac
source "$(dirname "${BASH_SOURCE[0]}")/../../launch_scripts/eval_common.sh"
(($# >= 3)) || { echo "run_cell: error: expected PROFILE SEED CELL_DIR [sim options] -- [replay options]" >&2; exit 2; }
profile="$1" seed="$2" dir="$3"
shift 3
sim_opts=()
while (($#)) && [ "$1" != "--" ]; do sim_opts+=("$1"); shift; done
(($#)) && shift
mkdir -p "$dir"
simulate "$profile" "$seed" "$dir/sim.lcmlog" "${sim_opts[@]}"
replay_and_eval "$dir/sim.lcmlog" "$dir/eval" "$@"
rm -f "$dir"/eval/*.png "$dir/eval/index.html" "$dir/eval/trajectory.geojson" "$dir/eval/trajectory.kml"
[ "${KEEP_LOGS:-0}" = 1 ] || rm -f "$dir/sim.lcmlog"
