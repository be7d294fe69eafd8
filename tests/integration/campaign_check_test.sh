#!/usr/bin/env bash
# nadir_campaign: a bad campaign file is an error naming the file and the key
# before anything runs; a failing cell is reported with its log and the rest
# still aggregates (the failed one listed as missing); a finished campaign is
# not run again; results of two code versions are not aggregated together
# unless --allow-mixed. Real cells: 6 s flights of test1.
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
export NADIR_BUILD="${NADIR_BUILD:-$root/build}"
tool="$NADIR_BUILD/bin/nadir_campaign"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
[ -x "$tool" ] || fail "$tool not built"

# expect_error FILE_BODY KEY: the tool refuses it, names the file and the key, and writes nothing.
expect_error() {
  local body="$1" key="$2" file="$work/bad.yaml"
  printf '%s\n' "$body" >"$file"
  "$tool" run --local "$file" --out "$work/bad_out" >"$work/err" 2>&1
  local rc=$?
  [ "$rc" = 2 ] || { cat "$work/err"; fail "exit $rc for a bad file (key $key), expected 2"; }
  grep -qF "$file: key '$key'" "$work/err" || { cat "$work/err"; fail "error does not name $file and key '$key'"; }
  [ ! -e "$work/bad_out" ] || fail "something was written for a bad file (key $key)"
  echo "ok: $(cat "$work/err")"
}
good='name: t
profiles: [test1]
seeds: [1]'
expect_error "$good
colour: blue" colour
expect_error "name: t
profiles: [test1, test9]
seeds: [1]" "profiles[1]"
expect_error "name: t
profiles: [test1]
seeds: []" seeds
expect_error "$good
sensor_sets: [standard, noisy]" "sensor_sets[1]"
expect_error "$good
variants: {fast: {vo_solver.no_such_key: 1}}" "variants.fast.vo_solver.no_such_key"
expect_error "$good
sim: {duration: 20}" sim.duration
# A misspelt key names the nearest known one.
expect_error "$good
sim: {duraton_s: 20}" sim.duraton_s
grep -qF "did you mean sim.duration_s?" "$work/err" || fail "no suggestion for sim.duraton_s"
expect_error "$good
variants: {v: {vo_solver.min_featurs: 3}}" "variants.v.vo_solver.min_featurs"
grep -qF "did you mean variants.v.vo_solver.min_features?" "$work/err" || fail "no suggestion for min_featurs"
expect_error "$good
config_overlays: [no_such_calibration.yaml]" "config_overlays[0]"
printf 'just text\n' >"$work/not_a_map.yaml"
expect_error "$good
config_overlays: [not_a_map.yaml]" "config_overlays[0]"

# A config overlay (a calibration.yaml) reaches every cell's replay: one the tracker refuses
# fails the cell, and the log names the overlay and the key.
printf 'tracker:\n  grid_cols: 0\n' >"$work/overlay.yaml"
printf 'name: overlay\nprofiles: [test1]\nseeds: [7]\nsim: {duration_s: 2}\nconfig_overlays: [overlay.yaml]\n' >"$work/o.yaml"
"$tool" plan "$work/o.yaml" --out "$work/o_out" >"$work/plan" 2>&1 || { cat "$work/plan"; fail "plan with an overlay"; }
grep -qF "config overlay $work/overlay.yaml (sha256" "$work/plan" || { cat "$work/plan"; fail "plan does not list the overlay"; }
"$tool" run --local "$work/o.yaml" --out "$work/o_out" >"$work/orun" 2>&1
[ "$?" = 1 ] || { cat "$work/orun"; fail "a cell replayed with grid_cols 0 from the overlay did not fail"; }
olog="$work/o_out/cells/test1_standard_default_seed7/cell.log"
grep -qF -- "--config-overlay $work/overlay.yaml" "$olog" || { cat "$olog"; fail "the replay was not given the overlay"; }
grep -qF "grid_cols" "$olog" || { cat "$olog"; fail "the overlay's key did not reach the tracker"; }
echo "ok: the overlay reaches the replay"

