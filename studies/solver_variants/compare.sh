#!/usr/bin/env bash
# The solver variants (feature_depth, the default; paper; level_ground;
# homography; flow) on the same simulated flights: test1-3 with the standard
# sensor set, each flown with several fixed seeds (the first is table1.sh's).
# Markdown tables of the final and the RMS 3-D error (% of distance flown),
# mean over the seeds and per seed, the default variant's margin over the best
# other, and bar charts.
# Usage: compare.sh [--reuse] [--reuse-evals] [--seeds N]   (N = 1..3 seeds per profile, default 3)
#   --reuse keeps existing simulations; --reuse-evals also keeps existing evaluations.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../../launch_scripts/eval_common.sh"
n_seeds=3
reuse_evals=0
while (($#)); do
  case "$1" in
    --reuse) export NADIR_REUSE=1; shift ;;
    --reuse-evals) export NADIR_REUSE=1; reuse_evals=1; shift ;;
    --seeds) n_seeds="$2"; shift 2 ;;
    -h|--help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "compare: error: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ "$n_seeds" =~ ^[123]$ ]] || { echo "compare: error: --seeds must be 1, 2 or 3" >&2; exit 2; }
"$NADIR_ROOT/launch_scripts/setup.sh" >/dev/null
sims="$NADIR_ROOT/logs/table1"
out="$NADIR_ROOT/logs/compare"
mkdir -p "$sims" "$out/sims"
declare -A seeds=([test1]="101 104 107" [test2]="102 105 108" [test3]="103 106 109")
variants=(feature_depth paper level_ground homography flow)
runs=()
for t in test1 test2 test3; do
  read -ra all <<< "${seeds[$t]}"
  used=("${all[@]:0:$n_seeds}")
  runs+=("$t=$(IFS=,; echo "${used[*]}")")
  for s in "${used[@]}"; do
    log="$out/sims/$t-$s.lcmlog"
    [ "$s" = "${all[0]}" ] && log="$sims/$t.lcmlog"   # table1.sh's flight
    simulate "$t" "$s" "$log"
    for v in "${variants[@]}"; do
      if [ "$reuse_evals" = 1 ] && [ -s "$out/$t-$s-$v/metrics.json" ] && [ "$out/$t-$s-$v/metrics.json" -nt "$log" ]; then
        echo "  reuse $t seed $s / $v"
        continue
      fi
      echo "  $t seed $s / $v"
      replay_and_eval "$log" "$out/$t-$s-$v" --set "vo_solver.variant=$v"
    done
  done
done
/usr/bin/python3 "$NADIR_ROOT/studies/solver_variants/variant_table.py" --root "$out" --variants "$(IFS=,; echo "${variants[*]}")" \
  "${runs[@]}" | tee "$out/compare.md"
for t in test1 test2 test3; do
  read -ra all <<< "${seeds[$t]}"
  /usr/bin/python3 "$NADIR_ROOT/studies/lib/plot_bars.py" --out "$out/compare-$t.png" \
    --title "Solver variants on $t, seed ${all[0]} (3-D error, % of distance)" --metrics error_pct_3d,rms_error_pct_3d \
    --labels "final %,RMS over the flight %" $(for v in "${variants[@]}"; do echo "$v=$out/$t-${all[0]}-$v"; done)
done
echo "charts: $out/compare-test*.png"
