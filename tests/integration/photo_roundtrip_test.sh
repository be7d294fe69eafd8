#!/usr/bin/env bash
# The round trip without real data: the simulator's survey flight
# exported as a DJI-style photo survey (0.5 Hz, 74-79 % overlap on the lines,
# one 180 deg turn between consecutive photos), imported back, replayed
# through tracker + vo_solver + yaw_fusion and evaluated against the sim's
# truth (the photos' GPS):
#   final horizontal error <= 2 % of the distance flown, and the pair across
#   the turn solved (its VO_DELTA unflagged, with inliers).
# The camera from the photos alone (no calibration file): a 16:9 crop of a 4:3
# sensor and DJI's XMP calibration, imported, give the true focal length.
# 12 MP photos of the survey's first 30 s come at the working resolution (1000x750).
# A return line stored turned 180 deg is found and turned back; a recorded yaw 11.5 deg off the
# images' heading is fitted against the GPS.
# Then the same flight as video + SRT when nadir_import has a video mode.
# Needs nadir_sim, nadir_export, nadir_import, nadir_replay, nadir_eval on
# PATH or in $NADIR_BUILD/bin. Exit 77 (skip) when nadir_import is absent.
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
source "$root/launch_scripts/common.sh"
[ -n "${NADIR_BUILD:-}" ] && export PATH="$NADIR_BUILD/bin:$PATH"
export PATH="$root/build/bin:$PATH"
command -v nadir_import >/dev/null || { echo "SKIP: nadir_import not built"; exit 77; }
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
failures=0
bad() { echo "FAIL: $*"; failures=$((failures + 1)); }   # a figure off: the other leg still runs
seed="${NADIR_ROUNDTRIP_SEED:-1}"
max_error_pct="${NADIR_ROUNDTRIP_MAX_ERROR_PCT:-2.0}"

nadir_sim --profile survey --seed "$seed" --out "$work/sim.lcmlog" >/dev/null 2>"$work/sim.txt" ||
  { cat "$work/sim.txt"; fail "nadir_sim failed"; }

# VO_DELTA of the pair of frames K-1, K (0-based, in the order of the CAMERA_IMAGE messages of
# the imported log $2) in the replay log $1: "quality inliers dyaw_deg" ("none 0 0" if absent),
# read straight from the lcm-logger format (no LCM Python bindings on Debian).
vo_delta_of_pair() {
  python3 - "$1" "$2" "$3" <<'PY'
import math, struct, sys

def events(path):
    data = open(path, "rb").read()
    pos = 0
    while pos + 28 <= len(data):
        sync, _, _, clen, dlen = struct.unpack_from(">IqqII", data, pos)
        if sync != 0xEDA1DA01:
            sys.exit(f"{path}: byte {pos}: no sync word")
        yield data[pos + 28:pos + 28 + clen].decode(), data[pos + 28 + clen:pos + 28 + clen + dlen]
        pos += 28 + clen + dlen

replay, imported, k = sys.argv[1], sys.argv[2], int(sys.argv[3])
# image_t and vo_delta_t: an 8-byte fingerprint, then utime (int64).
frames = [struct.unpack_from(">q", body, 8)[0] for channel, body in events(imported) if channel == "CAMERA_IMAGE"]
if k >= len(frames):
    sys.exit(f"{imported}: {len(frames)} frames, no frame {k}")
found = None
for channel, body in events(replay):
    if channel != "VO_DELTA":
        continue
    # vo_delta_t: utime, prev_utime, dx dy dz dyaw ground_roll ground_pitch, covariance[6][6],
    # altitude_m, inliers, outliers, residual_rms_px, iterations, quality
    u, p = struct.unpack_from(">qq", body, 8)
    if u == frames[k] and p == frames[k - 1]:
        dyaw, = struct.unpack_from(">d", body, 48)
        inliers, = struct.unpack_from(">i", body, 368)
        quality, = struct.unpack_from(">i", body, 388)
        found = (quality, inliers, math.degrees(dyaw))
print("none 0 0" if found is None else "%d %d %.2f" % found)
PY
}

