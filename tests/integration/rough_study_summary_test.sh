#!/usr/bin/env bash
# rough_study_summary.py: the ratio of the mean errors, the median ratio, the
# flights and three-seed runs within the goal, from known rows; a bootstrap
# interval that holds the ratio, lies between the per-seed ratios and is the
# same on a second run; two studies pooled; a flight given twice with two
# values, a bad number and a missing column are errors naming the file (and
# line) with exit 2, writing nothing.
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
tool="$root/studies/rough_ground/rough_study_summary.py"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
head='profile,seed,ground,variant,final_error_pct,final_error_m,distance_m'
# Seeds 1-3 in one study, seed 4 in another: rough 0.03 0.02 0.06 0.04, flat 0.02 0.02 0.03 0.04.
printf '%s\n' "$head" p,1,rough,fd,0.03,1.5,5000 p,1,flat,fd,0.02,1,5000 p,2,rough,fd,0.02,1,5000 \
  p,2,flat,fd,0.02,1,5000 p,3,rough,fd,0.06,3,5000 p,3,flat,fd,0.03,1.5,5000 >"$work/a.csv"
printf '%s\n' "$head" p,4,rough,fd,0.04,2,5000 p,4,flat,fd,0.04,2,5000 >"$work/b.csv"
"$tool" "$work/a.csv" "$work/b.csv" --out "$work/one" >"$work/one.md" || fail "exit $? on good rows"
"$tool" "$work/a.csv" "$work/b.csv" --out "$work/two" >/dev/null || fail "exit $? on the second run"
cmp -s "$work/one/summary.json" "$work/two/summary.json" || fail "two runs over the same rows differ"
/usr/bin/python3 - "$work/one/summary.json" <<'PY' || fail "summary figures"
import json, sys
s = json.load(open(sys.argv[1]))
(o,) = s["overall"]
def near(a, b): return abs(a - b) < 1e-12
assert o["seeds"] == [1, 2, 3, 4], o["seeds"]
assert near(o["mean_rough_pct"], 0.0375) and near(o["mean_flat_pct"], 0.0275), o
assert near(o["ratio_of_means"], 0.15 / 0.11), o["ratio_of_means"]
assert near(o["median_ratio"], 1.25), o["median_ratio"]  # ratios 1.5, 1, 2, 1
assert o["flights_within_goal"] == 3, o                    # 1.5 counts as within
assert [r["seeds"] for r in o["three_seed_runs"]] == [[1, 2, 3]], o["three_seed_runs"]
assert near(o["three_seed_runs"][0]["ratio"], 0.11 / 0.07) and o["three_seed_runs_within_goal"] == 0, o
lo, hi = o["ratio_interval"]
assert 1.0 <= lo < o["ratio_of_means"] < hi <= 2.0, (lo, hi)  # a ratio of sums lies between the ratios
assert [r["seed"] for r in s["per_seed"]] == [1, 2, 3, 4] and near(s["per_seed"][2]["ratio"], 2.0), s["per_seed"]
PY
row='| p | fd | 4 (1–4) | 0.0375 | 0.0275 | **1.36** ['
grep -qF "$row" "$work/one.md" || { cat "$work/one.md"; fail "markdown row"; }
echo "ok: $(grep -F "$row" "$work/one.md")"

# expect_error TEXT FILE...: exit 2, the message holds TEXT, nothing written.
expect_error() {
  local text="$1"; shift
  "$tool" "$@" --out "$work/bad" >"$work/err" 2>&1
  local rc=$?
  [ "$rc" = 2 ] || { cat "$work/err"; fail "exit $rc, expected 2 ($text)"; }
  grep -qF "$text" "$work/err" || { cat "$work/err"; fail "error does not say '$text'"; }
  [ ! -e "$work/bad" ] || fail "something was written ($text)"
  echo "ok: $(cat "$work/err")"
}
printf '%s\n' "$head" p,1,rough,fd,0.05,2.5,5000 >"$work/c.csv"
expect_error "$work/c.csv:2: ('p', 1, 'rough', 'fd') given twice" "$work/a.csv" "$work/c.csv"
printf '%s\n' "$head" p,1,rough,fd,abc,1,5000 >"$work/d.csv"
expect_error "$work/d.csv:2: bad seed or final_error_pct" "$work/d.csv"
printf '%s\n' "profile,seed,ground,variant" p,1,rough,fd >"$work/e.csv"
expect_error "$work/e.csv: no column final_error_pct" "$work/e.csv"
printf '%s\n' "$head" p,1,rough,fd,0.03,1.5,5000 >"$work/f.csv"
expect_error "no seed has both a rough and a flat flight" "$work/f.csv"
echo "PASS"
