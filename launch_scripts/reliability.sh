#!/usr/bin/env bash
# Faults on the live sim set, measured: each case flies the demo profile
# (seed 1) through the live set inside a private network namespace, with one
# fault, and evaluates it. Prints a table (and writes it to OUT/table.md):
#   clean        no fault (the reference)
#   hostile      nadir_hostile: ~600 hostile messages over 30 s (20 Hz) from t = 10 s
#   kill         yaw_fusion killed with SIGKILL at ~30 s (run_set restarts it),
#                lcm-logger stopped (SIGSTOP) for 3 s at ~22 s
#   stop         vo_solver stopped (SIGSTOP) for 3 s at ~30 s, then continued
#   rate2/rate3  the simulator at 2x / 3x real time
# Usage: reliability.sh [--cases clean,hostile,kill,stop,rate2,rate3] [--out DIR]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cases="clean,hostile,kill,stop,rate2,rate3"
out=""
while (($#)); do
  case "$1" in
    -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --cases) cases="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    *) echo "reliability: error: unknown option $1" >&2; exit 2 ;;
  esac
done
out="${out:-$NADIR_ROOT/logs/$(nadir_utc_stamp)-reliability}"
mkdir -p "$out"
if [ "${NADIR_IN_NETNS:-0}" != 1 ]; then
  exec bash -c 'source "$1/launch_scripts/common.sh"; shift; nadir_in_netns "$@"' _ "$NADIR_ROOT" \
    "$0" --cases "$cases" --out "$out"
fi


fly() {  # fly CASE: one flight with its fault, evaluated into $out/CASE
  local name="$1" dir="$out/$1" rate=1.0
  case "$name" in rate2) rate=2.0 ;; rate3) rate=3.0 ;; esac
  NADIR_CAPTURE_DIR="$dir" NADIR_PROFILE=demo NADIR_SEED=1 NADIR_SIM_RATE="$rate" \
    "$NADIR_ROOT/launch_scripts/run_set.sh" sim >"$dir.txt" 2>&1 &
  local set_pid=$!
  case "$name" in
    hostile)
      nadir_hostile --delay 10 --duration 30 --rate 20 --json >"$dir.hostile.json" ;;
    kill)
      sleep 22
      local logger; logger="$(pgrep -P "$set_pid" -x lcm-logger | head -1)"
      kill -STOP "$logger"; sleep 3; kill -CONT "$logger"
      sleep 5
      pkill -KILL -P "$set_pid" -f "^nadir_yaw_fusion " || echo "reliability: no yaw_fusion to kill" >&2 ;;
    stop)
      sleep 30
      local solver; solver="$(pgrep -P "$set_pid" -x nadir_vo_solver | head -1)"
      kill -STOP "$solver"; sleep 3; kill -CONT "$solver" ;;
  esac
  wait "$set_pid" || echo "reliability: $name: the set exited non-zero" >&2
  nadir_eval --log "$dir/capture.lcmlog" --out "$dir/report" --no-plots --json >"$dir/metrics.json" \
    2>"$dir/eval_stderr.txt" || echo "reliability: $name: nadir_eval failed" >&2
}

IFS=, read -r -a list <<<"$cases"
for c in "${list[@]}"; do
  echo "reliability: flying '$c' ..." >&2
  fly "$c"
done
/usr/bin/python3 "$NADIR_ROOT/tools/eval/reliability_table.py" "$out" "${list[@]}" | tee "$out/table.md"
echo "reliability: results in $out" >&2