# A campaign whose second variant cannot run (tracker.grid_cols 0 is refused by the tracker).
cat >"$work/c.yaml" <<'YAML'
name: check
profiles: [test1]
seeds: [7]
variants:
  default: {}
  broken: {tracker.grid_cols: 0}
sim: {duration_s: 6}
evaluate: {bootstrap_samples: 200}
YAML
out="$work/out"
"$tool" run --local -j 2 "$work/c.yaml" --out "$out" >"$work/run1" 2>&1
rc=$?
cat "$work/run1"
[ "$rc" = 1 ] || fail "a failed cell must make run exit 1 (got $rc)"
log="$out/cells/test1_standard_broken_seed7/cell.log"
grep -qF "test1_standard_broken_seed7: FAILED, log $log" "$work/run1" || fail "the failed cell's log is not named"
[ -s "$log" ] || fail "no log at $log"
"$tool" status "$work/c.yaml" --out "$out" >"$work/status" 2>&1 || fail "status failed"
grep -qF "1 done, 1 failed" "$work/status" || { cat "$work/status"; fail "status does not count 1 done, 1 failed"; }
grep -qF "log $log" "$work/status" || { cat "$work/status"; fail "status does not name the failed cell's log"; }

"$tool" aggregate "$work/c.yaml" --out "$out" >"$work/agg" 2>&1 || { cat "$work/agg"; fail "aggregate failed"; }
cat "$work/agg"
grep -qE '^\| test1 \| standard \| default \| 1/1 \| 0 \| [0-9.]+ \[' "$work/agg" || fail "no row for the good cell"
grep -qE '^\| test1 \| standard \| broken \| 0/1 \|' "$work/agg" || fail "no row for the failed cell"
grep -qF "missing test1_standard_broken_seed7 (failed), log $log" "$work/agg" || fail "missing cell not reported"
[ -s "$out/aggregate/distribution.png" ] || fail "no distribution.png"
/usr/bin/python3 - "$out/aggregate/aggregate.json" <<'PY' || fail "aggregate.json"
import json, sys
agg = json.load(open(sys.argv[1]))
g = {x["variant"]: x for x in agg["groups"]}
assert g["default"]["metrics"]["error_pct_3d"]["n"] == 1, g
assert g["broken"]["missing_cells"] == ["test1_standard_broken_seed7"], g
assert agg["missing"][0]["state"] == "failed", agg["missing"]
PY

# Resumable: the done cell is not run again, the failed one is.
"$tool" run --local "$work/c.yaml" --out "$out" >"$work/run2" 2>&1
grep -qF "1 of 2 cells done, running 1" "$work/run2" || { cat "$work/run2"; fail "run is not resumable"; }

# Two code versions: the good cell's result stands in for the broken cell too, from another version.
/usr/bin/python3 - "$out/cells" <<'PY'
import json, os, sys
cells = sys.argv[1]
r = json.load(open(os.path.join(cells, "test1_standard_default_seed7", "result.json")))
r.update(cell="test1_standard_broken_seed7", code_version={**r["code_version"], "version": "v0-other"})
r["params"].update(variant="broken", config_overrides={"tracker.grid_cols": 0})
os.remove(os.path.join(cells, "test1_standard_broken_seed7", "failed.json"))
json.dump(r, open(os.path.join(cells, "test1_standard_broken_seed7", "result.json"), "w"))
PY
"$tool" aggregate "$work/c.yaml" --out "$out" --no-plot >"$work/mixed" 2>&1
rc=$?
[ "$rc" = 1 ] || { cat "$work/mixed"; fail "mixed versions aggregated (exit $rc)"; }
grep -qF "results from 2 code versions" "$work/mixed" || { cat "$work/mixed"; fail "mixed versions not named"; }
cat "$work/mixed"
"$tool" aggregate "$work/c.yaml" --out "$out" --no-plot --allow-mixed >"$work/mixed2" 2>&1 ||
  { cat "$work/mixed2"; fail "--allow-mixed refused"; }
"$tool" --help >/dev/null || fail "--help"
echo "PASS"
