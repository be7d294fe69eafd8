#!/usr/bin/env bash
# The solver variants (paper, level_ground, homography, flow) on the same
# simulated flights (test1-3, standard sensors, the seeds of table1.sh):
# a markdown table of error % of distance and a bar chart.
# Usage: compare.sh [--reuse]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/eval_common.sh"
[ "${1:-}" = "--reuse" ] && export NADIR_REUSE=1
[ "${1:-}" = "-h" ] || [ "${1:-}" = "--help" ] && { sed -n '2,5p' "$0" | sed 's/^# \{0,1\}//'; exit 0; }
"$NADIR_ROOT/launch_scripts/setup.sh" >/dev/null
sims="$NADIR_ROOT/logs/table1"
out="$NADIR_ROOT/logs/compare"
mkdir -p "$sims" "$out"
declare -A seed=([test1]=101 [test2]=102 [test3]=103)
variants=(paper level_ground homography flow)
for t in test1 test2 test3; do
  simulate "$t" "${seed[$t]}" "$sims/$t.lcmlog"
  for v in "${variants[@]}"; do
    echo "  $t / $v"
    replay_and_eval "$sims/$t.lcmlog" "$out/$t-$v" --set "vo_solver.variant=$v"
  done
done
{
  echo "| variant | test1 error % | test2 error % | test3 error % |"
  echo "|---|---|---|---|"
  for v in "${variants[@]}"; do
    echo "| $v | $(metric "$out/test1-$v" error_pct_3d) | $(metric "$out/test2-$v" error_pct_3d) | $(metric "$out/test3-$v" error_pct_3d) |"
  done
} | tee "$out/compare.md"
for t in test1 test2 test3; do
  /usr/bin/python3 "$NADIR_ROOT/tools/eval/plot_bars.py" --out "$out/compare-$t.png" \
    --title "Solver variants on $t (error % of distance)" --metrics error_pct_h,error_pct_v \
    --labels "horizontal %,vertical %" $(for v in "${variants[@]}"; do echo "$v=$out/$t-$v"; done)
done
echo "charts: $out/compare-test*.png"
