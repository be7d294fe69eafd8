# Sourced by table1.sh and by the study scripts under studies/: simulate, replay in
# lockstep, evaluate. Results go under logs/<study>/.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

# simulate PROFILE SEED OUT [nadir_sim options...]: skipped when OUT exists and --reuse was given.
simulate() {
  local profile="$1" seed="$2" out="$3"; shift 3
  if [ "${NADIR_REUSE:-0}" = 1 ] && [ -s "$out" ]; then
    echo "  reuse $out"
    return 0
  fi
  echo "  nadir_sim --profile $profile --seed $seed $* -> $out"
  nadir_sim --profile "$profile" --seed "$seed" --out "$out" "$@" >"$out.sim.txt" 2>&1 ||
    { cat "$out.sim.txt" >&2; return 1; }
}

# replay_and_eval SIM_LOG OUT_DIR [nadir_replay options...]: prints metrics.json's path.
replay_and_eval() {
  local sim_log="$1" out_dir="$2"; shift 2
  mkdir -p "$out_dir"
  nadir_replay --in "$sim_log" --out "$out_dir/replay.lcmlog" --nodes tracker,vo_solver,yaw_fusion --json "$@" \
    >"$out_dir/replay.json" || return 1
  nadir_eval --log "$out_dir/replay.lcmlog" --out "$out_dir" --json >/dev/null || return 1
  rm -f "$out_dir/replay.lcmlog"   # large; the sim log and config reproduce it bit for bit
}

# metric DIR KEY: one number from DIR/metrics.json
metric() { /usr/bin/python3 -c 'import json,sys; print("%.3f" % json.load(open(sys.argv[1]))[sys.argv[2]])' "$1/metrics.json" "$2"; }

# The options table1.sh and noise_study.sh share. The caller
# declares sim_args=() overlays=() report_suffix="".
# use_sensor_set NAME OUT_VAR: simulate with config/sim_sensors.yaml's set NAME
# (standard: nothing to add); other sets get their own logs, OUT_VAR-NAME.
use_sensor_set() {
  [ "$1" = standard ] && return 0
  sim_args=(--sensor-set "$1")
  printf -v "$2" '%s-%s' "${!2}" "$1"
}
# add_config_overlay TOOL FILE: replay with FILE merged into the config; the
# reports get -<file name> appended.
add_config_overlay() {
  [ -f "$2" ] || { echo "$1: error: --config-overlay $2: no such file" >&2; exit 2; }
  local name
  name="$(basename "$2")"
  overlays+=(--config-overlay "$(realpath "$2")")
  report_suffix+="-${name%.*}"
}
