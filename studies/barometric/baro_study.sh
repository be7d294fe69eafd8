#!/usr/bin/env bash
# The vertical on a barometric height: the simulated photo survey (survey
# profile, exported as DJI-style photos whose RelativeAltitude is the height
# above take-off) imported, replayed with yaw_fusion.altitude_mode vo_dz and
# barometric (what the import now writes), and evaluated against the photos'
# GPS. Per seed and relief scale: final horizontal and vertical error, the
# largest vertical error over the flight, pairs solved. Prints a markdown table.
# Usage: baro_study.sh [--relief R[,R...]] [--overlay FILE] SEED [SEED ...]
#   --relief: terrain.relief_scale values to fly (nadir_sim --relief-scale;
#   default: the profile's own, 0.2).
#   --overlay: a config fragment added to both replays, e.g. mount_error.yaml
#   (a camera tilt the import does not know: each pair's dz is biased).
# Results under logs/barometric/<UTC>/.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../../launch_scripts/common.sh"
usage() { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; }
reliefs=(profile) seeds=() extra=()
while (($#)); do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --relief) IFS=, read -r -a reliefs <<<"$2"; shift 2 ;;
    --overlay) extra=(--config-overlay "$(realpath "$2")"); shift 2 ;;
    -*) echo "baro_study: error: unknown option $1 (--help)" >&2; exit 2 ;;
    *) seeds+=("$1"); shift ;;
  esac
done
[ ${#seeds[@]} -gt 0 ] || { echo "baro_study: error: give at least one SEED (--help)" >&2; exit 2; }
for tool in nadir_sim nadir_export nadir_import nadir_replay nadir_eval; do
  command -v "$tool" >/dev/null || { echo "baro_study: error: $tool not built (launch_scripts/setup.sh)" >&2; exit 1; }
done
out="$NADIR_ROOT/logs/barometric/$(nadir_utc_stamp)"
mkdir -p "$out"
[ ${#extra[@]} -eq 0 ] || echo "overlay on both replays: ${extra[1]}"
printf 'yaw_fusion: {altitude_mode: vo_dz}\n' >"$out/vo_dz.yaml"
printf 'yaw_fusion: {}\n' >"$out/barometric.yaml"   # the import's own config: barometric
echo "| seed | relief | mode | pairs solved | final horizontal | final vertical | max abs vertical | true height above ground (min-max) |"
echo "|---|---|---|---|---|---|---|---|"
for seed in "${seeds[@]}"; do
  for relief in "${reliefs[@]}"; do
    dir="$out/seed${seed}_relief${relief}"
    mkdir -p "$dir"
    relief_args=(); [ "$relief" = profile ] || relief_args=(--relief-scale "$relief")
    nadir_sim --profile survey --seed "$seed" "${relief_args[@]}" --out "$dir/sim.lcmlog" >"$dir/sim.txt" 2>&1 ||
      { cat "$dir/sim.txt" >&2; exit 1; }
    nadir_export photos --in "$dir/sim.lcmlog" --out "$dir/photos" --json >"$dir/export.json" 2>"$dir/export.txt" ||
      { cat "$dir/export.txt" >&2; exit 1; }
    nadir_import --photos "$dir/photos" --camera "$dir/photos/camera.yaml" --out "$dir/flight" --json \
      >"$dir/import.json" 2>"$dir/import.txt" || { cat "$dir/import.txt" >&2; exit 1; }
    # The true height above ground at the frames (GROUND_TRUTH KIND_FRAME, read straight from the
    # lcm-logger format: sync, event, timestamp, channel and data lengths; ground_truth_t after its
    # 8-byte fingerprint: utime, kind, position[3], velocity[3], roll, pitch, yaw, height_agl_m).
    /usr/bin/python3 - "$dir/sim.lcmlog" >"$dir/true_agl.txt" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
pos = 0
while pos + 28 <= len(data):
    sync, _, _, clen, dlen = struct.unpack_from(">IqqII", data, pos)
    assert sync == 0xEDA1DA01, pos
    channel = data[pos + 28:pos + 28 + clen].decode()
    body = data[pos + 28 + clen:pos + 28 + clen + dlen]
    if channel == "GROUND_TRUTH" and body[16] == 1:
        print(struct.unpack_from(">d", body, 17 + 9 * 8)[0])
    pos += 28 + clen + dlen
PY
    for mode in vo_dz barometric; do
      nadir_replay --in "$dir/flight.lcmlog" --out "$dir/replay_$mode.lcmlog" --nodes tracker,vo_solver,yaw_fusion \
        --config "$dir/flight.yaml" --config-overlay "$out/$mode.yaml" "${extra[@]}" --json >"$dir/replay_$mode.json" \
        2>"$dir/replay_$mode.txt" || { cat "$dir/replay_$mode.txt" >&2; exit 1; }
      nadir_eval --log "$dir/replay_$mode.lcmlog" --out "$dir/eval_$mode" --json --no-plots \
        >"$dir/metrics_$mode.json" 2>"$dir/eval_$mode.txt" || { cat "$dir/eval_$mode.txt" >&2; exit 1; }
      /usr/bin/python3 - "$dir" "$mode" "$seed" "$relief" <<'PY'
import csv, json, sys
d, mode, seed, relief = sys.argv[1:]
m = json.load(open(f"{d}/metrics_{mode}.json"))
rows = list(csv.DictReader(open(f"{d}/eval_{mode}/series.csv")))
vkey = next(k for k in rows[0] if k.startswith("error_v"))
vmax = max(abs(float(r[vkey])) for r in rows)
agl = [float(x) for x in open(f"{d}/true_agl.txt").read().split()]
span = f"{min(agl):.1f}-{max(agl):.1f} m"
print(f"| {seed} | {relief} | {mode} | {m['pairs_solved']} of {m['pairs']} | "
      f"{m['final_error_h_m']:.2f} m ({m['error_pct_h']:.2f} %) | {m['final_error_v_m']:+.2f} m | {vmax:.2f} m | {span} |")
PY
    done
    rm -f "$dir/sim.lcmlog"   # the seed reproduces it
  done
done
echo
echo "results: $out"
