#!/usr/bin/env bash
# A profile flown with and without map fixes on the same simulated flight:
# fly.sh --map simulated (simulation, the world's reference map, replay with
# the map matcher, evaluation), then the same simulator log replayed without
# the matcher and evaluated. Prints one line per seed with both.
# Usage: studies/map_fixes/long_flights.sh [--replay-only] PROFILE SEED... (output in logs/map_fixes/PROFILE-seedN/)
#   --replay-only  reuse the simulator log and map already there (after a change to the matcher or fusion)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
export PATH="$root/build/bin:$PATH"
replay_only=0
if [ "${1:-}" = --replay-only ]; then replay_only=1; shift; fi
profile="${1:?usage: long_flights.sh [--replay-only] PROFILE SEED...}"
shift
name="$(basename "${profile%.yaml}")"
mkdir -p "$root/logs/map_fixes"
for seed in "$@"; do
  out="$root/logs/map_fixes/$name-seed$seed"
  if ((replay_only)); then
    gsd="$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["gsd_m"])' "$out/map/map.json")"
    nadir_replay --in "$out/sim.lcmlog" --out "$out/with_map.lcmlog" --nodes tracker,vo_solver,yaw_fusion,map_matcher \
      --set "map_matcher.orthophoto=$out/map/orthophoto.tif" --set "map_matcher.dem=$out/map/dem.tif" \
      --set "map_matcher.gsd_m=$gsd" --json >"$out/with_map_replay.json"
    nadir_eval --log "$out/with_map.lcmlog" --out "$out/report" --no-plots --json >"$out.with_map.json"
    rm -f "$out/with_map.lcmlog"
  else
    "$root/launch_scripts/fly.sh" --profile "$profile" --seed "$seed" --map simulated --no-setup --out "$out" --json \
      >"$out.with_map.json" 2>"$out.fly.txt"
  fi
  nadir_replay --in "$out/sim.lcmlog" --out "$out/no_map.lcmlog" --nodes tracker,vo_solver,yaw_fusion --json \
    >"$out/no_map_replay.json"
  nadir_eval --log "$out/no_map.lcmlog" --out "$out/no_map_report" --no-plots --json >"$out.no_map.json"
  rm -f "$out/no_map.lcmlog"
  /usr/bin/python3 - "$out.with_map.json" "$out.no_map.json" "$name" "$seed" <<'PY'
import json, sys
w, n = (json.load(open(p)) for p in sys.argv[1:3])
f = w["map_fixes"]
print(f"{sys.argv[3]} seed {sys.argv[4]}: {w['distance_m'] / 1000:.1f} km; with the map p95 {w['p95_error_h_m']:.2f} m, "
      f"max {w['max_error_h_m']:.2f} m, final {w['final_error_h_m']:.2f} m ({f['fixes']} fixes, {f['applied']} applied, "
      f"{f['rejected']} rejected, fix error p95 {f['error_p95_m']:.2f} m, {f['beyond_3_sigma']} beyond 3 sigma); "
      f"without p95 {n['p95_error_h_m']:.2f} m, max {n['max_error_h_m']:.2f} m, final {n['final_error_h_m']:.2f} m")
PY
done
