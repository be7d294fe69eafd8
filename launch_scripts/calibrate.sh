#!/usr/bin/env bash
# Installation calibration from a calibration flight, one command
# (docs/calibration.md). Two passes of nadir_calibrate:
#   1. tracker replay -> epipolar fit (boresight, time offset, focal scale,
#      k1 check) and altimeter regression (scale, bias);
#   2. tracker + vo_solver replay with pass 1 applied -> the image scale against
#      GNSS written as the focal length (the scale the VO itself sees), the
#      boresight refined about pass 1's mount.
# Usage: calibrate.sh --log FLIGHT.lcmlog [--config FILE] [--installation FILE]...
#                     [--name NAME] [nadir_calibrate options...]
# --installation: lever arms and beam misalignment from the installation
#   drawing (camera.lever_arm_m, altimeter.lever_arm_m, altimeter.beam_misalignment_deg),
#   given to both passes and echoed in the fragment. Other options go to both
#   passes (--ins-attitude-accuracy-deg R P Y, --ins-attitude-correlation-s TAU, --ground-height-m H,
#   --from-s S, --until-s S).
# Output: logs/<UTC>-calibration-<NAME>/calibration.yaml, to replay any flight with
#   nadir_replay ... --config-overlay calibration.yaml.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
log=""
name=""
config=()
installation=()
calibrate_args=()
while (($#)); do
  case "$1" in
    -h|--help) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --log) log="$(realpath "$2")"; shift 2 ;;
    --name) name="$2"; shift 2 ;;
    --config) config=(--config "$(realpath "$2")"); shift 2 ;;
    --installation) installation+=(--config-overlay "$(realpath "$2")"); shift 2 ;;
    --ins-attitude-accuracy-deg) calibrate_args+=("$1" "$2" "$3" "$4"); shift 4 ;;
    --ground-height-m|--from-s|--until-s|--attitude-smoothing-s|--cluster-s|--ins-attitude-correlation-s)
      calibrate_args+=("$1" "$2"); shift 2 ;;
    *) echo "calibrate: error: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
[ -n "$log" ] || { echo "calibrate: error: give --log FLIGHT.lcmlog (see --help)" >&2; exit 2; }
[ -f "$log" ] || { echo "calibrate: error: $log: no such file" >&2; exit 2; }
[ -n "$name" ] || name="$(basename "${log%.*}")"
for tool in nadir_replay nadir_calibrate; do
  command -v "$tool" >/dev/null || { echo "calibrate: error: $tool not built (launch_scripts/setup.sh)" >&2; exit 1; }
done
run_dir="$NADIR_ROOT/logs/$(nadir_utc_stamp)-calibration-$name"
mkdir -p "$run_dir"
echo "calibrate: $log -> $run_dir"

# run STEP COMMAND...: output to STEP.txt, shown on failure.
run() {
  local step="$1"; shift
  "$@" >"$run_dir/$step.txt" 2>&1 || { cat "$run_dir/$step.txt" >&2; echo "calibrate: error: $step failed" >&2; exit 1; }
}
echo "  pass 1: tracker replay, epipolar fit and altimeter regression"
run tracks nadir_replay --in "$log" --out "$run_dir/tracks.lcmlog" --nodes tracker "${config[@]}" "${installation[@]}" --json
run pass1 nadir_calibrate --log "$run_dir/tracks.lcmlog" "${config[@]}" "${installation[@]}" "${calibrate_args[@]}" \
  --out "$run_dir/pass1.yaml"
rm -f "$run_dir/tracks.lcmlog"
echo "  pass 2: VO replay with pass 1, image scale against GNSS"
run vo nadir_replay --in "$log" --out "$run_dir/vo.lcmlog" --nodes tracker,vo_solver "${config[@]}" "${installation[@]}" \
  --config-overlay "$run_dir/pass1.yaml" --json
run pass2 nadir_calibrate --log "$run_dir/vo.lcmlog" "${config[@]}" "${installation[@]}" \
  --config-overlay "$run_dir/pass1.yaml" "${calibrate_args[@]}" --gps-scale focal --out "$run_dir/calibration.yaml"
rm -f "$run_dir/vo.lcmlog"
grep '^# ' "$run_dir/pass1.yaml" | sed 's/^# /  pass 1: /'
grep -E '^# (boresight|time offset|GNSS scale|warning)' "$run_dir/calibration.yaml" | sed 's/^# /  pass 2: /'
echo "calibration: $run_dir/calibration.yaml (nadir_replay ... --config-overlay $run_dir/calibration.yaml)"
