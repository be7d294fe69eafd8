#!/usr/bin/env bash
# nadir_export mcap against an independent MCAP reader (@mcap/core, through
# its chunk indexes and as a CRC-checked stream): a simulated flight replayed
# through the estimator, exported, read back: per topic as many messages as
# nadir_log info counts on its LCM channel, the same first and last sensor
# times, schemas that compile as JSON Schema (ajv), every message valid
# against its schema and against Foxglove's published one; statistics and
# chunk indexes consistent. With --image-rate 2: CAMERA_IMAGE at 2 Hz.
set -uo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
source "$root/launch_scripts/common.sh"
fail() { echo "FAIL: $*"; exit 1; }
export NODE_PATH="$NADIR_BUILD/node_foxglove/node_modules"
[ -d "$NODE_PATH/@mcap/core" ] ||
  fail "no @mcap/core in $NODE_PATH (run tests/processes/foxglove/install_node_foxglove.sh $NADIR_BUILD)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
here="$root/tests/processes/foxglove"

nadir_sim --profile demo --seed 4 --duration 12 --out "$work/sim.lcmlog" >/dev/null || fail "nadir_sim failed"
nadir_replay --in "$work/sim.lcmlog" --out "$work/flight.lcmlog" --nodes tracker,vo_solver,yaw_fusion --json \
  >/dev/null || fail "nadir_replay failed"
nadir_log info "$work/flight.lcmlog" --json >"$work/info.json" || fail "nadir_log info failed"
for rate in 0 2; do
  nadir_export mcap --in "$work/flight.lcmlog" --out "$work/flight$rate.mcap" --image-rate "$rate" --json \
    >"$work/export$rate.json" || fail "nadir_export mcap --image-rate $rate failed"
  node "$here/read_mcap.js" "$work/flight$rate.mcap" >"$work/read$rate.json" || fail "@mcap/core could not read flight$rate.mcap"
done

/usr/bin/python3 - "$work" <<'PY' || exit 1
import json, sys
w = sys.argv[1]
info = json.load(open(f"{w}/info.json"))["channels"]
problems = []
def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok: problems.append(what)
for rate in (0, 2):
    r = json.load(open(f"{w}/read{rate}.json"))
    print(f"--image-rate {rate}: {r['bytes'] / 1e6:.1f} MB, {r['chunks']} chunks, statistics {r['statistics']}")
    check(not r["errors"], f"no reader, schema or validation errors: {r['errors'][:3]}")
    check(r["out_of_order"] == 0, "messages in log-time order")
    total = 0
    for topic, t in sorted(r["topics"].items()):
        s = r["stream_counts"].get(topic, {"count": 0})
        total += t["count"]
        lcm = info.get(t["lcm_channel"], {"messages": 0})
        print(f"  {topic:18s} {t['schema']:27s} {t['count']:6d} messages (stream {s['count']}), LCM {t['lcm_channel']}: {lcm['messages']}")
        check(t["count"] == s["count"], f"{topic}: indexed and streamed counts equal")
        check(t["invalid"] == 0, f"{topic}: every message valid against its schema")
        if topic == "CAMERA_IMAGE" and rate == 2:
            span = (int(s["last_publish_ns"]) - int(s["first_publish_ns"])) / 1e9
            check(abs((t["count"] - 1) / span - 2.0) < 0.1, f"CAMERA_IMAGE at {(t['count'] - 1) / span:.2f} Hz of sensor time")
            continue
        if lcm["messages"] == 0:
            check(t["count"] == 0, f"{topic}: no messages, none on LCM")
            continue
        if topic.endswith("/fix") or topic.startswith("GROUND_TRUTH/"):
            # Geodetic only once the origin is known (the INS position at the first POSE); the
            # truth's map views from the first POSE on (relative to the truth there).
            check(0 < t["count"] <= lcm["messages"], f"{topic}: {t['count']} of the {lcm['messages']} (from the first POSE on)")
            check(int(s["last_publish_ns"]) == lcm["last_utime"] * 1000, f"{topic}: last sensor time equals the log's")
            continue
        check(t["count"] == lcm["messages"], f"{topic}: count equals nadir_log info's {lcm['messages']}")
        check(int(s["first_publish_ns"]) == lcm["first_utime"] * 1000 and int(s["last_publish_ns"]) == lcm["last_utime"] * 1000,
              f"{topic}: first/last sensor time equal the log's ({lcm['first_utime']} .. {lcm['last_utime']} us)")
    check(int(r["statistics"]["message_count"]) == total, f"statistics: {r['statistics']['message_count']} messages = the sum over topics")
    for name, sch in r["schemas"].items():
        if name.startswith("foxglove."):
            check(sch["checked_against_foxglove"], f"{name}: messages validated against Foxglove's published schema")
sys.exit(1 if problems else 0)
PY
echo PASS
