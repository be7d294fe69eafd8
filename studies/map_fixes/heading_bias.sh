#!/usr/bin/env bash
# The INS heading bias estimated from the map's fixes (yaw_fusion.map_fix.estimates_heading_bias) on
# simulated flights: each flight simulated with its reference map, replayed with the map matcher, then
# yaw fusion alone replayed again with the bias estimated and without, with all the fixes and with the
# fixes ending half-way through the flight (studies/map_fixes/fixes_end.py), and once without a map.
# Prints one line per flight and run: final and 95th-percentile horizontal error, horizontal NEES.
# Usage: studies/map_fixes/heading_bias.sh standard|realistic|noisy PROFILE:SEED...
#   (output in logs/heading_bias/SET-PROFILE-SEED/; `realistic` replays with config/uncertainty/realistic.yaml
#    and the 97 s calibration, config/installation/realistic_calibrated.yaml; `noisy` is the consistency
#    campaigns' noisy INS and altimeter on the standard set)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
if [ $# -lt 2 ] || [ "$1" = --help ] || [ "$1" = -h ]; then
  sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'
  exit 0
fi
set_name="$1"
shift
sim_set="$set_name"
sim_noise=()
case "$set_name" in
  standard) overlays=() ;;
  realistic) overlays=(--config-overlay "$root/config/uncertainty/realistic.yaml"
                       --config-overlay "$root/config/installation/realistic_calibrated.yaml") ;;
  noisy)  # the consistency campaigns' noisy INS and altimeter (config/campaigns/consistency_noisy_whole.yaml)
    sim_set=standard
    sim_noise=(--roll-pitch-noise-deg 0.3 --yaw-noise-deg 0.3 --altimeter-noise-pct 0.5)
    overlays=(--set vo_solver.uncertainty.roll_pitch_stddev_deg=0.3 --set vo_solver.uncertainty.yaw_stddev_deg=0.3
              --set vo_solver.uncertainty.altimeter_stddev_fraction=0.005) ;;
  *) echo "heading_bias.sh: sensor set '$set_name' is not standard, realistic or noisy" >&2; exit 2 ;;
esac
"$root/launch_scripts/setup.sh" >/dev/null
export PATH="$root/build/bin:$PATH"
summary() {  # NAME EVAL_JSON
  /usr/bin/python3 - "$1" "$2" <<'PY'
import json, sys
m = json.load(open(sys.argv[2]))
print(f"  {sys.argv[1]:28s} final {m['final_error_h_m']:5.2f} m  p95 {m['p95_error_h_m']:5.2f} m  "
      f"NEES {m['nees_h_mean']:5.2f}  beyond PL {m['pl_exceeded_pct']:5.2f} %")
PY
}
for flight in "$@"; do
  profile="${flight%%:*}"
  seed="${flight##*:}"
  out="$root/logs/heading_bias/$set_name-$profile-$seed"
  mkdir -p "$out"
  if [ ! -f "$out/sim.lcmlog" ]; then  # written aside and moved: an interrupted run leaves no partial log behind
    nadir_sim --profile "$profile" --seed "$seed" --sensor-set "$sim_set" "${sim_noise[@]}" --out "$out/sim.part.lcmlog" \
      >"$out/sim.txt" 2>&1
    mv "$out/sim.part.lcmlog" "$out/sim.lcmlog"
  fi
  if [ ! -f "$out/map/map.json" ]; then
    rm -rf "$out/map"
    nadir_map simulate --profile "$profile" --seed "$seed" --out "$out/map.part" --max-megapixels 80 --max-gsd 5 \
      >"$out/map.txt"
    mv "$out/map.part" "$out/map"
  fi
  gsd="$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["gsd_m"])' "$out/map/map.json")"
  duration="$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["duration_s"])' \
    <(nadir_log info "$out/sim.lcmlog" --json 2>/dev/null || echo '{"duration_s": 0}'))"
  nadir_replay --in "$out/sim.lcmlog" --out "$out/with_map.lcmlog" --nodes tracker,vo_solver,yaw_fusion,map_matcher \
    "${overlays[@]}" --set "map_matcher.orthophoto=$out/map/orthophoto.tif" --set "map_matcher.dem=$out/map/dem.tif" \
    --set "map_matcher.gsd_m=$gsd" >"$out/with_map.txt" 2>&1
  nadir_replay --in "$out/sim.lcmlog" --out "$out/no_map.lcmlog" --nodes tracker,vo_solver,yaw_fusion \
    "${overlays[@]}" >"$out/no_map.txt" 2>&1
  /usr/bin/python3 "$root/studies/map_fixes/fixes_end.py" "$out/with_map.lcmlog" "$out/all_fixes.lcmlog" --end-s 1e9 >/dev/null
  /usr/bin/python3 "$root/studies/map_fixes/fixes_end.py" "$out/with_map.lcmlog" "$out/half_fixes.lcmlog" \
    --end-s "$(/usr/bin/python3 -c "print(0.5 * float('$duration') if float('$duration') > 0 else 1e9)")" >/dev/null
  rm -f "$out/with_map.lcmlog"
  echo "$set_name $profile seed $seed"
  nadir_eval --log "$out/no_map.lcmlog" --out "$out/no_map" --no-plots --json >"$out/no_map.json"
  summary "no map" "$out/no_map.json"
  rm -f "$out/no_map.lcmlog"
  for fixes in all half; do
    for estimate in false true; do
      run="${fixes}_fixes_estimate_$estimate"
      nadir_replay --in "$out/${fixes}_fixes.lcmlog" --out "$out/$run.lcmlog" --nodes yaw_fusion "${overlays[@]}" \
        --set "yaw_fusion.map_fix.estimates_heading_bias=$estimate" >"$out/$run.txt" 2>&1
      nadir_eval --log "$out/$run.lcmlog" --out "$out/$run" --no-plots --json >"$out/$run.json"
      rm -f "$out/$run.lcmlog"
      summary "$fixes fixes, bias $([ "$estimate" = true ] && echo estimated || echo held)" "$out/$run.json"
    done
  done
  rm -f "$out/all_fixes.lcmlog" "$out/half_fixes.lcmlog"
done
