#!/usr/bin/env bash
# Coasting over near-featureless ground (docs/research/2026-12-coasting.md):
# each flight simulated without and with a texture outage (contrast cut to
# CONTRAST for DURATION s from START s), replayed in lockstep through tracker,
# vo_solver and yaw_fusion with an overlay (default follow_altimeter.yaml: the
# height from the altimeter, weighted against the held climb) and with
# held_climb.yaml (the climb rate held, neither ground followed), evaluated;
# prints a markdown table (coasting_summary.py) and writes it to
# logs/coasting/summary.md.
# Usage: coasting_study.sh [--reuse] [--duration S] [--contrast C] [--overlay FILE] PROFILE:SEED:START ...
#   e.g. coasting_study.sh test2:311:90 test2:312:125 test2:313:150 test3:314:60
#        coasting_study.sh --overlay studies/coasting/seen_ground.yaml test2:1601:90
#   --reuse      keeps simulator logs already in logs/coasting/
#   --duration   outage length (default 10 s); --contrast remaining contrast (default 0.03)
#   --overlay    the configuration overlay of the "texture" run
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/../../launch_scripts/eval_common.sh"
duration=10
contrast=0.03
overlay="$here/follow_altimeter.yaml"
flights=()
while (($#)); do
  case "$1" in
    --reuse) export NADIR_REUSE=1; shift ;;
    --duration) duration="$2"; shift 2 ;;
    --contrast) contrast="$2"; shift 2 ;;
    --overlay) overlay="$(cd "$(dirname "$2")" && pwd)/$(basename "$2")"; shift 2 ;;
    -h|--help) sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "coasting_study: error: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) flights+=("$1"); shift ;;
  esac
done
((${#flights[@]})) || { echo "coasting_study: error: no PROFILE:SEED:START given (see --help)" >&2; exit 2; }
"$NADIR_ROOT/launch_scripts/setup.sh" >/dev/null
out="$NADIR_ROOT/logs/coasting"
mkdir -p "$out"
rows=()
for f in "${flights[@]}"; do
  IFS=: read -r profile seed start <<<"$f"
  [ -n "$start" ] || { echo "coasting_study: error: '$f' is not PROFILE:SEED:START" >&2; exit 2; }
  name="$profile-$seed"
  echo "$name (texture outage $start s + $duration s, contrast $contrast):"
  simulate "$profile" "$seed" "$out/$name.lcmlog"
  outage="$out/$name-texture-$start-$duration-$contrast.lcmlog"
  runs="$out/$name-$start"
  simulate "$profile" "$seed" "$outage" --outage "texture:$start:$duration:$contrast"
  replay_and_eval "$out/$name.lcmlog" "$runs/clean"
  replay_and_eval "$outage" "$runs/texture" --config-overlay "$overlay"
  basename "$overlay" .yaml >"$runs/texture/overlay.txt"
  replay_and_eval "$outage" "$runs/texture-held" --config-overlay "$here/held_climb.yaml"
  rows+=("$runs:$start:$duration")
done
/usr/bin/python3 "$here/coasting_summary.py" "${rows[@]}" | tee "$out/summary.md"
