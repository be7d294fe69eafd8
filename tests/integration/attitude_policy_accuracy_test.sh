#!/usr/bin/env bash
# What the `propagate` attitude policy itself does to the estimate,
# on a Table 1 profile (test3, seed 103, its first 40 s) with the INS's
# per-sample white noise switched off, so that both policies see the same
# attitude signal and only the method differs. The simulated flight is
# replayed (tracker, vo_solver, yaw_fusion) once with each policy.
# Criteria: every POSE position of the two replays within 15 mm of each other
# (and the final 3-D errors within 0.0005 % of the distance, a tenth of the
# issue's bound); the replays do differ (the setting took effect). The
# uncertainty models weigh each frame's INS attitude by the share of the INS's
# white noise its policy leaves in it (1/2 propagated, 1/2 to 1 interpolated),
# so the two weigh the INS yaw differently by design: 9 mm at most here
# (under 5 mm before the shares were counted).
# With the white noise on, the difference is the noise draw, not the method:
# README § Latency, "Many flights".
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
[ -n "${NADIR_BUILD:-}" ] && export PATH="$NADIR_BUILD/bin:$PATH"
export PATH="$root/build/bin:$PATH"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

nadir_sim --profile test3 --seed 103 --duration 40 --roll-pitch-noise-deg 0 --yaw-noise-deg 0 \
  --out "$work/sim.lcmlog" >"$work/sim.txt" 2>&1 || { cat "$work/sim.txt"; fail "nadir_sim failed"; }
for policy in interpolate propagate; do
  dir="$work/$policy"
  mkdir -p "$dir"
  nadir_replay --in "$work/sim.lcmlog" --out "$dir/replay.lcmlog" --nodes tracker,vo_solver,yaw_fusion --json \
    --set vo_solver.sync.attitude_policy=$policy --set yaw_fusion.attitude_policy=$policy \
    >"$dir/replay.json" 2>"$dir/replay.txt" || { cat "$dir/replay.txt"; fail "($policy) nadir_replay failed"; }
  nadir_eval --log "$dir/replay.lcmlog" --out "$dir/eval" --json --no-plots >"$dir/metrics.json" \
    2>"$dir/eval.txt" || { cat "$dir/eval.txt"; fail "($policy) nadir_eval failed"; }
  nadir_log dump "$dir/replay.lcmlog" POSE -o "$dir/pose.csv" || fail "($policy) nadir_log dump failed"
done

PYTHONDONTWRITEBYTECODE=1 PYTHONPATH="$root/tests/integration" /usr/bin/python3 - "$work" <<'PY'
import csv, json, math, sys
work = sys.argv[1]
from checklist import check, failures

def poses(policy):
    with open(f"{work}/{policy}/pose.csv") as f:
        return {int(r["utime"]): [float(r[k]) for k in ("north", "east", "down")] for r in csv.DictReader(f)}

a, b = poses("interpolate"), poses("propagate")
# The flight's last frame has no INS sample after it in the log: interpolate
# cannot solve it, propagate can (it needs none). Nothing else may differ.
extra = sorted(set(b) - set(a))
check(len(a) > 500 and set(a) <= set(b) and len(extra) <= 1 and all(t > max(a) for t in extra),
      f"the same {len(a)} POSE times (propagate {len(b)}: {len(extra)} more after the last interpolated frame)")
common = sorted(set(a) & set(b))
gaps = [math.dist(a[t], b[t]) for t in common]
worst = max(gaps, default=float("inf"))
check(worst < 0.015, f"largest position difference between the policies {worst * 1e3:.3f} mm (< 15 mm)")
check(worst > 0.0, "the policies differ at all (the setting took effect)")
m = {p: json.load(open(f"{work}/{p}/metrics.json")) for p in ("interpolate", "propagate")}
d = m["propagate"]["error_pct_3d"] - m["interpolate"]["error_pct_3d"]
check(abs(d) < 0.0005, f"final 3-D error {m['interpolate']['error_pct_3d']:.5f} % (interpolate) and "
      f"{m['propagate']['error_pct_3d']:.5f} % (propagate) of {m['interpolate']['distance_m']:.0f} m: "
      f"difference {d:+.6f} points (< 0.0005)")
sys.exit(1 if failures else 0)
PY
