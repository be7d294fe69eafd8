#!/usr/bin/env bash
# The simulated survey (survey profile, seed 1) exported with each defect a
# real survey brings, each flown the way a new user flies it:
# launch_scripts/own_flight.sh --photos DIR and nothing else (no camera file);
# then the same folders with the exporter's camera.yaml (--camera), and the
# yaw-offset folder with --gps-scale focal --calibrate-until 60.
# Kinds: base (no defect), turned (the return line stored turned 180 deg),
# turned90 (... 90 deg), crop169 (16:9 crops of a 4:3 FC300X, 35 mm
# equivalent only), mp12 (12 MP frames), yawoffset (recorded yaw 11.5 deg off).
# Prints pairs solved, per-pair median (p90), final error per run, and wall
# time and peak memory of each own_flight.sh run (/usr/bin/time).
# Results under logs/photo_defects/<UTC>/.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../../launch_scripts/common.sh"
case "${1:-}" in -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;; esac
out="$NADIR_ROOT/logs/photo_defects/$(nadir_utc_stamp)"
mkdir -p "$out"
nadir_sim --profile survey --seed 1 --out "$out/sim.lcmlog" >/dev/null 2>&1
nadir_sim --profile survey --seed 1 --config-overlay "$NADIR_ROOT/config/sim_camera_12mp.yaml" \
  --out "$out/sim12.lcmlog" >/dev/null 2>&1
export_kind() {  # NAME LOG [nadir_export photos options]
  local name="$1" log="$2"; shift 2
  nadir_export photos --in "$log" --out "$out/$name" "$@" >/dev/null 2>&1
  mv "$out/$name/camera.yaml" "$out/$name.camera.yaml"  # not in the folder: the user has none
}
export_kind base "$out/sim.lcmlog"
export_kind turned "$out/sim.lcmlog" --turn-return-lines 180
export_kind turned90 "$out/sim.lcmlog" --turn-return-lines 90
export_kind crop169 "$out/sim.lcmlog" --crop-16-9 --model FC300X
export_kind mp12 "$out/sim12.lcmlog"
export_kind yawoffset "$out/sim.lcmlog" --yaw-offset-deg=-11.5
rm -f "$out/sim12.lcmlog"
fly() {  # RUN_NAME FOLDER [own_flight options]
  local run="$1" folder="$2"; shift 2
  /usr/bin/time -f "%e s, %M KB peak" -o "$out/$run.time" \
    "$NADIR_ROOT/launch_scripts/own_flight.sh" --photos "$out/$folder" --name "defects-$run" "$@" >"$out/$run.out" 2>&1 || true
  printf '| %s | %s | %s | %s | %s |\n' "$run" \
    "$(grep -m1 '^frame pairs' "$out/$run.out" | sed 's/.*VO_DELTA, \([0-9]* solved\).*/\1/')" \
    "$(grep -m1 '^frame pairs' "$out/$run.out" | sed 's/.*per pair \([0-9.]* %\) of the step median, \([0-9.]* %\) p90.*/\1 (\2)/')" \
    "$(grep -m1 '^final error' "$out/$run.out" | sed 's/^final error *//')" "$(cat "$out/$run.time")"
}
echo "| run | pairs solved (of 41) | per-pair median (p90) | final error | time, memory |"
echo "|---|---|---|---|---|"
for k in base turned turned90 crop169 mp12 yawoffset; do fly "$k" "$k"; done
for k in base turned turned90; do fly "$k-camera" "$k" --camera "$out/$k.camera.yaml"; done
fly yawoffset-fit yawoffset --gps-scale focal --calibrate-until 60
grep -E '^(image scale|heading|held-out)' "$out/yawoffset-fit.out" || true