# Runs nadir_import (the arguments after $1; it writes OUT.lcmlog + OUT.yaml for --out OUT) -> replay ->
# eval for one export in $work/$1, and checks the figures.
roundtrip() {
  local name="$1"; shift
  local dir="$work/$name"
  nadir_import "$@" --out "$dir/import" --json >"$dir/import.json" 2>"$dir/import.txt" ||
    { cat "$dir/import.txt"; fail "($name) nadir_import failed"; }
  [ -s "$dir/import.yaml" ] || fail "($name) nadir_import wrote no $dir/import.yaml"
  nadir_replay --in "$dir/import.lcmlog" --out "$dir/replay.lcmlog" --nodes tracker,vo_solver,yaw_fusion \
    --config "$dir/import.yaml" --json >"$dir/replay.json" 2>"$dir/replay.txt" ||
    { cat "$dir/replay.txt"; fail "($name) nadir_replay failed"; }
  nadir_eval --log "$dir/replay.lcmlog" --out "$dir/eval" --json --no-plots >"$dir/metrics.json" 2>"$dir/eval.txt" ||
    { cat "$dir/eval.txt"; fail "($name) nadir_eval failed"; }
  python3 - "$dir/metrics.json" "$max_error_pct" "$name" <<'PY' || bad "($name) final error above $max_error_pct % of distance"
import json, sys
m = json.load(open(sys.argv[1]))
limit, name = float(sys.argv[2]), sys.argv[3]
print(f"({name}) distance {m['distance_m']:.0f} m, final error {m['final_error_h_m']:.2f} m horizontal = "
      f"{m['error_pct_h']:.2f} % ({m['error_pct_3d']:.2f} % 3D), VO_DELTA {m['vo_deltas']} "
      f"({m['vo_deltas_flagged']} flagged), poses {m['poses']}")
sys.exit(0 if m["poses"] > 0 and m["error_pct_h"] <= limit else 1)
PY
}

# Photos: 0.5 Hz, no photo in the turn.
mkdir -p "$work/photos"
nadir_export photos --in "$work/sim.lcmlog" --out "$work/photos/survey" --json >"$work/photos/export.json" ||
  fail "nadir_export photos failed"
read -r photos turn_index turn_dyaw turn_overlap < <(python3 - "$work/photos/export.json" <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))["photos"]
turn = [k for k in range(1, len(p)) if abs(p[k]["heading_change_deg"]) > 170]
k = turn[0] if turn else 0
print(len(p), k, p[k]["heading_change_deg"], p[k]["overlap_with_previous"])
PY
)
echo "(photos) $photos photos; pair $turn_index across the turn: heading change $turn_dyaw deg, overlap $turn_overlap"
[ "$turn_index" != 0 ] || fail "(photos) no consecutive photos across a 180 deg turn"
roundtrip photos --photos "$work/photos/survey" --camera "$work/photos/survey/camera.yaml"
# The photos' height is barometric (above take-off): the import sets yaw_fusion.altitude_mode barometric,
# so the vertical follows it instead of summing each pair's dz.
python3 - "$work/photos/metrics.json" <<'PY' || bad "(photos) final vertical error above 0.5 m"
import json, sys
v = json.load(open(sys.argv[1]))["final_error_v_m"]
print(f"(photos) final vertical error {v:+.2f} m")
sys.exit(0 if abs(v) <= 0.5 else 1)
PY
read -r quality inliers dyaw < <(vo_delta_of_pair "$work/photos/replay.lcmlog" "$work/photos/import.lcmlog" "$turn_index")
echo "(photos) VO_DELTA across the turn: quality $quality, $inliers inliers, dyaw $dyaw deg"
[ "$quality" = 0 ] && [ "$inliers" -gt 0 ] || bad "(photos) the pair across the turn is not solved"

