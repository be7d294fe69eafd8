#!/usr/bin/env bash
# Watching a lockstep replay in Foxglove changes nothing for the estimator:
# nadir_replay with and without the foxglove node (served to a client that
# stays and one that disconnects after 1000 messages, mid-run) writes the same POSE messages,
# byte for byte. Runs in a private network namespace (its own loopback).
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

nadir_sim --profile demo --seed 7 --duration 15 --out "$work/sim.lcmlog" >/dev/null || fail "nadir_sim failed"
nadir_replay --in "$work/sim.lcmlog" --out "$work/plain.lcmlog" --nodes tracker,vo_solver,yaw_fusion >/dev/null ||
  fail "nadir_replay without foxglove failed"
node "$here/ws_client.js" ws://127.0.0.1:8765 "$work/stay.json" --topics POSE,CAMERA_IMAGE,TRACKS --idle-exit 0 --max-wait 60 &
stay=$!
node "$here/ws_client.js" ws://127.0.0.1:8765 "$work/leave.json" --topics '*' --disconnect-after-messages 1000 --idle-exit 0 --max-wait 60 &
leave=$!
nadir_replay --in "$work/sim.lcmlog" --out "$work/watched.lcmlog" --nodes tracker,vo_solver,yaw_fusion,foxglove \
  >"$work/watched.txt" 2>&1 || { cat "$work/watched.txt"; fail "nadir_replay with foxglove failed"; }
wait "$stay" "$leave"
nadir_log compare "$work/plain.lcmlog" "$work/watched.lcmlog" --channel POSE --tolerance 0 ||
  fail "POSE differ with the foxglove node watched"
digest() { nadir_log dump "$1" POSE --json 2>/dev/null | sha256sum | cut -c1-16; }
echo "POSE digest without foxglove $(digest "$work/plain.lcmlog"), with foxglove and clients $(digest "$work/watched.lcmlog")"
[ "$(digest "$work/plain.lcmlog")" = "$(digest "$work/watched.lcmlog")" ] || fail "POSE digests differ"
/usr/bin/python3 - "$work" <<'PY' || exit 1
import json, sys
w = sys.argv[1]
stay, leave = json.load(open(f"{w}/stay.json")), json.load(open(f"{w}/leave.json"))
print(f"client that stayed: connected at {stay.get('connected_at_ms')} ms, {len(stay['pose'])} POSE, "
      f"{stay['received']} messages, closed by {stay['closed_by']}")
print(f"client that left: {leave['received']} messages, closed by {leave['closed_by']}")
ok = stay["connected"] and len(stay["pose"]) > 0 and leave["connected"] and leave["closed_by"].startswith("client")
sys.exit(0 if ok else 1)
PY
[ $? = 0 ] || fail "the clients did not both connect (and one leave)"

# Another program holds the port: the replay still runs, served on a free port it names.
/usr/bin/python3 -c 'import socket, sys, time
s = socket.socket(); s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1); s.bind(("127.0.0.1", 8765)); s.listen(); print("held", flush=True); time.sleep(120)' \
  >"$work/holder.txt" 2>&1 &
holder=$!
for _ in $(seq 50); do grep -q held "$work/holder.txt" 2>/dev/null && break; sleep 0.1; done
grep -q held "$work/holder.txt" || { cat "$work/holder.txt"; fail "could not hold port 8765 for the test"; }
nadir_replay --in "$work/sim.lcmlog" --out "$work/taken.lcmlog" --nodes tracker,vo_solver,yaw_fusion,foxglove \
  >"$work/taken.txt" 2>&1 || { cat "$work/taken.txt"; kill "$holder"; fail "nadir_replay failed with port 8765 taken"; }
kill "$holder"
grep "nadir_foxglove: port 8765 was taken, serving on" "$work/taken.txt" || { cat "$work/taken.txt"; fail "no note of the port taken"; }
grep -E "serving ws://127.0.0.1:[0-9]+" "$work/taken.txt" | grep -v ":8765" >/dev/null || fail "not served on another port"
[ "$(digest "$work/plain.lcmlog")" = "$(digest "$work/taken.lcmlog")" ] || fail "POSE digests differ with the port taken"
echo PASS
