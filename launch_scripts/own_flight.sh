#!/usr/bin/env bash
# Your own flight, one command: imports a recorded flight (nadir_import), runs
# the estimator on it (nadir_replay: tracker, vo_solver, yaw_fusion, with the
# config the import wrote) and evaluates it against the flight's GPS (nadir_eval).
# Usage: own_flight.sh --photos DIR [--camera FILE] [--name NAME] [import options...]
#        own_flight.sh --video FILE (--srt FILE | --csv FILE) [--camera FILE] [--name NAME] [import options...]
# Import options (nadir_import --help): --focal-px F, --scale S, --interval S, --skip-bad, --config FILE.
# Output under logs/<UTC>-own-<NAME>/ (NAME: the folder's / video's name unless given).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
name=""
source_path=""
import_args=()
while (($#)); do
  case "$1" in
    -h|--help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --name) name="$2"; shift 2 ;;
    --photos|--video) source_path="$2"; import_args+=("$1" "$2"); shift 2 ;;
    --skip-bad) import_args+=("$1"); shift ;;
    --srt|--csv|--camera|--focal-px|--scale|--interval|--config) import_args+=("$1" "$2"); shift 2 ;;
    *) echo "own_flight: error: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
[ -n "$source_path" ] || { echo "own_flight: error: give --photos DIR or --video FILE (see --help)" >&2; exit 2; }
[ -n "$name" ] || name="$(basename "${source_path%/}")"; name="${name%.*}"
for tool in nadir_import nadir_replay nadir_eval; do
  command -v "$tool" >/dev/null || { echo "own_flight: error: $tool not built (launch_scripts/setup.sh)" >&2; exit 1; }
done

run_dir="$NADIR_ROOT/logs/$(nadir_utc_stamp)-own-$name"
mkdir -p "$run_dir/report"
echo "own_flight: $source_path -> $run_dir"
nadir_import "${import_args[@]}" --out "$run_dir/flight" --json >"$run_dir/import.json" 2> >(tee "$run_dir/import.txt" >&2)
nadir_replay --in "$run_dir/flight.lcmlog" --out "$run_dir/replay.lcmlog" --nodes tracker,vo_solver,yaw_fusion \
  --config "$run_dir/flight.yaml" --json >"$run_dir/replay.json" 2>"$run_dir/replay.txt" ||
  { cat "$run_dir/replay.txt" >&2; echo "own_flight: error: replay failed (see $run_dir/replay.txt)" >&2; exit 1; }
echo
echo "=== nadir on your own flight: $name ==="
nadir_eval --log "$run_dir/replay.lcmlog" --out "$run_dir/report" | tee "$run_dir/report/summary.txt"
echo
echo "files:"
echo "  imported    $run_dir/flight.lcmlog + flight.yaml  (summary: $run_dir/import.json)"
echo "  replay      $run_dir/replay.lcmlog  ($run_dir/replay.json)"
echo "  trajectory  $run_dir/report/trajectory.png"
echo "  metrics     $run_dir/report/metrics.json  (+ series.csv, trajectory.geojson, trajectory.kml)"
