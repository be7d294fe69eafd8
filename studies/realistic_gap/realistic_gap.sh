#!/usr/bin/env bash
# What the `realistic` sensor set's Table 1 gap to `standard` is made of
# (docs/research/2026-12-realistic-gap.md). Each PROFILE:SEED is simulated three
# times with the same seed: `standard`, `realistic`, and `realistic` with the INS
# heading error taken out (sensors.yaml beside this script; the same noise
# everywhere else). The realistic flight is replayed once per installation given
# with --installation NAME=FILE (calibration fragments or the true installation,
# each with config/uncertainty/realistic.yaml), the heading-free one with the
# first installation. Everything is evaluated under logs/realistic_gap/;
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
    -h|--help) sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
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
for f in "${flights[@]}"; do
  IFS=: read -r profile seed <<<"$f"
  [ -n "$seed" ] || { echo "realistic_gap: error: '$f' is not PROFILE:SEED" >&2; exit 2; }
  name="$profile-$seed"
  simulate "$profile" "$seed" "$out/$name-standard.lcmlog"
  replay_and_eval "$out/$name-standard.lcmlog" "$out/$name-standard"
  echo "$name standard error_pct_3d $(metric "$out/$name-standard" error_pct_3d)"
  simulate "$profile" "$seed" "$out/$name-realistic.lcmlog" --sensor-set realistic
  for i in "${installations[@]}"; do
    replay_and_eval "$out/$name-realistic.lcmlog" "$out/$name-realistic-${i%%=*}" --config-overlay "${i#*=}" "${uncertainty[@]}"
    echo "$name realistic-${i%%=*} error_pct_3d $(metric "$out/$name-realistic-${i%%=*}" error_pct_3d)"
  done
  first="${installations[0]}"
  simulate "$profile" "$seed" "$out/$name-exact_heading.lcmlog" --sensors "$here/sensors.yaml" --sensor-set realistic_exact_heading
  replay_and_eval "$out/$name-exact_heading.lcmlog" "$out/$name-exact_heading-${first%%=*}" --config-overlay "${first#*=}" "${uncertainty[@]}"
  echo "$name exact_heading-${first%%=*} error_pct_3d $(metric "$out/$name-exact_heading-${first%%=*}" error_pct_3d)"
done
