#!/usr/bin/env bash
# The working resolution's measurement: one photo folder imported at several
# scales (nadir_import --scale S), replayed (tracker, vo_solver, yaw_fusion)
# and evaluated; per scale the working size, pairs solved, per-pair error
# (median, p90), final error, and the wall time and peak memory of each step
# (/usr/bin/time). Prints a markdown table.
# Usage: resolution_sweep.sh --photos DIR --camera FILE [--skip-bad] SCALE [SCALE ...]
#        resolution_sweep.sh --sim12 [--interval S] [--count N] SCALE [SCALE ...]
#   --sim12: a simulated 12 MP survey (survey profile, seed 1, the 12 MP camera of
#   config/sim_camera_12mp.yaml) exported with --attitude ins, the first N photos.
#   SCALE: a number in (0, 1], or "auto" (the import's own rule).
# Results under logs/photo_resolution/<UTC>/.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../../launch_scripts/common.sh"
usage() { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; }
photos="" camera="" sim12=0 interval=2 count=0 import_extra=() scales=()
while (($#)); do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --photos) photos="$2"; shift 2 ;;
    --camera) camera="$2"; shift 2 ;;
    --skip-bad) import_extra+=(--skip-bad); shift ;;
    --sim12) sim12=1; shift ;;
    --interval) interval="$2"; shift 2 ;;
    --count) count="$2"; shift 2 ;;
    -*) echo "resolution_sweep: error: unknown option $1 (--help)" >&2; exit 2 ;;
    *) scales+=("$1"); shift ;;
  esac
done
[ ${#scales[@]} -gt 0 ] || { echo "resolution_sweep: error: give at least one SCALE (--help)" >&2; exit 2; }
[ "$sim12" = 1 ] || { [ -n "$photos" ] && [ -n "$camera" ]; } ||
  { echo "resolution_sweep: error: give --photos DIR --camera FILE, or --sim12 (--help)" >&2; exit 2; }
for tool in nadir_sim nadir_export nadir_import nadir_replay nadir_eval; do
  command -v "$tool" >/dev/null || { echo "resolution_sweep: error: $tool not built (launch_scripts/setup.sh)" >&2; exit 1; }
done
out="$NADIR_ROOT/logs/photo_resolution/$(nadir_utc_stamp)"
mkdir -p "$out"
if [ "$sim12" = 1 ]; then
  nadir_sim --profile survey --seed 1 --config-overlay "$NADIR_ROOT/config/sim_camera_12mp.yaml" \
    --out "$out/sim12.lcmlog" >"$out/sim.txt" 2>&1 || { cat "$out/sim.txt" >&2; exit 1; }
  nadir_export photos --in "$out/sim12.lcmlog" --out "$out/survey" --attitude ins --interval "$interval" \
    >/dev/null 2>"$out/export.txt" || { cat "$out/export.txt" >&2; exit 1; }
  rm -f "$out/sim12.lcmlog"   # ~12 MB a frame; the seed and the overlay reproduce it
  camera="$out/survey/camera.yaml"
  photos="$out/survey"
  if [ "$count" -gt 0 ]; then
    mkdir -p "$out/first"
    for f in $(ls "$out/survey"/*.JPG | head -n "$count"); do ln -s "$f" "$out/first/"; done
    photos="$out/first"
  fi
fi
timed() { local what="$1"; shift; /usr/bin/time -f "%e %M" -o "$dir/time_$what" "$@"; }
{
echo "| scale | working size | pairs solved | per-pair error median / p90 | final error | import s / MB | replay s / MB | eval s / MB |"
echo "|---|---|---|---|---|---|---|---|"
for s in "${scales[@]}"; do
  dir="$out/scale_$s"
  mkdir -p "$dir"
  scale_args=(); [ "$s" = auto ] || scale_args=(--scale "$s")
  timed import nadir_import --photos "$photos" --camera "$camera" "${scale_args[@]}" "${import_extra[@]}" \
    --out "$dir/flight" --json >"$dir/import.json" 2>"$dir/import.txt" || { cat "$dir/import.txt" >&2; exit 1; }
  timed replay nadir_replay --in "$dir/flight.lcmlog" --out "$dir/replay.lcmlog" \
    --nodes tracker,vo_solver,yaw_fusion --config "$dir/flight.yaml" --json >"$dir/replay.json" 2>"$dir/replay.txt" ||
    { tail "$dir/replay.txt" >&2; exit 1; }
  timed eval nadir_eval --log "$dir/replay.lcmlog" --out "$dir/report" --json >"$dir/metrics.json" \
    2>"$dir/eval.txt" || { tail "$dir/eval.txt" >&2; exit 1; }
  rm -f "$dir/flight.lcmlog" "$dir/replay.lcmlog"
  /usr/bin/python3 - "$dir" "$s" <<'PY'
import csv, json, statistics, sys
d, s = sys.argv[1], sys.argv[2]
cam = json.load(open(d + "/import.json"))["camera"]
m = json.load(open(d + "/metrics.json"))
rows = list(csv.DictReader(open(d + "/report/pairs.csv")))
errs = sorted(float(r["error_pct"]) for r in rows if r["solved"] == "1")
med = statistics.median(errs) if errs else float("nan")
p90 = errs[int(0.9 * (len(errs) - 1))] if errs else float("nan")
def t(what):
    sec, kb = open(f"{d}/time_{what}").read().split()[-2:]
    return f"{float(sec):.1f} / {int(kb) / 1024:.0f}"
print(f"| {s} ({cam['scale_rule']}) | {cam['width']}x{cam['height']} | {len(errs)} of {len(rows)} | "
      f"{med:.2f} / {p90:.2f} % | {m['final_error_h_m']:.2f} m ({m['error_pct_h']:.2f} %) | "
      f"{t('import')} | {t('replay')} | {t('eval')} |")
PY
done
} | tee "$out/table.md"
echo "(results: $out)"
