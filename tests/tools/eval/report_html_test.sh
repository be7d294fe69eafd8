#!/usr/bin/env bash
# nadir_eval's HTML report (report/index.html) opened in headless Chromium:
# the script ran to its end (body data-rendered="ok"), the trajectory, error,
# protection-level and yaw plots have their curves, a short coast is shaded in
# them and counted in the key figures, the key figures, process
# and pair tables their rows, no console message from the page (errors, warnings,
# failed requests), and the page references nothing outside itself. A page
# with a deliberate error checks that the console check sees errors.
# Usage: report_html_test.sh [SCREENSHOT.png]  (also writes a screenshot)
set -uo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
source "$root/launch_scripts/common.sh"
fail() { echo "FAIL: $*"; exit 1; }
command -v chromium >/dev/null || fail "chromium is not installed (launch_scripts/setup.sh --tests installs it)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
shot="${1:-}"

# 2 s of featureless ground from 6 s: a coast, shaded in the plots and counted in the key figures.
nadir_sim --profile demo --seed 2 --duration 12 --outage texture:6:2:0.03 --out "$work/sim.lcmlog" >/dev/null ||
  fail "nadir_sim failed"
nadir_replay --in "$work/sim.lcmlog" --out "$work/flight.lcmlog" --nodes tracker,vo_solver,yaw_fusion >/dev/null ||
  fail "nadir_replay failed"
nadir_eval --log "$work/flight.lcmlog" --out "$work/report" --no-plots >/dev/null || fail "nadir_eval failed"
page="$work/report/index.html"
[ -s "$page" ] || fail "no $page"

browse() {  # FILE DOM_OUT CONSOLE_OUT
  timeout 120 chromium --headless --disable-gpu --no-sandbox --user-data-dir="$work/profile" \
    --enable-logging=stderr --v=0 --dump-dom "file://$1" >"$2" 2>"$3" || fail "chromium failed on $1"
}
printf '<html><body><script>console.error("deliberate"); notDefined();</script></body></html>' >"$work/bad.html"
browse "$work/bad.html" "$work/bad.dom" "$work/bad.console"
[ "$(grep ':CONSOLE' "$work/bad.console" | grep -vc 'source: chrome://')" -ge 2 ] ||
  fail "the console check does not see a page's errors"

browse "$page" "$work/dom.html" "$work/console.txt"
# Chromium's own pages (chrome://, e.g. its "slow network" font notice on a
# loaded machine) are not the report's: only messages from the page count.
grep ':CONSOLE' "$work/console.txt" | grep -v 'source: chrome://' &&
  fail "console messages while rendering the report (above)"
/usr/bin/python3 - "$work/dom.html" "$page" <<'PY' || exit 1
import re, sys
dom, src = open(sys.argv[1]).read(), open(sys.argv[2]).read()
problems = []
def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok: problems.append(what)
check('data-rendered="ok"' in dom, "the page's script ran to its end")
def svg(i):
    m = re.search(r'<svg id="%s".*?</svg>' % i, dom, re.S)
    return m.group(0) if m else ""
for i, n in (("trajectory", 2), ("errors", 7), ("protection", 2), ("yaw", 3)):
    paths = re.findall(r'<path d="M[^"]{200,}"', svg(i))
    check(len(paths) >= n, f"plot {i}: {len(paths)} curves (>= {n})")
check('class="series truth"' in svg("trajectory") and 'class="series estimate"' in svg("trajectory"), "trajectory: truth and estimate")
check(len(re.findall(r'class="fig"', dom)) >= 8, "key figures")
coast = re.findall(r'<rect[^>]*class="coast"', dom)
check(len(coast) >= 3, f"the coast shaded in the error, protection-level and yaw plots ({len(coast)} spans)")
check(re.search(r'<b>[0-9.]+ s in 1 episode</b><span>coasting:', dom) is not None, "key figure: coasting, 1 episode")
procs = re.search(r'<table id="processes">.*?</table>', dom, re.S).group(0)
check(len(re.findall(r"<tr", procs)) >= 4, f"process table: {len(re.findall(r'<tr', procs)) - 1} processes")
pairs = re.search(r'<table id="pairs">.*?</table>', dom, re.S).group(0)
check(len(re.findall(r"<tr", pairs)) > 100, f"pair table: {len(re.findall(r'<tr', pairs)) - 1} pairs")
external = re.findall(r'(?:src|href)="(https?:[^"]*)"', src)
check(not external, f"nothing loaded from outside the page ({external[:3]})")
sys.exit(1 if problems else 0)
PY
if [ -n "$shot" ]; then
  timeout 120 chromium --headless --disable-gpu --no-sandbox --user-data-dir="$work/profile" --hide-scrollbars \
    --window-size=1400,1500 --screenshot="$shot" "file://$page" 2>/dev/null || fail "no screenshot"
  echo "screenshot: $shot"
fi
echo PASS
