#!/usr/bin/env bash
# The paper's Fig. 8b on the test1 profile: the standard sensor set, then
# sigma 3 deg roll/pitch noise, sigma 3 deg yaw noise, 3 % altimeter noise.
# Prints the table (seed 201) and draws a bar chart of horizontal and vertical
# drift %. Every case flies the same seed, so the difference between a noisy
# run and the standard run is the error the added noise caused:
# studies/sensor_noise/added_drift.py tabulates and plots it against distance flown
# (bounded or growing), averaged over the seeds flown.
# Usage: noise_study.sh [--reuse] [--profile NAME] [--seeds N]   (N = 1..3 seeds: 201, 202, 203; default 3)
#                       [--sensor-set NAME] [--config-overlay FILE]...
# --sensor-set: the set the noise is added to (default standard; logs/noise_study-PROFILE-NAME/);
# --config-overlay: replay with this fragment (e.g. calibrate.sh's calibration.yaml; reports beside
#   the simulator logs, in CASE-<file name>/).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../../launch_scripts/eval_common.sh"
profile=test1
n_seeds=3
sensor_set=standard
sim_args=()
overlays=()
report_suffix=""
while (($#)); do
  case "$1" in
    --reuse) export NADIR_REUSE=1; shift ;;
    --profile) profile="$2"; shift 2 ;;
    --seeds) n_seeds="$2"; shift 2 ;;
    --sensor-set) sensor_set="$2"; shift 2 ;;
    --config-overlay) add_config_overlay noise_study "$2"; shift 2 ;;
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "noise_study: error: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ "$n_seeds" =~ ^[123]$ ]] || { echo "noise_study: error: --seeds must be 1, 2 or 3" >&2; exit 2; }
"$NADIR_ROOT/launch_scripts/setup.sh" >/dev/null
out="$NADIR_ROOT/logs/noise_study-$profile"
use_sensor_set "$sensor_set" out
cases=(standard roll_pitch_3deg yaw_3deg altimeter_3pct)
declare -A args=([standard]="" [roll_pitch_3deg]="--roll-pitch-noise-deg 3" [yaw_3deg]="--yaw-noise-deg 3"
                 [altimeter_3pct]="--altimeter-noise-pct 3")
seeds=(201 202 203)
seeds=("${seeds[@]:0:$n_seeds}")
seed_dir() { if [ "$1" = 201 ]; then echo "$out"; else echo "$out/seed-$1"; fi; }   # 201: the table's flight
for s in "${seeds[@]}"; do
  dir=$(seed_dir "$s")
  mkdir -p "$dir"
  for c in "${cases[@]}"; do
    echo "$c (seed $s):"
    # shellcheck disable=SC2086
    simulate "$profile" "$s" "$dir/$c.lcmlog" "${sim_args[@]}" ${args[$c]}
    replay_and_eval "$dir/$c.lcmlog" "$dir/$c$report_suffix" "${overlays[@]}"
  done
done
{
  echo "| added noise ($profile, seed 201) | horizontal drift % | vertical drift % | final error m | fused yaw error rms deg |"
  echo "|---|---|---|---|---|"
  for c in "${cases[@]}"; do
    r="$out/$c$report_suffix"
    echo "| $c | $(metric "$r" error_pct_h) | $(metric "$r" error_pct_v) | $(metric "$r" final_error_3d_m)" \
      "| $(metric "$r" rms_yaw_error_deg) |"
  done
  echo
  /usr/bin/python3 "$NADIR_ROOT/studies/sensor_noise/added_drift.py" \
    $(for s in "${seeds[@]}"; do echo "--reference $(seed_dir "$s")/standard$report_suffix"; done) \
    --out-png "$out/added_drift$report_suffix.png" --out-json "$out/added_drift$report_suffix.json" \
    $(for c in "${cases[@]:1}"; do echo "$c=$(for s in "${seeds[@]}"; do printf '%s,' "$(seed_dir "$s")/$c$report_suffix"; done | sed 's/,$//')"; done)
} | tee "$out/noise_study$report_suffix.md"
/usr/bin/python3 "$NADIR_ROOT/studies/lib/plot_bars.py" --out "$out/noise_study$report_suffix.png" \
  --title "Drift with added sensor noise ($profile, $sensor_set set${report_suffix:+, ${report_suffix#-}}, seed 201)" \
  --metrics error_pct_h,error_pct_v --labels "horizontal %,vertical %" \
  $(for c in "${cases[@]}"; do echo "$c=$out/$c$report_suffix"; done)
echo "charts: $out/noise_study$report_suffix.png $out/added_drift$report_suffix.png"
