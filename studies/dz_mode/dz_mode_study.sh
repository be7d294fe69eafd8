#!/usr/bin/env bash
# Evidence for vo_solver.dz_mode beyond Table 1: flights simulated with a
# sensor set and seeds given here, each replayed twice (dz_mode forward and
# symmetric, nothing else changed), evaluated; prints a markdown table of the
# final 3-D, horizontal and vertical error (% of distance) per flight and mode.
# Usage: dz_mode_study.sh SET PROFILE:SEED [PROFILE:SEED ...]
#   e.g. dz_mode_study.sh correlated_ins test1:111 test2:112 test3:113
# Results under logs/dz_mode/SET/. NADIR_REUSE=1 keeps existing simulations.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../../launch_scripts/eval_common.sh"
if [ "${1:-}" = "-h" ] || [ "${1:-}" = "--help" ]; then
  sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'
  exit 0
fi
if [ $# -lt 2 ]; then
  echo "dz_mode_study: error: need a sensor set and at least one PROFILE:SEED (--help)" >&2
  exit 2
fi
set_name="$1"; shift
out="$NADIR_ROOT/logs/dz_mode/$set_name"
mkdir -p "$out"
rows=()
for run in "$@"; do
  profile="${run%%:*}" seed="${run##*:}"
  [[ "$seed" =~ ^[0-9]+$ ]] || { echo "dz_mode_study: error: '$run' is not PROFILE:SEED" >&2; exit 2; }
  log="$out/$profile-$seed.lcmlog"
  simulate "$profile" "$seed" "$log" --sensor-set "$set_name"
  row="| $profile | $seed |"
  for mode in forward symmetric; do
    d="$out/$profile-$seed-$mode"
    replay_and_eval "$log" "$d" --set "vo_solver.dz_mode=$mode"
    row+=" $(metric "$d" error_pct_3d) / $(metric "$d" error_pct_h) / $(metric "$d" error_pct_v) |"
  done
  rows+=("$row")
  echo "$row"
done
{
  echo "| profile | seed | forward: 3-D / horizontal / vertical % | symmetric: 3-D / horizontal / vertical % |"
  echo "|---|---|---|---|"
  printf '%s\n' "${rows[@]}"
} | tee "$out/dz_mode.md"
