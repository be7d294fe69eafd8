#!/usr/bin/env bash
# Reliability of the live sim set (README "Reliability"), inside the private
# network namespace test.sh provides:
#  (a) the demo flight with nadir_hostile publishing ~600 hostile messages
#      over 30 s among the real ones: no process dies, the final error is
#      within 1.2x of the same flight without them, no POSE velocity is off
#      by more than 5 m/s, the rejections are counted in STATUS;
#  (b) yaw_fusion killed with SIGKILL mid-flight: run_set restarts it, it
#      continues from its checkpoint (no pose back at the origin), within
#      its reported covariance;
#  (c) the capture of (b) with lcm-logger stopped (SIGSTOP) for 3 s: the hole
#      is reported by nadir_log info and nadir_eval.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
export PATH="${NADIR_BUILD:-$root/build}/bin:$PATH"
source "$root/launch_scripts/common.sh"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
here="$(dirname "$0")"

fly() {  # fly NAME [hostile|kill]: demo profile, seed 1, captured into $work/NAME
  local name="$1" mode="${2:-}"
  NADIR_CAPTURE_DIR="$work/$name" NADIR_PROFILE=demo NADIR_SEED=1 \
    "$root/launch_scripts/run_set.sh" sim >"$work/$name.txt" 2>&1 &
  local set_pid=$!
  case "$mode" in
    hostile)
      nadir_hostile --delay 10 --duration 30 --rate 20 --json >"$work/hostile.json" ;;
    kill)
      sleep 22
      local logger; logger="$(pgrep -f "lcm-logger.*$work/$name/capture.lcmlog" | head -1)"
      kill -STOP "$logger"; sleep 3; kill -CONT "$logger"
      sleep 5
      pkill -KILL -f "nadir_yaw_fusion --checkpoint $work/$name/" || fail "(b) no yaw_fusion to kill"
      echo "killed yaw_fusion at ~30 s" ;;
  esac
  wait "$set_pid" || { tail -30 "$work/$name.txt"; fail "$name: the set failed"; }
  grep -q "GIVING UP" "$work/$name.txt" && fail "$name: run_set gave up on a process"
  nadir_eval --log "$work/$name/capture.lcmlog" --out "$work/$name/report" --no-plots --json \
    >"$work/$name/metrics.json" 2>"$work/$name/eval_stderr.txt" || fail "$name: nadir_eval failed"
}
metric() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }

fly clean
fly hostile hostile
clean_pct="$(metric "$work/clean/metrics.json" error_pct_3d)"
hostile_pct="$(metric "$work/hostile/metrics.json" error_pct_3d)"
sent="$(metric "$work/hostile.json" sent)"
ratio="$(python3 -c "print(f'{$hostile_pct / $clean_pct:.3f}')")"
echo "(a) $sent hostile messages: final error $hostile_pct % against $clean_pct % clean, ratio $ratio"
python3 -c "import sys; sys.exit(0 if $hostile_pct <= 1.2 * $clean_pct else 1)" || fail "(a) ratio $ratio > 1.2"
python3 "$here/check_series.py" "$work/hostile/report/series.csv" --max-velocity-error 5 || fail "(a) velocity"
for p in tracker vo_solver yaw_fusion; do
  grep -q "\[run_set\] $p died" "$work/hostile.txt" && fail "(a) $p died under hostile input"
done

fly killed kill
grep -q "\[run_set\] yaw_fusion died" "$work/killed.txt" || { tail -20 "$work/killed.txt"; fail "(b) yaw_fusion was not restarted"; }
python3 "$here/check_series.py" "$work/killed/report/series.csv" --restart-after 30 || fail "(b) pose continuity"
killed_pct="$(metric "$work/killed/metrics.json" error_pct_3d)"
echo "(b) yaw_fusion killed at ~30 s and restarted: final error $killed_pct % (clean $clean_pct %)"

nadir_log info "$work/killed/capture.lcmlog" >"$work/killed/info.txt"
grep -E "^INS: no messages for [0-9.]+ s" "$work/killed/info.txt" || { cat "$work/killed/info.txt"; fail "(c) nadir_log info reports no hole"; }
grep -q "hole(s) in the capture" "$work/killed/eval_stderr.txt" || fail "(c) nadir_eval did not warn about the hole"
[ "$(metric "$work/killed/metrics.json" capture_holes)" -ge 1 ] || fail "(c) metrics.json has no hole"
echo "PASS: hostile input ratio $ratio; killed yaw_fusion continued; the 3 s capture hole is reported"
