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
echo "PASS: killed process restarted ($first -> $second); set stopped cleanly"
