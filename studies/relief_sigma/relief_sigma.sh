#!/usr/bin/env bash
# The reported covariance on flights nothing was tuned on, and the relief term's
# fit (docs/research/2026-12-relief-sigma.md). Each PROFILE:SEED is simulated
# (PROFILE: a name under config/profiles/ or one of this folder's heli_low,
# high_fast, racetrack), replayed with the defaults and evaluated into
# logs/relief_sigma/PROFILE-SEED/default; with --fit it is also replayed with
# the relief term off (relief0/), at one height (relief1/), and off with the
# one-plane walk raised (paper_walk/: only the pairs the paper alone solved
# move), each replay's VO_DELTA written beside it for relief_fit.py. The
# estimates are the same in all of them. Extra nadir_sim options
# (e.g. --relief-scale 3) go after --sim, up to the next flight.
# Usage: relief_sigma.sh [--fit] [--reuse] PROFILE:SEED [--sim OPTION...] ...
# Then:  studies/relief_sigma/relief_fit.py logs/relief_sigma/*   (after --fit)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/../../launch_scripts/eval_common.sh"
fit=0
flights=()
declare -A sim_options=()
while (($#)); do
  case "$1" in
    --fit) fit=1; shift ;;
    --reuse) export NADIR_REUSE=1; shift ;;
    --sim) shift; [ ${#flights[@]} -gt 0 ] || { echo "relief_sigma: error: --sim before any PROFILE:SEED" >&2; exit 2; }
           while (($#)) && [[ "$1" != *:* || "$1" == -* ]]; do sim_options[${flights[-1]}]+=" $1"; shift; done ;;
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "relief_sigma: error: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) flights+=("$1"); shift ;;
  esac
done
((${#flights[@]})) || { echo "relief_sigma: error: no PROFILE:SEED given (see --help)" >&2; exit 2; }
"$NADIR_ROOT/launch_scripts/setup.sh" >/dev/null
out="$NADIR_ROOT/logs/relief_sigma"
mkdir -p "$out"
for f in "${flights[@]}"; do
  IFS=: read -r profile seed <<<"$f"
  [ -n "$seed" ] || { echo "relief_sigma: error: '$f' is not PROFILE:SEED" >&2; exit 2; }
  profile_arg="$profile"
  [ -f "$here/$profile.yaml" ] && profile_arg="$here/$profile.yaml"
  dir="$out/$profile-$seed"
  mkdir -p "$dir"
  # shellcheck disable=SC2086  # the options are words
  simulate "$profile_arg" "$seed" "$dir/sim.lcmlog" ${sim_options[$f]:-}
  replay_and_eval "$dir/sim.lcmlog" "$dir/default"
  echo "$profile-$seed default: NEES $(metric "$dir/default" nees_h_mean)," \
       "beyond the protection level $(metric "$dir/default" pl_exceeded_pct) %, error $(metric "$dir/default" error_pct_3d) %"
  if [ "$fit" = 1 ]; then
    for run in relief0:0:0.068 relief1:1:0.068 paper_walk:0:0.168; do
      IFS=: read -r name heights walk <<<"$run"
      mkdir -p "$dir/$name"
      nadir_replay --in "$dir/sim.lcmlog" --out "$dir/$name/replay.lcmlog" --nodes tracker,vo_solver,yaw_fusion \
        --set "vo_solver.uncertainty.feature_depth_relief_heights=$heights" \
        --set "vo_solver.uncertainty.relief_walk_along_m_per_sqrt_m=$walk" --json >"$dir/$name/replay.json"
      nadir_log dump "$dir/$name/replay.lcmlog" VO_DELTA -o "$dir/$name/delta.csv" 2>/dev/null
      [ "$name" = relief0 ] && nadir_eval --log "$dir/$name/replay.lcmlog" --out "$dir/$name" --no-plots --json >/dev/null
      rm -f "$dir/$name/replay.lcmlog"
    done
  fi
done
