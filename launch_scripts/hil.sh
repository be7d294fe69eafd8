#!/usr/bin/env bash
# Runs the vehicle process set (camera capture over GigE Vision, INS/altimeter
# bridge over pseudo-terminals, tracker, VO solver, yaw fusion) on a simulated
# flight inside a private network namespace, then evaluates POSE against the
# simulator's GROUND_TRUTH moved onto the live clock.
# Usage: hil.sh [--profile NAME] [--seed N] [--duration S]   (default demo, 1, 60)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
profile=demo; seed=1; duration=60
while (($#)); do
  case "$1" in
    -h|--help) sed -n '2,6p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --profile) profile="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    *) echo "hil: error: unknown option $1" >&2; exit 2 ;;
  esac
done
"$NADIR_ROOT/launch_scripts/setup.sh" >/dev/null
run_dir="$NADIR_ROOT/logs/$(nadir_utc_stamp)-hil-$profile"
mkdir -p "$run_dir/tty" "$run_dir/report"
sim_log="$run_dir/sim.lcmlog"
nadir_sim --profile "$profile" --seed "$seed" --duration "$duration" --out "$sim_log" >"$run_dir/sim.txt" 2>&1
# The simulator's log epoch (first sensor time) is the shared clock's origin.
log_origin=$(nadir_log info "$sim_log" --json | /usr/bin/python3 -c 'import json,sys; c=json.load(sys.stdin)["channels"]; print(min(v["first_utime"] for k,v in c.items() if v["first_utime"]>0))')
export NADIR_HIL_LOG="$sim_log" NADIR_HIL_LOG_ORIGIN_US="$log_origin" NADIR_HIL_TTY_DIR="$run_dir/tty"
export NADIR_HIL_ORIGIN_US=$(( $(date +%s%6N) + 8000000 ))   # 8 s for the set to come up
echo "hil: $profile (seed $seed, $duration s) through the vehicle set; output in $run_dir"
# As root the namespace keeps CAP_SYS_NICE: the set's real-time request is granted, as on the vehicle.
NADIR_NETNS_KEEP_CAPS=1 NADIR_CAPTURE_DIR="$run_dir" nadir_in_netns "$NADIR_ROOT/launch_scripts/run_set.sh" hil >"$run_dir/run.txt" 2>&1 || true
grep -E '^\[run_set\]' "$run_dir/run.txt" | tail -3
nadir_eval --log "$run_dir/capture.lcmlog" --truth "$sim_log" --truth-shift-us $((NADIR_HIL_ORIGIN_US - log_origin)) \
  --out "$run_dir/report" | tee "$run_dir/report/summary.txt"