# The camera from what the photos say (import only, no --camera): the exporter's true focal length
# (its camera.yaml) recovered from a 16:9 crop of a 4:3 sensor with only the 35 mm equivalent in EXIF
# (to 0.5 %, and not the 16:9 frame's diagonal answer, 8.2 % short), from DJI's XMP calibration
# (as written), and from DJI's DewarpData with the lens distortion.
camera_kind() {
  local name="$1"; shift
  local dir="$work/$name"
  mkdir -p "$dir"
  nadir_export photos --in "$work/sim.lcmlog" --out "$dir/survey" --interval 20 "$@" >/dev/null 2>"$dir/export.txt" ||
    { cat "$dir/export.txt"; fail "($name) nadir_export photos $* failed"; }
  nadir_import --photos "$dir/survey" --out "$dir/import" --json >"$dir/import.json" 2>"$dir/import.txt" ||
    { cat "$dir/import.txt"; fail "($name) nadir_import failed"; }
  python3 - "$dir/survey/camera.yaml" "$dir/import.json" "$name" <<'PY' || bad "($name) focal length not recovered"
import json, math, re, sys
text = open(sys.argv[1]).read()
k = [float(v) for v in re.search(r"camera_matrix:.*?data:\s*\[([^\]]*)\]", text, re.S).group(1).split(",")]
fx, cx, cy = k[0], k[2], k[5]
c = json.load(open(sys.argv[2]))["camera"]
name = sys.argv[3]
err = c["fx"] / fx - 1.0
print(f"({name}) focal {c['fx']:.3f} px from {c['source']} vs true {fx:.3f} px ({100 * err:+.3f} %); "
      f"principal point {c['cx']:.3f}, {c['cy']:.3f} vs {cx:.3f}, {cy:.3f}")
ok = c["fy"] == c["fx"]
if name == "crop169":
    w, h = c["width"], c["height"]
    own = c["fx"] * math.hypot(w, h) / math.hypot(w, 0.75 * w)  # what the 16:9 frame's diagonal would give
    print(f"({name}) {w}x{h}: the 16:9 diagonal would give {own:.3f} px ({100 * (own / fx - 1):+.2f} %)")
    ok = ok and c["source"] == "EXIF FocalLengthIn35mmFilm" and abs(err) < 0.005 and own / fx - 1 < -0.07
elif name == "dewarp":
    # DewarpData carries the lens distortion too: the import's config has the exporter's k1 k2 p1 p2 k3.
    dist = [float(v) for v in re.search(r"distortion_coefficients:.*?data:\s*\[([^\]]*)\]", text, re.S).group(1).split(",")]
    written = open(sys.argv[2].replace("import.json", "import.yaml")).read()
    block = re.search(r"\n  distortion:\n((?:    - [^\n]*\n)+)", written).group(1)
    got = [float(v.strip()[2:]) for v in block.strip().split("\n")]
    print(f"({name}) distortion {got} vs true {dist}")
    ok = ok and c["source"] == "XMP drone-dji:DewarpData" and abs(c["fx"] - fx) < 1e-6
    ok = ok and abs(c["cx"] - cx) < 1e-6 and abs(c["cy"] - cy) < 1e-6
    ok = ok and len(got) == len(dist) and all(abs(a - b) < 1e-9 for a, b in zip(got, dist))
else:
    ok = ok and c["source"] == "XMP drone-dji:CalibratedFocalLength" and abs(c["fx"] - fx) < 1e-6
    ok = ok and abs(c["cx"] - cx) < 1e-6 and abs(c["cy"] - cy) < 1e-6
sys.exit(0 if ok else 1)
PY
}
camera_kind crop169 --crop-16-9 --model FC300X
camera_kind calibrated --dji-calibration
camera_kind dewarp --dji-dewarp

# A return line stored turned 180 deg in its pixels (a photo viewer re-saved it; EXIF Orientation 1):
# found from the images and turned back (exactly the return line's photos named), the pair across the
# turn solved again, the flight within the same bound.
mkdir -p "$work/turned"
nadir_export photos --in "$work/sim.lcmlog" --out "$work/turned/survey" --turn-return-lines 180 --json \
  >"$work/turned/export.json" 2>"$work/turned/export.txt" || { cat "$work/turned/export.txt"; fail "nadir_export --turn-return-lines failed"; }
roundtrip turned --photos "$work/turned/survey" --camera "$work/turned/survey/camera.yaml"
python3 - "$work/turned/export.json" "$work/turned/import.json" <<'PY' || bad "(turned) the turned photos were not all found"
import json, os, sys
stored = {p["file"]: p["stored_turn_deg"] for p in json.load(open(sys.argv[1]))["photos"] if p["stored_turn_deg"]}
imported = json.load(open(sys.argv[2]))
found = {os.path.basename(t["where"]): t["degrees"] for t in imported["turned_back"]}
print(f"(turned) {len(stored)} photos stored turned, {len(found)} found and turned back, "
      f"{imported['orientation_unchecked']} not linked to a neighbour")
sys.exit(0 if stored and found == stored else 1)
PY
read -r quality inliers dyaw < <(vo_delta_of_pair "$work/turned/replay.lcmlog" "$work/turned/import.lcmlog" "$turn_index")
echo "(turned) VO_DELTA across the turn: quality $quality, $inliers inliers, dyaw $dyaw deg"
[ "$quality" = 0 ] && [ "$inliers" -gt 0 ] || bad "(turned) the pair across the turn is not solved"

# The recorded yaw 11.5 deg off the images' heading (a compass disturbed by the site): the offset fitted
# against the GPS over the flight's solved pairs (nadir_calibrate --scale-only, as own_flight.sh
# --gps-scale does) to within 3 sigma and 1 deg, and written into the camera mount's yaw.
mkdir -p "$work/yawoffset"
nadir_export photos --in "$work/sim.lcmlog" --out "$work/yawoffset/survey" --yaw-offset-deg=-11.5 \
  >/dev/null 2>"$work/yawoffset/export.txt" || { cat "$work/yawoffset/export.txt"; fail "nadir_export --yaw-offset-deg failed"; }
