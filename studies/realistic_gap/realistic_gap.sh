#!/usr/bin/env bash
# What the `realistic` sensor set's Table 1 gap to `standard` is made of
# (docs/research/2026-12-realistic-gap.md). Each PROFILE:SEED is simulated three
# times with the same seed: `standard`, `realistic`, and `realistic` with the INS
# heading error taken out (a set written from config/sim_sensors.yaml's
# `realistic` with no Gauss-Markov heading error and no walk; the simulator
# draws the first from a stream of its own and the walk whatever its size, so
# the noise elsewhere is the same). The realistic flight is replayed once per
# installation given with --installation NAME=FILE (calibration fragments or the
# true installation, each with config/uncertainty/realistic.yaml), the
# heading-free one with the first installation. Everything is evaluated under logs/realistic_gap/;
# realistic_gap_summary.py makes the tables.
# Usage: realistic_gap.sh [--reuse] [--installation NAME=FILE]... PROFILE:SEED ...
#   default installations: cal97=config/installation/realistic_calibrated.yaml (97 s flight)
#                          cal600=config/installation/realistic_calibrated_long.yaml (600 s)
#                          true=config/installation/realistic_true.yaml
#   --reuse   keeps simulator logs already in logs/realistic_gap/
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/../../launch_scripts/eval_common.sh"
flights=()
installations=()
while (($#)); do
  case "$1" in
    --reuse) export NADIR_REUSE=1; shift ;;
    --installation) installations+=("$2"); shift 2 ;;
    -h|--help) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "realistic_gap: error: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) flights+=("$1"); shift ;;
  esac
done
((${#flights[@]})) || { echo "realistic_gap: error: no PROFILE:SEED given (see --help)" >&2; exit 2; }
((${#installations[@]})) || installations=("cal97=$NADIR_ROOT/config/installation/realistic_calibrated.yaml"
                                           "cal600=$NADIR_ROOT/config/installation/realistic_calibrated_long.yaml"
                                           "true=$NADIR_ROOT/config/installation/realistic_true.yaml")
for i in "${installations[@]}"; do
  [[ "$i" == *=* && -f "${i#*=}" ]] || { echo "realistic_gap: error: --installation $i: not NAME=FILE with FILE present" >&2; exit 2; }
done
"$NADIR_ROOT/launch_scripts/setup.sh" >/dev/null
out="$NADIR_ROOT/logs/realistic_gap"
mkdir -p "$out"
uncertainty=(--config-overlay "$NADIR_ROOT/config/uncertainty/realistic.yaml")
# `realistic` with its heading error taken out, written from the project's set so it never goes stale.
exact_heading="$out/sensors_exact_heading.yaml"
awk '/^realistic:/ {on = 1; print "realistic_exact_heading:"; next}
     on && /^[^ ]/ {exit}
     on' "$NADIR_ROOT/config/sim_sensors.yaml" |
  sed -E 's/^( +yaw_gm_sigma_deg:).*/\1 0.0/; s/^( +yaw_bias_walk_deg_per_sqrt_s:).*/\1 0.0/' >"$exact_heading"
grep -q 'yaw_gm_sigma_deg: 0.0$' "$exact_heading" ||
  { echo "realistic_gap: error: config/sim_sensors.yaml's realistic set has no yaw_gm_sigma_deg to take out" >&2; exit 1; }
# evaluate SIM_LOG RUN [replay options...]: replays and evaluates into $out/$name-RUN, prints its error.
evaluate() {
  replay_and_eval "$1" "$out/$name-$2" "${@:3}"
  echo "$name $2 error_pct_3d $(metric "$out/$name-$2" error_pct_3d)"
}
for f in "${flights[@]}"; do
  IFS=: read -r profile seed <<<"$f"
  [ -n "$seed" ] || { echo "realistic_gap: error: '$f' is not PROFILE:SEED" >&2; exit 2; }
  name="$profile-$seed"
  simulate "$profile" "$seed" "$out/$name-standard.lcmlog"
  evaluate "$out/$name-standard.lcmlog" standard
  simulate "$profile" "$seed" "$out/$name-realistic.lcmlog" --sensor-set realistic
  for i in "${installations[@]}"; do
    evaluate "$out/$name-realistic.lcmlog" "realistic-${i%%=*}" --config-overlay "${i#*=}" "${uncertainty[@]}"
  done
  first="${installations[0]}"
  simulate "$profile" "$seed" "$out/$name-exact_heading.lcmlog" --sensors "$exact_heading" --sensor-set realistic_exact_heading
  evaluate "$out/$name-exact_heading.lcmlog" "exact_heading-${first%%=*}" --config-overlay "${first#*=}" "${uncertainty[@]}"
done
