#!/usr/bin/env bash
# The paper's Table 1 on simulated flights: test1, test2, test3 with the
# standard sensor set and fixed seeds, replayed in lockstep and evaluated.
# Prints a markdown table with the paper's figures beside ours.
# Usage: table1.sh [--reuse] [--profiles test1,test2,test3[,rough_120,rough_250]]
#                  [--sensor-set NAME] [--config-overlay FILE]...
#   --reuse     keeps simulator logs already in logs/table1/
#   --profiles  the rows (default test1,test2,test3); the rough-ground profiles
#               of the rough-ground study (rough_120, rough_250: seeds 104, 105) have no paper figures
#   --sensor-set  simulate with this set of config/sim_sensors.yaml (default standard;
#               logs in logs/table1-NAME/), e.g. realistic
#   --config-overlay  replay with this fragment merged into the config, e.g.
#               launch_scripts/calibrate.sh's calibration.yaml (reports in <profile>-<file name>/)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/eval_common.sh"
profiles=test1,test2,test3
sensor_set=standard
sim_args=()
overlays=()
report_suffix=""
while (($#)); do
  case "$1" in
    --reuse) export NADIR_REUSE=1; shift ;;
    --profiles) profiles="$2"; shift 2 ;;
    --sensor-set) sensor_set="$2"; shift 2 ;;
    --config-overlay) add_config_overlay table1 "$2"; shift 2 ;;
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "table1: error: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
declare -A seed=([test1]=101 [test2]=102 [test3]=103 [rough_120]=104 [rough_250]=105)
declare -A paper=([test1]="7800m | 300m | 30m/s | 0.39%" [test2]="3700m | 150m | 20m/s | 0.73%" [test3]="4500m | 200m | 20m/s | 0.78%"
                  [rough_120]="- | - | - | -" [rough_250]="- | - | - | -")
IFS=, read -r -a rows <<<"$profiles"
for t in "${rows[@]}"; do
  [ -n "${seed[$t]:-}" ] || { echo "table1: error: unknown profile '$t' (allowed: ${!seed[*]})" >&2; exit 2; }
done
"$NADIR_ROOT/launch_scripts/setup.sh" >/dev/null
out="$NADIR_ROOT/logs/table1"
use_sensor_set "$sensor_set" out
mkdir -p "$out"
for t in "${rows[@]}"; do
  echo "$t:"
  simulate "$t" "${seed[$t]}" "$out/$t.lcmlog" "${sim_args[@]}"
  replay_and_eval "$out/$t.lcmlog" "$out/$t$report_suffix" "${overlays[@]}"
done
{
  echo "| Test | Paper: distance | altitude | speed | accuracy | nadir (sim): distance | final error | error % of distance | horizontal % | vertical % |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
  for t in "${rows[@]}"; do
    d="$out/$t$report_suffix"
    echo "| ${t#test} | ${paper[$t]} | $(metric "$d" distance_m) m | $(metric "$d" final_error_3d_m) m | $(metric "$d" error_pct_3d) % | $(metric "$d" error_pct_h) % | $(metric "$d" error_pct_v) % |"
  done
} | tee "$out/table1$report_suffix.md"
echo "reports: $out/<profile>$report_suffix/ (trajectory.png, drift.png, velocity_errors.png, metrics.json)"
