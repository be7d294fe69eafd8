#!/usr/bin/env bash
# nadir_campaign on a real Slurm: starts the single-node cluster of
# launch_scripts/slurm_local.sh, submits config/campaigns/test_small.yaml
# (2 profiles x 3 seeds, 20 s flights) as a job array with its aggregation
# job, waits, then runs the same campaign with run --local: the aggregated
# numbers and every cell's metrics must be identical. Skips (exit 77) only
# where Slurm cannot start here: its Debian packages missing.
#
# Inside nadir_in_netns (a user namespace that forbids setgroups, a network
# namespace with only loopback) the daemons cannot run as root: Slurm drops
# supplementary groups when it is root. So there the test re-runs itself in a
# nested user namespace as 'nobody' (the same real user), and first gives lo a
# non-loopback address, without which getaddrinfo(AI_ADDRCONFIG) finds no
# IPv4 address for slurmctld to listen on.
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
export NADIR_BUILD="${NADIR_BUILD:-$root/build}"
tool="$NADIR_BUILD/bin/nadir_campaign"
fail() { echo "FAIL: $*"; exit 1; }

for t in munged slurmctld slurmd sbatch; do
  command -v "$t" >/dev/null ||
    { echo "SKIP: $t not installed (Debian slurm-wlm and munge; launch_scripts/setup.sh)"; exit 77; }
done
if [ "$(cat /proc/self/setgroups 2>/dev/null)" = deny ] && [ "$(id -u)" = 0 ] && [ -z "${NADIR_SLURM_NESTED:-}" ]; then
  [ "${NADIR_IN_NETNS:-0}" != 1 ] || ip addr add 10.254.254.1/32 dev lo 2>/dev/null || true
  exec unshare -U --map-user=65534 --map-group=65534 env NADIR_SLURM_NESTED=1 bash "$0" "$@"
fi
[ -x "$tool" ] || fail "$tool not built"

work="$(mktemp -d)"
# Ports of its own, free now (another one-node cluster on the machine, e.g.
# another checkout's test, must not be reached nor collided with), and its
# own state, spool and log folders under $work.
read -r ctld_port d_port < <(/usr/bin/python3 -c '
import socket
socks = [socket.socket() for _ in range(2)]
for s in socks: s.bind(("127.0.0.1", 0))
print(*(s.getsockname()[1] for s in socks))')
[ -n "$d_port" ] || fail "no free ports for the test cluster"
export NADIR_SLURM_DIR="$work/slurm" NADIR_SLURM_CTLD_PORT="$ctld_port" NADIR_SLURM_D_PORT="$d_port"
cleanup() {
  "$root/launch_scripts/slurm_local.sh" stop >/dev/null 2>&1
  rm -rf "$work"
}
trap cleanup EXIT
if ! "$root/launch_scripts/slurm_local.sh" start >"$work/start.log" 2>&1; then
  cat "$work/start.log"
  for f in "$NADIR_SLURM_DIR"/log/*.log; do echo "== $f"; tail -n 20 "$f"; done
  fail "the local Slurm cluster did not start"
fi
cat "$work/start.log"
eval "$("$root/launch_scripts/slurm_local.sh" env)"
campaign="$root/config/campaigns/test_small.yaml"

"$tool" submit --slurm "$campaign" --out "$work/slurm_run" >"$work/submit" 2>&1 ||
  { cat "$work/submit"; fail "submit"; }
cat "$work/submit"
read -r array_job agg_job < <(sed -n 's/^submitted //p' "$work/submit")
if [ -z "$agg_job" ] || [ "$array_job" = - ]; then fail "no job ids from submit"; fi
grep -qE '^#SBATCH --array=0-5%2$' "$work"/slurm_run/slurm/cells-*.sbatch || fail "array without its concurrency limit"
scontrol show job "$agg_job" | grep -qF "Dependency=afterok:$array_job" ||
  fail "aggregation job does not depend (afterok) on the array"

# Meanwhile, the same campaign on this machine.
"$tool" run --local -j 1 "$campaign" --out "$work/local_run" >"$work/local" 2>&1 ||
  { cat "$work/local"; fail "run --local"; }
"$tool" aggregate "$campaign" --out "$work/local_run" >"$work/local_agg" 2>&1 ||
  { cat "$work/local_agg"; fail "local aggregate"; }

for ((i = 0; i < 300; ++i)); do
  "$tool" status --wait "$campaign" --out "$work/slurm_run" >"$work/status" 2>&1 && break
  sleep 2
done
cat "$work/status"
grep -qF "6 done, 0 failed" "$work/status" || { cat "$work"/slurm_run/slurm/*.out; fail "not all Slurm cells done"; }
agg="$work/slurm_run/aggregate/aggregate.json"
[ -s "$agg" ] || { cat "$work"/slurm_run/slurm/*.out; fail "the aggregation job wrote no $agg"; }
cat "$work"/slurm_run/slurm/aggregate-*.out
/usr/bin/python3 - "$agg" "$work/local_run/aggregate/aggregate.json" "$work/slurm_run" "$work/local_run" <<'PY' ||
import json, os, sys
slurm, local = (json.load(open(p)) for p in sys.argv[1:3])
assert slurm["groups"] == local["groups"], "aggregated numbers differ between Slurm and --local"
assert slurm["code_versions"] == local["code_versions"], (slurm["code_versions"], local["code_versions"])
assert len(slurm["groups"]) == 2 and all(g["flights"] == 3 for g in slurm["groups"]), slurm["groups"]
cells = sorted(os.listdir(os.path.join(sys.argv[3], "cells")))
for c in cells:
    a, b = (json.load(open(os.path.join(d, "cells", c, "result.json"))) for d in sys.argv[3:5])
    for k in ("error_pct_3d", "rms_error_pct_3d", "final_error_3d_m", "poses", "distance_m"):
        assert a["metrics"][k] == b["metrics"][k], (c, k, a["metrics"][k], b["metrics"][k])
print(f"identical: {len(cells)} cells, {len(slurm['groups'])} groups")
PY
  fail "Slurm and --local results differ"
diff <(sed 1,2d "$work/slurm_run/aggregate/table.md") <(sed 1,2d "$work/local_run/aggregate/table.md") ||
  fail "tables differ"
cat "$work/local_run/aggregate/table.md"
echo "PASS"
