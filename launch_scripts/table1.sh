#!/usr/bin/env bash
# The paper's Table 1 on simulated flights: test1, test2, test3 with the
# standard sensor set and fixed seeds, replayed in lockstep and evaluated.
# Prints a markdown table with the paper's figures beside ours.
# Usage: table1.sh [--reuse]   (--reuse keeps simulator logs already in logs/table1/)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/eval_common.sh"
[ "${1:-}" = "--reuse" ] && export NADIR_REUSE=1
[ "${1:-}" = "-h" ] || [ "${1:-}" = "--help" ] && { sed -n '2,5p' "$0" | sed 's/^# \{0,1\}//'; exit 0; }
"$NADIR_ROOT/launch_scripts/setup.sh" >/dev/null
out="$NADIR_ROOT/logs/table1"
mkdir -p "$out"
declare -A seed=([test1]=101 [test2]=102 [test3]=103)
declare -A paper=([test1]="7800m | 300m | 30m/s | 0.39%" [test2]="3700m | 150m | 20m/s | 0.73%" [test3]="4500m | 200m | 20m/s | 0.78%")
for t in test1 test2 test3; do
  echo "$t:"
  simulate "$t" "${seed[$t]}" "$out/$t.lcmlog"
  replay_and_eval "$out/$t.lcmlog" "$out/$t"
done
{
  echo "| Test | Paper: distance | altitude | speed | accuracy | nadir (sim): distance | final error | error % of distance | horizontal % | vertical % |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
  for t in test1 test2 test3; do
    d="$out/$t"
    echo "| ${t#test} | ${paper[$t]} | $(metric "$d" distance_m) m | $(metric "$d" final_error_3d_m) m | $(metric "$d" error_pct_3d) % | $(metric "$d" error_pct_h) % | $(metric "$d" error_pct_v) % |"
  done
} | tee "$out/table1.md"
echo "reports: $out/test*/ (trajectory.png, drift.png, velocity_errors.png, metrics.json)"
