#!/usr/bin/env bash
# Your own flight, one command: imports a recorded flight (nadir_import), runs
# the estimator on it (nadir_replay: tracker, vo_solver, yaw_fusion, with the
# config the import wrote) and evaluates it against the flight's GPS (nadir_eval).
# Usage: own_flight.sh --photos DIR [--camera FILE] [--name NAME] [import options...]
#        own_flight.sh --video FILE (--srt FILE | --csv FILE) [--camera FILE] [--name NAME] [import options...]
# Import options (nadir_import --help): --focal-px F, --scale S, --interval S, --skip-bad, --config FILE,
#   --attitude-stddev-deg D, --heading-stddev-deg D (how well the recorded attitude is known).
# --overlay FILE: a config fragment for the replay (e.g. vo_solver: {variant: homography}).
# --gps-scale focal|altimeter --calibrate-until S: fit the image scale and the heading offset (the images'
#   heading against the recorded yaw) to the GPS on the first S seconds (nadir_calibrate --scale-only),
#   replay again with them and report the pairs after S apart.
# Output under logs/<UTC>-own-<NAME>/ (NAME: the folder's / video's name unless given).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
name=""
source_path=""
import_args=()
overlay_args=()
gps_scale=""
calibrate_until=""
while (($#)); do
  case "$1" in
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --name) name="$2"; shift 2 ;;
    --photos|--video) source_path="$2"; import_args+=("$1" "$2"); shift 2 ;;
    --skip-bad) import_args+=("$1"); shift ;;
    --overlay) overlay_args=(--config-overlay "$(realpath "$2")"); shift 2 ;;
    --gps-scale) gps_scale="$2"; shift 2 ;;
    --calibrate-until) calibrate_until="$2"; shift 2 ;;
    --srt|--csv|--camera|--focal-px|--scale|--interval|--config|--attitude-stddev-deg|--heading-stddev-deg)
      import_args+=("$1" "$2"); shift 2 ;;
    *) echo "own_flight: error: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
[ -n "$source_path" ] || { echo "own_flight: error: give --photos DIR or --video FILE (see --help)" >&2; exit 2; }
if [ -n "$gps_scale$calibrate_until" ] && { [ -z "$gps_scale" ] || [ -z "$calibrate_until" ]; }; then
  echo "own_flight: error: --gps-scale and --calibrate-until go together (see --help)" >&2; exit 2
fi
[ -n "$name" ] || name="$(basename "${source_path%/}")"; name="${name%.*}"
for tool in nadir_import nadir_replay nadir_eval nadir_calibrate; do
  command -v "$tool" >/dev/null || { echo "own_flight: error: $tool not built (launch_scripts/setup.sh)" >&2; exit 1; }
done

run_dir="$NADIR_ROOT/logs/$(nadir_utc_stamp)-own-$name"
mkdir -p "$run_dir/report"
echo "own_flight: $source_path -> $run_dir"
nadir_import "${import_args[@]}" --out "$run_dir/flight" --json >"$run_dir/import.json" 2> >(tee "$run_dir/import.txt" >&2)
nadir_replay --in "$run_dir/flight.lcmlog" --out "$run_dir/replay.lcmlog" --nodes tracker,vo_solver,yaw_fusion \
  --config "$run_dir/flight.yaml" "${overlay_args[@]}" --json >"$run_dir/replay.json" 2>"$run_dir/replay.txt" ||
  { cat "$run_dir/replay.txt" >&2; echo "own_flight: error: replay failed (see $run_dir/replay.txt)" >&2; exit 1; }
echo
echo "=== nadir on your own flight: $name ==="
nadir_eval --log "$run_dir/replay.lcmlog" --out "$run_dir/report" | tee "$run_dir/report/summary.txt"
echo "heading             the recorded yaw (not fitted to the GPS: --gps-scale focal --calibrate-until S fits its offset)" |
  tee -a "$run_dir/report/summary.txt"
if [ -n "$gps_scale" ]; then
  # The image scale against the GPS on the first part, checked on the rest.
  nadir_calibrate --log "$run_dir/replay.lcmlog" --config "$run_dir/flight.yaml" --gps-scale "$gps_scale" \
    --scale-only --until-s "$calibrate_until" --out "$run_dir/gps_scale.yaml" 2>"$run_dir/calibrate.txt" ||
    { cat "$run_dir/calibrate.txt" >&2; echo "own_flight: error: calibration failed" >&2; exit 1; }
  overlay="$run_dir/calibrated_overlay.yaml"
  { [ ${#overlay_args[@]} -eq 0 ] || cat "${overlay_args[1]}"; grep -v '^#' "$run_dir/gps_scale.yaml"; } >"$overlay"
  nadir_replay --in "$run_dir/flight.lcmlog" --out "$run_dir/replay_calibrated.lcmlog" \
    --nodes tracker,vo_solver,yaw_fusion --config "$run_dir/flight.yaml" --config-overlay "$overlay" --json \
    >"$run_dir/replay_calibrated.json" 2>"$run_dir/replay_calibrated.txt" ||
    { cat "$run_dir/replay_calibrated.txt" >&2; echo "own_flight: error: calibrated replay failed" >&2; exit 1; }
  mkdir -p "$run_dir/report_calibrated"
  echo
  echo "=== with the image scale and heading fitted on the first $calibrate_until s ==="
  nadir_eval --log "$run_dir/replay_calibrated.lcmlog" --out "$run_dir/report_calibrated" \
    | tee "$run_dir/report_calibrated/summary.txt"
  { echo "image scale         $(grep -m1 'GNSS scale' "$run_dir/gps_scale.yaml" | sed 's/^# *GNSS scale *//')"
    echo "heading             offset $(grep -m1 'heading offset' "$run_dir/gps_scale.yaml" | sed 's/^# *heading offset *//')"
  } | tee -a "$run_dir/report_calibrated/summary.txt"
  /usr/bin/python3 "$NADIR_ROOT/tools/import/held_out_pairs.py" --split-s "$calibrate_until" \
    --before "$run_dir/report/pairs.csv" --after "$run_dir/report_calibrated/pairs.csv" \
    | tee -a "$run_dir/report_calibrated/summary.txt"
fi
echo
echo "files:"
echo "  imported    $run_dir/flight.lcmlog + flight.yaml  (summary: $run_dir/import.json)"
echo "  replay      $run_dir/replay.lcmlog  ($run_dir/replay.json)"
echo "  trajectory  $run_dir/report/trajectory.png"
echo "  metrics     $run_dir/report/metrics.json  (+ series.csv, trajectory.geojson, trajectory.kml)"
