#!/usr/bin/env bash
# A set whose drivers are not built fails at once, naming what is missing.
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
printf 'require nadir_no_such_driver the missing driver\nrun x nadir_status --lcm-url memq://\n' >"$work/needs_driver"
out="$("$root/launch_scripts/run_set.sh" "$work/needs_driver" --no-capture 2>&1)"; rc=$?
echo "$out"
[ "$rc" -eq 3 ] || { echo "FAIL: expected exit 3, got $rc"; exit 1; }
echo "$out" | grep -q "needs nadir_no_such_driver (the missing driver)" || { echo "FAIL: message does not name it"; exit 1; }
echo "PASS"
