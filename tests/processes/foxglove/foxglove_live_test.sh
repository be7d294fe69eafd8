#!/usr/bin/env bash
# nadir_foxglove during a live flight of the sim_foxglove set (udpm inside a
# private network namespace), against Foxglove's own client library
# (@foxglove/ws-protocol, installed by install_node_foxglove.sh):
#  - client A (POSE, CAMERA_IMAGE, STATUS) and client B (POSE), connected the
#    whole flight, receive every POSE the capture holds, with the same values;
#    A receives CAMERA_IMAGE at the configured rate (2 Hz of sensor time);
#  - client C subscribes to everything and disconnects mid-flight;
#  - bad clients at the same time (garbage, no subprotocol, not JSON, unknown
#    op and channel, binary, oversized and invalid frames, too many errors, a
#    slow consumer) are answered with status errors or disconnected, the
#    server stays up, and the bridge's STATUS counts them; its memory stays
#    bounded.
set -uo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
source "$root/launch_scripts/common.sh"
[ "${NADIR_IN_NETNS:-0}" = 1 ] || exec bash -c "source '$root/launch_scripts/common.sh'; nadir_in_netns bash '$0'"
fail() { echo "FAIL: $*"; exit 1; }
export NODE_PATH="$NADIR_BUILD/node_foxglove/node_modules"
[ -d "$NODE_PATH/@foxglove/ws-protocol" ] ||
  fail "no @foxglove/ws-protocol in $NODE_PATH (run tests/processes/foxglove/install_node_foxglove.sh $NADIR_BUILD)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
here="$root/tests/processes/foxglove"
url=ws://127.0.0.1:8765

# The simulator starts 3 s after the set: every client is connected before the first POSE.
NADIR_CAPTURE_DIR="$work/run" NADIR_PROFILE=demo NADIR_SEED=5 NADIR_SIM_ARGS="--duration ${FOXGLOVE_TEST_DURATION:-30}" \
  NADIR_FOXGLOVE_ARGS="--set foxglove.max_client_buffer_kb=1024 --set foxglove.slow_client_timeout_s=2" \
  "$root/launch_scripts/run_set.sh" sim_foxglove >"$work/run.txt" 2>&1 &
set_pid=$!
node "$here/ws_client.js" "$url" "$work/a.json" --topics POSE,CAMERA_IMAGE,STATUS --idle-exit 0 --max-wait 30 &
a_pid=$!
node "$here/ws_client.js" "$url" "$work/b.json" --topics POSE --idle-exit 0 --max-wait 30 &
b_pid=$!
node "$here/ws_client.js" "$url" "$work/c.json" --topics '*' --disconnect-after 12 --idle-exit 0 --max-wait 30 &
c_pid=$!
node "$here/bad_clients.js" 127.0.0.1 8765 "$work/bad.json" --slow-pause 15 >"$work/bad.txt" 2>&1 &
bad_pid=$!
wait "$set_pid" || { cat "$work/run.txt"; fail "the sim_foxglove set failed"; }
for p in $a_pid $b_pid $c_pid $bad_pid; do wait "$p" || fail "a client failed (pid $p)"; done
capture="$work/run/capture.lcmlog"
[ -s "$capture" ] || { cat "$work/run.txt"; fail "no capture"; }
nadir_log dump "$capture" POSE --json -o "$work/pose.jsonl" 2>/dev/null || fail "nadir_log dump POSE failed"
grep -E '^\[foxglove\]' "$work/run.txt" | head -40

/usr/bin/python3 - "$work" <<'PY' || exit 1
import json, sys
w = sys.argv[1]
a, b, c, bad = (json.load(open(f"{w}/{n}.json")) for n in ("a", "b", "c", "bad"))
lcm = [json.loads(l) for l in open(f"{w}/pose.jsonl")]
lcm_rows = [[p["utime"], p["north"], p["east"], p["down"]] for p in lcm]
problems = []
def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok: problems.append(what)
for name, r in (("A", a), ("B", b)):
    rows = [p[:4] for p in r["pose"]]
    check(len(rows) == len(lcm_rows), f"client {name}: {len(rows)} POSE received, the capture holds {len(lcm_rows)}")
    check(rows == lcm_rows, f"client {name}: every POSE's utime, north, east, down equal the capture's (exactly)")
    check(r["closed_by"] == "server", f"client {name}: connected until the bridge stopped ({r['closed_by']})")
img = a["topics"].get("CAMERA_IMAGE", {"count": 0, "first_ns": 0, "last_ns": 0})
span = (int(img["last_ns"]) - int(img["first_ns"])) / 1e9 if img["count"] > 1 else 0
rate = (img["count"] - 1) / span if span > 0 else 0
check(1.9 <= rate <= 2.1, f"client A: {img['count']} CAMERA_IMAGE over {span:.1f} s of sensor time: {rate:.2f} Hz (configured 2)")
check(c["closed_by"].startswith("client") and c["received"] > 0,
      f"client C: subscribed to {len(c['topics'])} topics, received {c['received']} messages, then disconnected mid-flight")
s = a["bridge_status"] or {}
k = s.get("counters", {})
print("bridge STATUS at the end:", json.dumps({n: k.get(n) for n in sorted(k)}))
print("bad clients:", json.dumps({n: {x: v[x] for x in ("closed", "close_code", "error", "statuses") if x in v} if isinstance(v, dict) else v for n, v in bad.items()})[:3000])
check(bad["raw_garbage"]["closed"], "raw TCP garbage: connection closed")
check(bad["no_subprotocol"]["closed"] and not bad["no_subprotocol"]["opened"], "no foxglove subprotocol: handshake refused")
for n in ("not_json", "unknown_op", "unknown_channel", "binary"):
    check(len(bad[n]["statuses"]) > 0, f"{n}: answered with status error(s): {bad[n]['statuses'][:2]}")
check(bad["oversized"]["closed"] and bad["oversized"]["close_code"] == 1009, f"oversized frame: closed with {bad['oversized']['close_code']} (1009)")
check(bad["invalid_frame"]["closed"], f"invalid frame: closed ({bad['invalid_frame']['close_code']})")
check(bad["many_errors"]["closed"] and bad["many_errors"]["close_code"] == 1008, f"15 bad requests, 50 ms apart: disconnected with {bad['many_errors']['close_code']} (1008) after {len(bad['many_errors']['statuses'])} status errors")
sc = bad["slow_consumer"]
check(sc["closed"], f"slow consumer: subscribed to {sc['subscribed']} topics, stopped reading, disconnected (at {sc.get('closed_at_s')} s)")
check(k.get("clients_slow_disconnected", 0) >= 1, f"STATUS clients_slow_disconnected = {k.get('clients_slow_disconnected')}")
check(k.get("clients_protocol_disconnected", 0) >= 2, f"STATUS clients_protocol_disconnected = {k.get('clients_protocol_disconnected')}")
check(k.get("clients_rejected", 0) >= 1, f"STATUS clients_rejected = {k.get('clients_rejected')}")
check(k.get("protocol_errors", 0) >= 15, f"STATUS protocol_errors = {k.get('protocol_errors')}")
check(k.get("messages_dropped_client", 0) >= 1, f"STATUS messages_dropped_client = {k.get('messages_dropped_client')}")
check(0 < a["bridge_peak_rss_kb"] < 200 * 1024, f"bridge peak resident memory {a['bridge_peak_rss_kb'] / 1024:.1f} MB (< 200 MB)")
sys.exit(1 if problems else 0)
PY
echo "PASS"
