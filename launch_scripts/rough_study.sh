#!/usr/bin/env bash
# Rough ground against flat ground (issue 16): each rough profile flown with
# each seed twice, over its own relief and over flat ground (nadir_sim
# --relief-scale 0: the same trajectory, sensors and noise), replayed with
# each solver variant and evaluated. Prints the final error (% of distance)
# per flight and the rough/flat ratio per seed with its median; writes
# summary.json and summary.csv under logs/rough_study/<UTC stamp>/.
# Simulator logs are cached in logs/rough_study/sims/ and reused when present.
# Usage: rough_study.sh [--profiles rough_120,rough_250] [--seeds "1 2 3"]
#          [--variants paper[,feature_depth]] [--duration S] [--nice N]
#          [--config-overlay FILE]... [--set section.key=value]...
#   --duration S   simulate only the first S seconds (a quick look; cached apart)
#   --nice N       niceness of every step (default 10)
#   --config-overlay FILE  a config overlay for every replay (before the variant's)
#   --set K=V      a config override for every replay (after the overlays), e.g.
#                  --set tracker.klt_window_warp=false (the plain KLT)
# Needs nadir_sim, nadir_replay and nadir_eval built (launch_scripts/setup.sh).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/eval_common.sh"
profiles=rough_120,rough_250
seeds="1 2 3"
variants=paper
duration=""
niceness=10
overlays=()  # add_config_overlay (eval_common.sh) appends here
report_suffix=""
extra_sets=()
usage() { sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; }
while (($#)); do
  case "$1" in
    --profiles) profiles="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    --variants) variants="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    --nice) niceness="$2"; shift 2 ;;
    --config-overlay) add_config_overlay rough_study "$2"; shift 2 ;;
    --set) extra_sets+=(--set "$2"); shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "rough_study: error: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
[[ "$niceness" =~ ^[0-9]+$ ]] && ((niceness <= 19)) || { echo "rough_study: error: --nice must be 0..19" >&2; exit 2; }
[ -z "$duration" ] || [[ "$duration" =~ ^[0-9]+([.][0-9]+)?$ ]] ||
  { echo "rough_study: error: --duration must be a number of seconds" >&2; exit 2; }
for s in $seeds; do [[ "$s" =~ ^[0-9]+$ ]] || { echo "rough_study: error: bad seed '$s'" >&2; exit 2; }; done
IFS=, read -r -a profile_list <<<"$profiles"
IFS=, read -r -a variant_list <<<"$variants"
for p in "${profile_list[@]}"; do
  [ -f "$NADIR_ROOT/config/profiles/$p.yaml" ] || { echo "rough_study: error: no profile config/profiles/$p.yaml" >&2; exit 2; }
done
for v in "${variant_list[@]}"; do
  [[ "$v" =~ ^[a-z_]+$ ]] || { echo "rough_study: error: bad variant name '$v'" >&2; exit 2; }
done

for tool in nadir_sim nadir_replay nadir_eval; do
  command -v "$tool" >/dev/null || { echo "rough_study: error: $tool not built (launch_scripts/setup.sh)" >&2; exit 1; }
done
renice -n "$niceness" -p $$ >/dev/null  # every step below inherits it: the machine is shared
study="$NADIR_ROOT/logs/rough_study"
sims="$study/sims"
out="$study/$(nadir_utc_stamp)"
mkdir -p "$sims" "$out"
suffix=""
[ -n "$duration" ] && suffix="_${duration}s"

# sim_log PROFILE SEED GROUND (rough | flat): simulates once, then reuses.
sim_log() {
  local p="$1" s="$2" ground="$3"
  local f="$sims/${p}_seed${s}_${ground}${suffix}.lcmlog"
  if [ ! -s "$f" ]; then
    local args=(--profile "$p" --seed "$s" --out "$f.tmp" --json)
    [ "$ground" = flat ] && args+=(--relief-scale 0)
    [ -n "$duration" ] && args+=(--duration "$duration")
    echo "  simulate $p seed $s $ground -> $f" >&2
    nadir_sim "${args[@]}" >"$f.sim.json" 2>"$f.sim.txt" || { cat "$f.sim.txt" >&2; return 1; }
    mv "$f.tmp" "$f"
  fi
  echo "$f"
}

rows="$out/rows.csv"
echo "profile,seed,ground,variant,final_error_pct,final_error_m,distance_m" >"$rows"
for p in "${profile_list[@]}"; do
  for s in $seeds; do
    for ground in rough flat; do
      echo "$p seed $s, $ground ground:"
      log=$(sim_log "$p" "$s" "$ground")
      for v in "${variant_list[@]}"; do
        d="$out/$p/seed$s/$ground/$v"
        mkdir -p "$d"
        printf 'vo_solver:\n  variant: %s\n' "$v" >"$d/overlay.yaml"
        replay_and_eval "$log" "$d" "${overlays[@]}" --config-overlay "$d/overlay.yaml" "${extra_sets[@]}"
        echo "$p,$s,$ground,$v,$(metric "$d" error_pct_3d),$(metric "$d" final_error_3d_m),$(metric "$d" distance_m)" >>"$rows"
        echo "  $v: final error $(metric "$d" error_pct_3d) % of distance"
      done
    done
  done
done

/usr/bin/python3 - "$rows" "$out" <<'EOF'
import csv, json, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
out = sys.argv[2]
err = {(r["profile"], int(r["seed"]), r["ground"], r["variant"]): float(r["final_error_pct"]) for r in rows}
groups = sorted({(r["profile"], r["variant"]) for r in rows})
summary = []
print("| profile | variant | seed | rough: final error % | flat: final error % | rough / flat |")
print("|---|---|---|---|---|---|")
for p, v in groups:
    seeds = sorted({k[1] for k in err if k[0] == p and k[3] == v})
    ratios = []
    for s in seeds:
        rough, flat = err[(p, s, "rough", v)], err[(p, s, "flat", v)]
        ratio = rough / flat if flat > 0 else float("inf")
        ratios.append(ratio)
        summary.append({"profile": p, "variant": v, "seed": s, "rough_error_pct": rough, "flat_error_pct": flat,
                        "ratio": ratio})
        print(f"| {p} | {v} | {s} | {rough:.3f} | {flat:.3f} | {ratio:.2f} |")
    med = statistics.median(ratios)
    summary.append({"profile": p, "variant": v, "seed": "median", "ratio": med})
    print(f"| {p} | {v} | median | | | **{med:.2f}** |")
json.dump(summary, open(out + "/summary.json", "w"), indent=1)
with open(out + "/summary.csv", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=["profile", "variant", "seed", "rough_error_pct", "flat_error_pct", "ratio"])
    w.writeheader()
    w.writerows(summary)
EOF
echo "summary: $out/summary.json $out/summary.csv (per-flight reports under $out/<profile>/seed<N>/<ground>/<variant>/)"
