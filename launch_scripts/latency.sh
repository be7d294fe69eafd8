#!/usr/bin/env bash
# Trigger -> POSE latency of a live process set over several runs:
# flies the demo profile through SET (sim: separate processes; sim_composed:
# the estimator nodes in one process) RUNS times inside the private network
# namespace, evaluates each capture and prints per run the latency by stage
# (p50/p99/worst) with the load average, then the medians over the runs.
# Usage: latency.sh [--set sim|sim_composed] [--runs N] [--attitude-policy auto|propagate|interpolate]
#        [--nice N] [--rt-priority P|off] [--keep-captures]   (reports in logs/latency/<UTC>-SET-POLICY/;
#        captures deleted unless kept; --nice runs the whole set at that niceness, e.g. -10 on a machine
#        others load; the set's own `realtime` priority applies where granted, as in the demo;
#        --rt-priority P insists on SCHED_FIFO P for the estimator nodes, the logger and the simulator's
#        publisher, off declines it: run_set.sh --rt-priority)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
set_name=sim
runs=5
keep=0
policy=""
niceness=0
rt_args=()
while (($#)); do
  case "$1" in
    -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --set) set_name="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --attitude-policy) policy="$2"; shift 2 ;;
    --nice) niceness="$2"; shift 2 ;;
    --rt-priority) rt_args=(--rt-priority "$2"); shift 2 ;;
    --keep-captures) keep=1; shift ;;
    *) echo "latency: error: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "latency: error: --runs must be a positive integer, got '$runs'" >&2; exit 2; }
export NADIR_NETNS_KEEP_CAPS=1   # as root: CAP_SYS_NICE survives, as in the demo
out="$NADIR_ROOT/logs/latency/$(nadir_utc_stamp)-$set_name${policy:+-$policy}-nice$niceness${rt_args[1]:+-rt${rt_args[1]}}"
mkdir -p "$out"
if [ -n "$policy" ]; then
  nadir_config_with_attitude_policy "$policy" "$out/config.yaml"
  export NADIR_CONFIG="$out/config.yaml"   # every process of the set reads it
fi
for ((i = 1; i <= runs; i++)); do
  run_dir="$out/run$i"
  load_before=$(cut -d' ' -f1 /proc/loadavg)
  NADIR_PROFILE=demo NADIR_SEED=1 NADIR_CAPTURE_DIR="$run_dir" \
    nice -n "$niceness" bash -c "$(declare -f nadir_in_netns); nadir_in_netns \"\$@\"" _ \
    "$NADIR_ROOT/launch_scripts/run_set.sh" "$set_name" "${rt_args[@]}" >"$run_dir.txt" 2>&1 ||
    { tail -20 "$run_dir.txt" >&2; echo "latency: error: run $i of set $set_name failed" >&2; exit 1; }
  load_after=$(cut -d' ' -f1 /proc/loadavg)
  mkdir -p "$run_dir/report"
  nadir_eval --log "$run_dir/capture.lcmlog" --out "$run_dir/report" >"$run_dir/report/summary.txt"
  ((keep)) || rm -f "$run_dir/capture.lcmlog"
  echo "run $i (load average $load_before -> $load_after, nice $niceness):"
  grep -E '^latency' "$run_dir/report/summary.txt" | sed 's/^/  /'
  echo "$load_before $load_after" >"$run_dir/load.txt"
done
/usr/bin/python3 - "$out" "$runs" <<'PY'
import json, statistics, sys
out, runs = sys.argv[1], int(sys.argv[2])
m = [json.load(open(f"{out}/run{i}/report/metrics.json")) for i in range(1, runs + 1)]
p50 = [x["latency_p50_ms"] for x in m]
p99 = [x["latency_p99_ms"] for x in m]
worst = [x["latency_max_ms"] for x in m]
print(f"trigger -> POSE over {runs} runs: p50 median {statistics.median(p50):.1f} ms; "
      f"p99 median {statistics.median(p99):.1f} ms (runs: {', '.join('%.1f' % v for v in p99)}); "
      f"worst {max(worst):.1f} ms")
after = [x.get("after_image_latency_p99_ms") for x in m]
if all(v is not None for v in after):
    print(f"after the image (POSE logged - CAMERA_IMAGE logged) over {runs} runs: p50 median "
          f"{statistics.median(x['after_image_latency_p50_ms'] for x in m):.1f} ms; p99 median "
          f"{statistics.median(after):.1f} ms (runs: {', '.join('%.1f' % v for v in after)}); "
          f"worst {max(x['after_image_latency_max_ms'] for x in m):.1f} ms")
PY
echo "reports: $out/run*/report/"
