#!/usr/bin/env bash
# launch_scripts/fly.sh on a profile file that is not in the repository: it
# simulates, replays in lockstep and evaluates it, the figures are bounded, the
# same flight twice gives the same metrics, and bad input stops with a message
# naming what is wrong before anything is flown.
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
fly() { "$root/launch_scripts/fly.sh" --no-setup "$@"; }

# A profile of our own: at 150 m, a left turn, over steeper relief (its first 24 s: 600 m).
cat >"$work/hill_turn.yaml" <<'YAML'
name: hill_turn
distance_m: 1200
speed_mps: 25
altitude_agl_m: 150
initial_heading_deg: 45
pitch_trim_deg: -1.0
oscillation: {roll_deg: 0.5, pitch_deg: 0.5, yaw_deg: 0.3}
reference: {latitude_deg: 47.0, longitude_deg: 8.0, height_m: 500.0}
terrain: {relief_scale: 1.5}
legs:
  - {type: straight, distance_m: 250}
  - {type: turn, angle_deg: -45, bank_deg: 10}
  - {type: straight}
YAML

for run in 1 2; do
  fly --profile "$work/hill_turn.yaml" --seed 7 --duration 24 --out "$work/run$run" --json >"$work/run$run.json" 2>"$work/run$run.err" ||
    { cat "$work/run$run.err"; fail "fly.sh run $run failed"; }
done
/usr/bin/python3 - "$work" <<'PY' || fail "the metrics are not what a flown profile gives"
import json, sys
w = sys.argv[1]
a, b = (json.load(open(f"{w}/run{i}.json")) for i in (1, 2))
assert a == b, "two flights of the same profile and seed differ"
assert 570 < a["distance_m"] < 610, a["distance_m"]
assert a["error_pct_h"] < 0.5, a["error_pct_h"]
print(f"distance {a['distance_m']:.1f} m, horizontal {a['error_pct_h']:.3f} % of distance")
PY
[ -s "$work/run1/sim.lcmlog" ] || fail "no simulator log kept"
[ ! -e "$work/run1/replay.lcmlog" ] || fail "the replay log was kept without --keep-replay"
[ -s "$work/run1/report/summary.txt" ] && [ -s "$work/run1/report/trajectory.png" ] || fail "no report"
grep -q "hill_turn" "$work/run1.err" || fail "progress does not name the profile"

# A named profile, a sensor set, an outage, an overlay, shorter, the replay kept, the summary printed.
printf 'tracker:\n  features_per_cell: 30\n  replenish_below: 27\n' >"$work/fewer.yaml"
fly --profile demo --seed 3 --duration 6 --sensor-set realistic --outage altimeter:2:1 --config-overlay "$work/fewer.yaml" \
  --keep-replay --out "$work/named" >"$work/named.txt" 2>&1 || { cat "$work/named.txt"; fail "fly.sh with options failed"; }
grep -q "^=== nadir fly: demo, seed 3 ===" "$work/named.txt" || fail "no summary header"
grep -q "^distance flown" "$work/named.txt" || fail "no summary"
[ -s "$work/named/replay.lcmlog" ] || fail "--keep-replay did not keep the replay"
# The overlay reached the tracker: about 9 x 30 tracks a frame, not the default's ~450.
most=$(nadir_log dump "$work/named/replay.lcmlog" TRACKS 2>/dev/null | awk -F, 'NR > 1 { n[$1]++ } END { m = 0; for (k in n) if (n[k] > m) m = n[k]; print m }')
((most > 100 && most < 330)) || fail "the overlay did not reach the replay: up to $most tracks a frame"
grep -q "sim_sensors.yaml:realistic" "$work/named.txt" || fail "the sensor set did not reach the simulator"

# Bad input: exit 2, the message names it, nothing flown.
expect_refused() {
  local what="$1" pattern="$2"; shift 2
  local out
  out="$(fly "$@" --out "$work/refused" 2>&1)"; local rc=$?
  [ "$rc" = 2 ] || { echo "$out"; fail "$what: exit $rc, not 2"; }
  grep -q -- "$pattern" <<<"$out" || { echo "$out"; fail "$what: the message does not name it"; }
  [ ! -e "$work/refused/sim.lcmlog" ] || fail "$what: flown anyway"
}
expect_refused "no profile" "--profile NAME|FILE is required"
expect_refused "unknown profile" "no such profile" --profile no_such_profile
expect_refused "missing file" "no_such.yaml: no such file" --profile "$work/no_such.yaml"
expect_refused "bad seed" "got 'seven'" --profile demo --seed seven
expect_refused "unknown option" "unknown option --sped" --profile demo --sped 3
expect_refused "missing overlay" "missing.yaml: no such file" --profile demo --config-overlay "$work/missing.yaml"
printf 'yaw_fusion:\n  gate_sigmaz: 3\n' >"$work/misspelt.yaml"
expect_refused "misspelt overlay key" "yaw_fusion.gate_sigmaz" --profile demo --config-overlay "$work/misspelt.yaml"
echo "PASS: fly.sh flew a profile file twice with identical metrics; options reach the simulator and replay; bad input refused"
