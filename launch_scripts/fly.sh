#!/usr/bin/env bash
# One command for any flight profile: simulates PROFILE with SEED, replays the
# log in lockstep through the estimator (tracker, VO solver, yaw fusion: the
# same nodes and configuration as the live set, bit for bit), evaluates POSE
# against the simulator's truth and prints the report's summary.
# Usage: fly.sh --profile NAME|FILE [--seed N] [--sensor-set S] [--config-overlay F]...
#               [--map simulated|DIR] [--outage KIND:START_S:DURATION_S[:CONTRAST]]... [--duration S]
#               [--out DIR] [--keep-replay] [--json] [--no-setup]
#   --profile         a profile of config/profiles/ by name, or any profile YAML file
#   --seed            terrain, motion and sensor noise draws (default 1)
#   --sensor-set      the sensor set of config/sim_sensors.yaml (default standard)
#   --config-overlay  replay with this fragment merged into the configuration (repeatable)
#   --map             position fixes from a reference map (the map matcher joins the replay):
#                     'simulated' writes the simulated world's map (nadir_map simulate: another season,
#                     1 m, changed patches) into the output folder; DIR: a folder holding
#                     orthophoto.tif and dem.tif (GeoTIFF, any CRS; docs/maps.md)
#   --outage, --duration  passed to nadir_sim (a sensor outage cut into the flight; a shorter flight)
#   --out             output folder (default logs/fly/<UTC>-<profile>-seed<N>/)
#   --keep-replay     keep the replayed log (by default deleted: the simulator's log and the
#                     configuration reproduce it bit for bit)
#   --json            print metrics.json instead of the summary (progress and notes on stderr)
#   --no-setup        use the programs as built (by default setup.sh installs what is missing and builds)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
usage() { sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'; }
fail() { echo "fly: error: $*" >&2; exit 2; }

profile="" seed=1 out="" keep_replay=0 json=0 setup=1 map=
sim_args=() replay_args=()
while (($#)); do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --profile|--seed|--sensor-set|--config-overlay|--outage|--duration|--out|--map)
      (($# >= 2)) || fail "$1 needs a value (see --help)" ;;&
    --profile) profile="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --sensor-set) sim_args+=(--sensor-set "$2"); shift 2 ;;
    --config-overlay)
      [ -f "$2" ] || fail "--config-overlay $2: no such file"
      replay_args+=(--config-overlay "$(realpath "$2")"); shift 2 ;;
    --outage) sim_args+=(--outage "$2"); shift 2 ;;
    --map) map="$2"; shift 2 ;;
    --duration) sim_args+=(--duration "$2"); shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --keep-replay) keep_replay=1; shift ;;
    --json) json=1; shift ;;
    --no-setup) setup=0; shift ;;
    *) fail "unknown option $1 (see --help)" ;;
  esac
done
[ -n "$profile" ] || fail "--profile NAME|FILE is required (see --help)"
[[ "$seed" =~ ^[0-9]+$ ]] || fail "--seed must be a non-negative integer, got '$seed'"
if [[ "$profile" == */* || "$profile" == *.yaml || "$profile" == *.yml ]]; then
  [ -f "$profile" ] || fail "--profile $profile: no such file"
  profile="$(realpath "$profile")"
  name="$(basename "${profile%.*}")"
else
  [ -f "$NADIR_ROOT/config/profiles/$profile.yaml" ] ||
    fail "--profile $profile: no such profile (config/profiles/: $(cd "$NADIR_ROOT/config/profiles" && ls -- *.yaml | sed 's/\.yaml$//' | tr '\n' ' '); or give a YAML file)"
  name="$profile"
fi

if [ -n "$map" ] && [ "$map" != simulated ]; then
  [ -f "$map/orthophoto.tif" ] && [ -f "$map/dem.tif" ] ||
    fail "--map $map: give 'simulated' or a folder holding orthophoto.tif and dem.tif (docs/maps.md)"
  map="$(realpath "$map")"
fi

((setup == 0)) || "$NADIR_ROOT/launch_scripts/setup.sh" >&2
for program in nadir_sim nadir_replay nadir_eval nadir_config; do
  command -v "$program" >/dev/null || fail "$program is not built (run launch_scripts/setup.sh)"
done
# A misspelt key or a bad value in an overlay stops here, not after the simulation.
nadir_config --check "${replay_args[@]}" >/dev/null || fail "the configuration with the overlays given is not valid (above)"
out="${out:-$NADIR_ROOT/logs/fly/$(nadir_utc_stamp)-$name-seed$seed}"
mkdir -p "$out/report"
sim_log="$out/sim.lcmlog"
echo "fly: $name, seed $seed${sim_args[*]:+ (${sim_args[*]})}${map:+, map $map}; output in $out" >&2
nadir_sim --profile "$profile" --seed "$seed" --out "$sim_log" "${sim_args[@]}" >"$out/sim.txt" ||
  { tail -20 "$out/sim.txt" >&2; echo "fly: error: the simulation failed (see $out/sim.txt)" >&2; exit 1; }
nodes=tracker,vo_solver,yaw_fusion
if [ -n "$map" ]; then
  command -v nadir_map >/dev/null && command -v nadir_map_matcher >/dev/null ||
    fail "--map needs nadir_map and the map matcher, built with GDAL (run launch_scripts/setup.sh)"
  if [ "$map" = simulated ]; then
    echo "fly: writing the simulated world's reference map into $out/map" >&2
    # 1 m, or coarser for a flight over so much ground that 1 m would exceed 80 million pixels:
    # up to 2 m as a real orthophoto, up to 5 m (a coarse map, fewer fixes) before giving up.
    nadir_map simulate --profile "$profile" --seed "$seed" --out "$out/map" --max-megapixels 80 --max-gsd 5 \
      >"$out/map.txt" ||
      { tail -5 "$out/map.txt" >&2; fail "the simulated map failed (see $out/map.txt)"; }
    map="$out/map"
  fi
  nodes+=,map_matcher
  replay_args+=(--set "map_matcher.orthophoto=$map/orthophoto.tif" --set "map_matcher.dem=$map/dem.tif")
  # A simulated map coarser than 1 m is matched at its own ground sample distance.
  if [ -f "$map/map.json" ]; then
    gsd="$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["gsd_m"])' "$map/map.json")"
    replay_args+=(--set "map_matcher.gsd_m=$gsd")
  fi
fi
nadir_replay --in "$sim_log" --out "$out/replay.lcmlog" --nodes "$nodes" "${replay_args[@]}" \
  >"$out/replay.txt" ||
  { tail -20 "$out/replay.txt" >&2; echo "fly: error: the replay failed (see $out/replay.txt)" >&2; exit 1; }
nadir_eval --log "$out/replay.lcmlog" --out "$out/report" >"$out/report/summary.txt" ||
  { echo "fly: error: the evaluation failed" >&2; exit 1; }
((keep_replay)) || rm -f "$out/replay.lcmlog"
if ((json)); then
  cat "$out/report/metrics.json"
else
  echo "=== nadir fly: $name, seed $seed ==="
  cat "$out/report/summary.txt"
  echo "simulator log: $sim_log$( ((keep_replay)) && echo "; replay: $out/replay.lcmlog")"
fi
