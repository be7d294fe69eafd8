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
echo PASS