nadir_import --photos "$work/yawoffset/survey" --camera "$work/yawoffset/survey/camera.yaml" --out "$work/yawoffset/import" \
  >/dev/null 2>"$work/yawoffset/import.txt" || { cat "$work/yawoffset/import.txt"; fail "(yawoffset) nadir_import failed"; }
nadir_replay --in "$work/yawoffset/import.lcmlog" --out "$work/yawoffset/replay.lcmlog" --nodes tracker,vo_solver,yaw_fusion \
  --config "$work/yawoffset/import.yaml" --json >/dev/null 2>"$work/yawoffset/replay.txt" ||
  { cat "$work/yawoffset/replay.txt"; fail "(yawoffset) nadir_replay failed"; }
nadir_calibrate --log "$work/yawoffset/replay.lcmlog" --config "$work/yawoffset/import.yaml" --gps-scale focal \
  --scale-only --out "$work/yawoffset/fit.yaml" --json >"$work/yawoffset/fit.json" 2>"$work/yawoffset/fit.txt" ||
  { cat "$work/yawoffset/fit.txt"; fail "(yawoffset) nadir_calibrate failed"; }
python3 - "$work/yawoffset/fit.json" "$work/yawoffset/fit.yaml" <<'PY' || bad "(yawoffset) the heading offset was not recovered"
import json, re, sys
f = json.load(open(sys.argv[1]))
h = f["heading_offset_deg"]
yaml = open(sys.argv[2]).read()
mount = re.search(r"mount_rpy_deg: \[([^\]]*)\]", yaml)
print(f"(yawoffset) heading offset {h['value']:+.2f} +- {h['sigma']:.2f} deg (true +11.50), applied "
      f"{f['heading_offset_applied']}, mount {mount.group(1) if mount else 'not written'}")
ok = h["estimated"] and abs(h["value"] - 11.5) <= max(3 * h["sigma"], 0.2) and abs(h["value"] - 11.5) < 1.0
sys.exit(0 if ok and f["heading_offset_applied"] and mount else 1)
PY

# 12 MP photos (a DJI Phantom 3's 4000x3000: the simulator's camera from config/sim_camera_12mp.yaml,
# the survey's first 30 s, 16 photos), imported without --scale: the working resolution (1/4, 1000x750)
# with the intrinsics scaled exactly, then replayed and evaluated.
mkdir -p "$work/photos12"
nadir_sim --profile survey --seed "$seed" --duration 30 --config-overlay "$root/config/sim_camera_12mp.yaml" \
  --out "$work/sim12.lcmlog" >/dev/null 2>"$work/sim12.txt" || { cat "$work/sim12.txt"; fail "nadir_sim (12 MP) failed"; }
nadir_export photos --in "$work/sim12.lcmlog" --out "$work/photos12/survey" >/dev/null 2>"$work/photos12/export.txt" ||
  { cat "$work/photos12/export.txt"; fail "nadir_export photos (12 MP) failed"; }
rm -f "$work/sim12.lcmlog"
roundtrip photos12 --photos "$work/photos12/survey" --camera "$work/photos12/survey/camera.yaml"
python3 - "$work/photos12/import.json" <<'PY' || bad "(photos12) not imported at the working resolution 1000x750"
import json, sys
c = json.load(open(sys.argv[1]))["camera"]
print(f"(photos12) {c['width']}x{c['height']}, scale {c['scale']} ({c['scale_rule']}), fx {c['fx']}, cx {c['cx']}, cy {c['cy']}")
# camera.yaml: 4000x3000, f 2311, principal point (1999.5, 1499.5); pixel centres kept at 1/4.
sys.exit(0 if (c["width"], c["height"], c["scale"], c["fx"], c["fy"], c["cx"], c["cy"]) ==
         (1000, 750, 0.25, 577.75, 577.75, 499.5, 374.5) else 1)
PY

# Video + SRT (every 7th frame: 2 Hz), when the importer has a video mode.
if nadir_import --help 2>&1 | grep -q -- '--srt'; then
  mkdir -p "$work/video"
  nadir_export video --in "$work/sim.lcmlog" --out "$work/video/flight.avi" --srt "$work/video/flight.SRT" \
    --camera "$work/video/camera.yaml" --every 7 >/dev/null || fail "nadir_export video failed"
  roundtrip video --video "$work/video/flight.avi" --srt "$work/video/flight.SRT" \
    --camera "$work/video/camera.yaml"
else
  echo "(video) nadir_import has no video mode: skipped"
fi
[ "$failures" = 0 ] || exit 1
echo "PASS"
