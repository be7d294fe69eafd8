#!/usr/bin/env bash
# run_set.sh restarts a process that is killed and stops the whole set
# cleanly on SIGTERM. The set runs real nadir processes (nadir_status on a
# memq bus: long-running, no traffic).
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cat >"$work/test_set" <<'SET'
require nadir_status the status monitor
run     monitor_a   nadir_status --lcm-url memq://
run     monitor_b   nadir_status --lcm-url memq://
SET
"$root/launch_scripts/run_set.sh" "$work/test_set" --no-capture >"$work/out" 2>&1 &
set_pid=$!
pid_of() { grep -oE "started $1 \(pid [0-9]+\)" "$work/out" | tail -1 | grep -oE '[0-9]+\)' | tr -d ')'; }
for _ in $(seq 50); do [ -n "$(pid_of monitor_b)" ] && break; sleep 0.1; done
first=$(pid_of monitor_a)
[ -n "$first" ] || { cat "$work/out"; echo "FAIL: monitor_a did not start"; exit 1; }
kill -KILL "$first"
for _ in $(seq 60); do
  second=$(pid_of monitor_a)
  [ -n "$second" ] && [ "$second" != "$first" ] && break
  sleep 0.1
done
[ "$second" != "$first" ] || { cat "$work/out"; echo "FAIL: monitor_a was not restarted"; exit 1; }
kill -0 "$second" || { cat "$work/out"; echo "FAIL: restarted monitor_a is not running"; exit 1; }
b=$(pid_of monitor_b)
kill -TERM "$set_pid"
wait "$set_pid"; rc=$?
cat "$work/out"
[ "$rc" -eq 0 ] || { echo "FAIL: run_set exited $rc on SIGTERM"; exit 1; }
for p in "$second" "$b"; do
  if kill -0 "$p" 2>/dev/null; then echo "FAIL: process $p still running after the set stopped"; exit 1; fi
done
grep -q "monitor_a died" "$work/out" || { echo "FAIL: the death was not reported"; exit 1; }
grep -q "set 'test_set' stopped" "$work/out" || { echo "FAIL: no clean stop message"; exit 1; }

# A set that asks for real-time priority: printed for the units, taken where
# SCHED_FIFO is granted, a note and ordinary scheduling where it is not;
# --rt-priority off declines, a bad priority is refused naming the line.
cat >"$work/rt_set" <<'SET'
realtime 20
run     monitor   nadir_status --lcm-url memq://
SET
printed="$("$root/launch_scripts/run_set.sh" "$work/rt_set" --print-commands)"
grep -qx "realtime 20" <<<"$printed" || { echo "FAIL: --print-commands does not carry the set's realtime line"; exit 1; }
printed="$("$root/launch_scripts/run_set.sh" "$work/rt_set" --print-commands --rt-priority off)"
! grep -q realtime <<<"$printed" || { echo "FAIL: --rt-priority off still prints realtime"; exit 1; }
"$root/launch_scripts/run_set.sh" "$work/rt_set" --no-capture --duration 1 >"$work/rt_out" 2>&1 ||
  { cat "$work/rt_out"; echo "FAIL: the realtime set did not run"; exit 1; }
if chrt -f 20 true 2>/dev/null; then
  grep -q "runs its processes at real-time priority 20" "$work/rt_out" ||
    { cat "$work/rt_out"; echo "FAIL: SCHED_FIFO granted but not taken"; exit 1; }
  rt_case="granted"
else
  grep -q "asks for real-time priority 20 (SCHED_FIFO), which this machine refuses" "$work/rt_out" ||
    { cat "$work/rt_out"; echo "FAIL: no note that real-time priority was refused"; exit 1; }
  rt_case="refused, with a note"
fi
grep -q "started monitor" "$work/rt_out" || { cat "$work/rt_out"; echo "FAIL: monitor not started"; exit 1; }
"$root/launch_scripts/run_set.sh" "$work/rt_set" --no-capture --duration 1 --rt-priority off >"$work/rt_off" 2>&1
! grep -q "real-time" "$work/rt_off" || { cat "$work/rt_off"; echo "FAIL: --rt-priority off still asks"; exit 1; }
printf 'realtime 99\nrun monitor nadir_status --lcm-url memq://\n' >"$work/bad_rt_set"
out="$("$root/launch_scripts/run_set.sh" "$work/bad_rt_set" --print-commands 2>&1)" &&
  { echo "FAIL: realtime 99 accepted"; exit 1; }
echo "$out" | grep -q "bad_rt_set:1: 'realtime 99'" || { echo "FAIL: unclear message: $out"; exit 1; }
echo "PASS: killed process restarted ($first -> $second); set stopped cleanly; realtime set: $rt_case"
