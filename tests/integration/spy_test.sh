#!/usr/bin/env bash
# spy.sh starts under xvfb-run, finds every nadir type in the generated jar and
# throws no exception in 8 s.
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
expected=$(ls "$root"/lcmtypes/*.lcm | wc -l)
out="$(mktemp)"
timeout 8 xvfb-run -a "$root/launch_scripts/spy.sh" --lcm-url memq:// >"$out" 2>&1
rc=$?
cat "$out"
[ "$rc" -eq 124 ] || { echo "FAIL: spy exited early with $rc (expected to run until the timeout)"; exit 1; }
grep -q "Found $expected LCM types" "$out" || { echo "FAIL: expected 'Found $expected LCM types'"; exit 1; }
if grep -qiE 'exception|error' "$out"; then echo "FAIL: exception in lcm-spy output"; exit 1; fi
echo "PASS: lcm-spy loaded $expected nadir types"
