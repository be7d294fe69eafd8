#!/usr/bin/env bash
# The main job on a built-in default: sets up, flies the `demo` profile through
# the live `sim` process set (simulator + tracker + VO solver + yaw fusion over
# LCM udpm inside a private network namespace), captures it with lcm-logger,
# evaluates POSE against GROUND_TRUTH and prints a short report.
# Usage: demo.sh [--profile NAME] [--seed N] [--foxglove]
#   (report under logs/<UTC>-demo-NAME/; --foxglove: with nadir_foxglove serving the
#   flight at ws://127.0.0.1:8765 inside the namespace, see docs/foxglove.md)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
profile=demo
seed=1
set_name=sim
while (($#)); do
  case "$1" in
    -h|--help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --foxglove) set_name=sim_foxglove; shift ;;
    --profile) profile="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    *) echo "demo: error: unknown option $1" >&2; exit 2 ;;
  esac
done
"$NADIR_ROOT/launch_scripts/setup.sh" --demo
if [ "$set_name" = sim_foxglove ]; then
  # Not part of the demo's build (needs websocketpp: setup.sh without --demo).
  cmake --build "$NADIR_BUILD" --target nadir_foxglove >/dev/null ||
    { echo "demo: error: nadir_foxglove does not build (run launch_scripts/setup.sh first)" >&2; exit 1; }
fi

run_dir="$NADIR_ROOT/logs/$(nadir_utc_stamp)-demo-$profile"
mkdir -p "$run_dir/report"
echo "demo: flying profile '$profile' (seed $seed) through the live $set_name set; output in $run_dir"
# As root the namespace keeps CAP_SYS_NICE, so that the set's `realtime`
# request is granted as it would be on the vehicle (run_set.sh says so).
NADIR_NETNS_KEEP_CAPS=1 NADIR_PROFILE="$profile" NADIR_SEED="$seed" NADIR_CAPTURE_DIR="$run_dir" \
  nadir_in_netns "$NADIR_ROOT/launch_scripts/run_set.sh" "$set_name" 2>&1 | tee "$run_dir/run.txt" |
  grep -E '^\[run_set\]|: error|GIVING UP' || true
capture="$run_dir/capture.lcmlog"
[ -s "$capture" ] || { echo "demo: error: no capture at $capture (see $run_dir/run.txt)" >&2; exit 1; }
nadir_log info "$capture" >"$run_dir/log_info.txt"
echo
echo "=== nadir demo: profile $profile, seed $seed ==="
nadir_eval --log "$capture" --out "$run_dir/report" | tee "$run_dir/report/summary.txt"
echo
echo "files:"
echo "  capture     $capture   (nadir_log info: $run_dir/log_info.txt)"
echo "  trajectory  $run_dir/report/trajectory.png"
echo "  drift       $run_dir/report/drift.png"
echo "  velocity    $run_dir/report/velocity_errors.png"
echo "  report      $run_dir/report/index.html   (open in a browser: plots, pairs, processes)"
echo "  metrics     $run_dir/report/metrics.json  (+ series.csv, trajectory.geojson, trajectory.kml)"
echo "  processes   $run_dir/run.txt"
