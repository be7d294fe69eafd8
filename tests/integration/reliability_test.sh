#!/usr/bin/env bash
# Reliability of the live sim set (README "Reliability"), inside the private
# network namespace test.sh provides; the flights are launch_scripts/reliability.sh's:
#  (a) hostile: the demo flight with nadir_hostile publishing ~600 hostile
#      messages over 30 s among the real ones: no process dies, the final
#      error is within 1.2x of the clean flight, no POSE velocity is off by
#      more than 5 m/s;
#  (b) kill: yaw_fusion killed with SIGKILL mid-flight is restarted and
#      continues from its checkpoint (no pose back at the origin), within its
#      reported covariance;
#  (c) the same flight's capture, lcm-logger stopped for 3 s: the hole is
#      reported by nadir_log info and nadir_eval, and so are the messages the
#      publishers' STATUS counted that the capture lacks.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
export PATH="${NADIR_BUILD:-$root/build}/bin:$PATH"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
here="$(dirname "$0")"
metric() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }

"$root/launch_scripts/reliability.sh" --cases clean,hostile,kill --out "$work"
for c in clean hostile kill; do [ -s "$work/$c/metrics.json" ] || fail "$c: no evaluation (see $work/$c.txt)"; done

clean_pct="$(metric "$work/clean/metrics.json" error_pct_3d)"
hostile_pct="$(metric "$work/hostile/metrics.json" error_pct_3d)"
sent="$(metric "$work/hostile.hostile.json" sent)"
ratio="$(python3 -c "print(f'{$hostile_pct / $clean_pct:.3f}')")"
echo "(a) $sent hostile messages: final error $hostile_pct % against $clean_pct % clean, ratio $ratio"
python3 -c "import sys; sys.exit(0 if $hostile_pct <= 1.2 * $clean_pct else 1)" || fail "(a) ratio $ratio > 1.2"
python3 "$here/check_series.py" "$work/hostile/report/series.csv" --max-velocity-error 5 || fail "(a) velocity"
for c in clean hostile; do
  grep -q "\] [a-z_]* died (exit" "$work/$c.txt" && fail "($c) a process died"
done

grep -q "\[run_set\] yaw_fusion died" "$work/kill.txt" || { tail -20 "$work/kill.txt"; fail "(b) yaw_fusion was not killed and restarted"; }
# The kill comes ~28 s into the flight; the restarted process's first pose is flagged VO_GAP.
python3 "$here/check_series.py" "$work/kill/report/series.csv" --restart-after 20 || fail "(b) pose continuity"
echo "(b) yaw_fusion killed and restarted: final error $(metric "$work/kill/metrics.json" error_pct_3d) % (clean $clean_pct %)"

nadir_log info "$work/kill/capture.lcmlog" >"$work/kill/info.txt"
grep -E "^INS: no messages for [0-9.]+ s" "$work/kill/info.txt" || { cat "$work/kill/info.txt"; fail "(c) nadir_log info reports no hole"; }
grep -q "hole(s) in the capture" "$work/kill/eval_stderr.txt" || fail "(c) nadir_eval did not warn about the hole"
[ "$(metric "$work/kill/metrics.json" capture_holes)" -ge 1 ] || fail "(c) metrics.json has no hole"
# 3 s of the sim's 100 Hz INS alone is ~300 messages the logger never wrote.
grep -E "^INS: [0-9]+ of [0-9]+ published by sim missing from the capture" "$work/kill/info.txt" ||
  fail "(c) nadir_log info does not count the INS messages the capture lacks"
missing="$(metric "$work/kill/metrics.json" capture_missing)"
[ "$missing" -ge 200 ] || fail "(c) metrics.json capture_missing $missing < 200"
echo "(c) the stopped logger's hole and its $missing missing messages are reported"
echo "PASS: hostile input ratio $ratio; killed yaw_fusion continued; the 3 s capture hole is reported"
