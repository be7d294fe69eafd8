#!/usr/bin/env bash
# The coasting on real simulated flights (rough_120: relief 3, level
# for the first 15 s, then a 40 m climb to 45 s; seed 1), through nadir_replay
# (tracker, vo_solver, yaw_fusion) and nadir_eval.
#   coasting_test.sh altimeter: the same 45 s flight with and without a 10 s
#     altimeter outage from 25 s (in the climb). Criterion: final 3-D error with the outage
#     <= 3 x the final 3-D error without it (the added error is printed); the
#     reported horizontal sigma covers the true error at the end of the outage
#     (error_h <= 3 sigma_h, sigma_h = sqrt(var_n + var_e)); the outage's poses
#     are flagged coasting and none 2 s after it; no jump when VO resumes;
#     the clean flight never coasts (the detectors' thresholds).
#   coasting_test.sh texture: a 25 s flight with a 10 s texture outage
#     (contrast 0.03) from 3.5 s (level flight: without VO nothing measures a
#     climb over rough ground, the climb rate is held): coasting flagged, no
#     vertical excursion (the vertical error moves less than 3 m; the coasting study saw
#     8 m in 1.5 s), every POSE field finite.
# Nothing is cached: the flights are simulated each run (short for that).
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
source "$root/launch_scripts/common.sh"
[ -n "${NADIR_BUILD:-}" ] && export PATH="$NADIR_BUILD/bin:$PATH"
export PATH="$root/build/bin:$PATH"
mode="${1:-altimeter}"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
seed="${NADIR_COASTING_SEED:-1}"
duration=45
outage_start=25
outage_s=10
if [ "$mode" = texture ]; then duration=25; outage_start=3.5; fi

# fly NAME [nadir_sim options...]: simulate, replay, evaluate into $work/NAME/
fly() {
  local name="$1"; shift
  local dir="$work/$name"
  mkdir -p "$dir"
  nadir_sim --profile rough_120 --seed "$seed" --duration "$duration" --out "$dir/sim.lcmlog" "$@" \
    >"$dir/sim.txt" 2>&1 || { cat "$dir/sim.txt"; fail "($name) nadir_sim failed"; }
  nadir_replay --in "$dir/sim.lcmlog" --out "$dir/replay.lcmlog" --nodes tracker,vo_solver,yaw_fusion --json \
    >"$dir/replay.json" 2>"$dir/replay.txt" || { cat "$dir/replay.txt"; fail "($name) nadir_replay failed"; }
  rm -f "$dir/sim.lcmlog"
  nadir_eval --log "$dir/replay.lcmlog" --out "$dir/eval" --json --no-plots >"$dir/metrics.json" \
    2>"$dir/eval.txt" || { cat "$dir/eval.txt"; fail "($name) nadir_eval failed"; }
  nadir_log dump "$dir/replay.lcmlog" POSE -o "$dir/pose.csv" || fail "($name) nadir_log dump failed"
  rm -f "$dir/replay.lcmlog"
}

case "$mode" in
  altimeter)
    fly clean
    fly outage --outage "altimeter:$outage_start:$outage_s"
    ;;
  texture)
    fly outage --outage "texture:$outage_start:$outage_s:0.03"
    ;;
  *) fail "mode must be altimeter or texture, not '$mode'" ;;
esac

PYTHONDONTWRITEBYTECODE=1 PYTHONPATH="$root/tests/integration" python3 - "$work" "$mode" "$outage_start" "$outage_s" <<'PY'
import csv, json, math, sys
work, mode, start, length = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
end = start + length
COASTING, VO_GAP = 16, 1
from checklist import check, failures

def series(name):
    with open(f"{work}/{name}/eval/series.csv") as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]

def metrics(name):
    return json.load(open(f"{work}/{name}/metrics.json"))

def poses_finite(name):
    with open(f"{work}/{name}/pose.csv") as f:
        rows = list(csv.DictReader(f))
    bad = [r["utime"] for r in rows if not all(math.isfinite(float(v)) for k, v in r.items())]
    return len(rows), bad

s = series("outage")
m = metrics("outage")
inside = [r for r in s if start + 0.5 <= r["t_s"] <= end]
coasting = sum(1 for r in inside if int(r["flags"]) & COASTING)
check(len(inside) > 100 and coasting >= 0.8 * len(inside),
      f"{coasting} of {len(inside)} poses in the outage flagged coasting")
after = [r for r in s if r["t_s"] >= end + 2.0]
check(after and not any(int(r["flags"]) & COASTING for r in after),
      f"no coasting flag from 2 s after the outage on ({len(after)} poses)")
# No jump at the transitions: every step between poses is within 2 m of the true step.
jumps = []
for a, b in zip(s, s[1:]):
    if start - 1.0 <= a["t_s"] <= end + 3.0:
        est = math.dist((a["est_n"], a["est_e"], a["est_d"]), (b["est_n"], b["est_e"], b["est_d"]))
        true = math.dist((a["true_n"], a["true_e"], a["true_d"]), (b["true_n"], b["true_e"], b["true_d"]))
        jumps.append(abs(est - true))
check(jumps and max(jumps) < 2.0, f"largest pose step error around the outage {max(jumps or [0]):.2f} m (< 2 m)")
n, bad = poses_finite("outage")
check(not bad, f"all fields of {n} POSE messages finite")

if mode == "altimeter":
    c = metrics("clean")
    clean_coasting = sum(1 for r in series("clean") if int(r["flags"]) & COASTING)
    check(clean_coasting == 0, f"the clean flight never coasts ({clean_coasting} poses flagged)")
    e_clean, e_out = c["final_error_3d_m"], m["final_error_3d_m"]
    print(f"final 3-D error: {e_clean:.2f} m without the outage, {e_out:.2f} m with it "
          f"(added {e_out - e_clean:.2f} m; {m['error_pct_3d']:.3f} % vs {c['error_pct_3d']:.3f} %)")
    check(e_out <= 3.0 * e_clean, f"final error with the outage {e_out:.2f} m <= 3 x {e_clean:.2f} m")
    last = [r for r in s if r["t_s"] <= end][-1]
    check(last["error_h_m"] <= 3.0 * last["sigma_h_m"],
          f"at the end of the outage (t {last['t_s']:.2f} s) error_h {last['error_h_m']:.2f} m <= "
          f"3 sigma_h = {3.0 * last['sigma_h_m']:.2f} m")
else:
    window = [r for r in s if start <= r["t_s"] <= end + 3.0]
    before = [r for r in s if r["t_s"] < start][-1]
    excursion = max(abs(r["error_v_m"] - before["error_v_m"]) for r in window)
    check(excursion < 3.0, f"vertical error moved {excursion:.2f} m over the texture outage (< 3 m)")
sys.exit(1 if failures else 0)
PY
