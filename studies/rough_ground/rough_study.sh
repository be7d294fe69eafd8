#!/usr/bin/env bash
# Rough ground against flat ground: each rough profile flown with
# each seed twice, over its own relief and over flat ground (nadir_sim
# --relief-scale 0: the same trajectory, sensors and noise), replayed with
# each solver variant and evaluated. Prints the final error (% of distance)
# per flight and the rough/flat ratio per seed; over all the seeds, the ratio
# of the mean errors with a 90 % bootstrap interval, the flights within 1.5x
# and the ratio over each run of three seeds (rough_study_summary.py, which
# also pools the rows.csv of several studies); writes summary.json and
# summary.csv under logs/rough_study/<UTC stamp>/.
# Simulator logs are cached in logs/rough_study/sims/ and reused when present
# (about 1 GB a flight; --drop-sims deletes each once replayed).
# Usage: rough_study.sh [--profiles rough_120,rough_250] [--seeds "1 2 3"]
#          [--variants paper[,feature_depth]] [--duration S] [--nice N]
#          [--config-overlay FILE]... [--set section.key=value]... [--drop-sims]
#   --duration S   simulate only the first S seconds (a quick look; cached apart)
#   --nice N       niceness of every step (default 10)
#   --config-overlay FILE  a config overlay for every replay (before the variant's)
#   --set K=V      a config override for every replay (after the overlays), e.g.
#                  --set tracker.klt_window_warp=false (the plain KLT)
#   --drop-sims    delete each simulator log once replayed, cached ones too (many
#                  seeds, little disk)
# Needs nadir_sim, nadir_replay and nadir_eval built (launch_scripts/setup.sh).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../../launch_scripts/eval_common.sh"
profiles=rough_120,rough_250
seeds="1 2 3"
variants=paper
duration=""
niceness=10
overlays=()  # add_config_overlay (eval_common.sh) appends here
report_suffix=""
extra_sets=()
drop_sims=0
usage() { sed -n '2,23p' "$0" | sed 's/^# \{0,1\}//'; }
while (($#)); do
  case "$1" in
    --profiles) profiles="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    --variants) variants="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    --nice) niceness="$2"; shift 2 ;;
    --config-overlay) add_config_overlay rough_study "$2"; shift 2 ;;
    --set) extra_sets+=(--set "$2"); shift 2 ;;
    --drop-sims) drop_sims=1; shift ;;
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
      if ((drop_sims)); then rm -f "$log"; fi
    done
  done
done

"$(dirname "${BASH_SOURCE[0]}")/rough_study_summary.py" "$rows" --out "$out"
echo "summary: $out/summary.json $out/summary.csv (per-flight reports under $out/<profile>/seed<N>/<ground>/<variant>/)"
