#!/usr/bin/env bash
# Starts a named set of processes (launch_scripts/sets/NAME, or a path to a
# set file), prefixes each one's output with its name, restarts a process that
# dies (backoff 1, 2, 4 ... s; gives up after --max-restarts, loudly), and
# stops them all cleanly on Ctrl-C / SIGTERM, in reverse order of start, one
# after the other (SIGKILL after 5 s). Optional lcm-logger capture.
#
# Usage: run_set.sh SET [--no-capture] [--duration S] [--max-restarts N] [--lcm-url URL]
#                    [--rt-priority P|off] [--print-commands]
# --print-commands prints each process of the set as `KIND NAME COMMAND...`
# (variables expanded, nothing started; `capture NAME` for the logger,
# `realtime P` for the priority) and exits: what
# launch_scripts/systemd_units.sh turns into systemd units.
# --rt-priority P runs every `run` process (the vehicle's long-running nodes, not
# the finite source) and the capture logger (the stand-in for the POSE
# consumer, and the latency instrument: it must not be starved by the nodes)
# under SCHED_FIFO priority P (1-98; needs root or CAP_SYS_NICE), as an
# aircraft's computer would run its navigation. It is also exported as
# NADIR_RT_PRIORITY, for a set line to pass on (the simulator's publisher:
# nadir_sim --publish-rt-priority, the stand-in for the vehicle's drivers).
# A set with a `realtime P` line gets P where the machine grants SCHED_FIFO
# and runs with ordinary scheduling, with a note, where it does not;
# --rt-priority P insists (an error where refused), --rt-priority off declines.
#
# Set file lines (# starts a comment; ${VAR:-default} is expanded when started):
#   require  BINARY  what it is     the set fails at once if BINARY is not built
#   capture  NAME                   lcm-logger into logs/<UTC>-NAME/capture.lcmlog
#   realtime P                      ask for SCHED_FIFO priority P (1-98) where granted
#   run      NAME  [delay=S] COMMAND...  long-running process, restarted if it dies
#   background NAME [delay=S] COMMAND... the same, off the real-time path: never
#                                   SCHED_FIFO, at nice 10 (the map matcher)
#   finite   NAME  [delay=S] COMMAND...  runs to completion; when it ends the set stops
# delay=S starts that process S seconds after the set (e.g. a source after
# its subscribers are up). NADIR_CAPTURE_DIR overrides the capture folder.
# NADIR_STATE_DIR (exported to every command): a folder new with each start
# of the set for state a restarted process continues from (yaw fusion's
# checkpoint): the capture folder, or logs/state/<UTC>-SET without capture.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

usage() { sed -n '2,37p' "$0" | sed 's/^# \{0,1\}//'; }
set_arg=""
capture_enabled=1
duration=""
max_restarts=5
grace_s=2
rt_priority=
print_commands=0
while (($#)); do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --no-capture) capture_enabled=0; shift ;;
    --duration) duration="$2"; shift 2 ;;
    --max-restarts) max_restarts="$2"; shift 2 ;;
    --lcm-url) export LCM_DEFAULT_URL="$2"; shift 2 ;;
    --rt-priority) rt_priority="$2"; shift 2 ;;
    --print-commands) print_commands=1; shift ;;
    -*) echo "run_set: error: unknown option $1" >&2; exit 2 ;;
    *) set_arg="$1"; shift ;;
  esac
done
[ -n "$set_arg" ] || { usage >&2; exit 2; }
set_file="$set_arg"
[ -f "$set_file" ] || set_file="$NADIR_ROOT/launch_scripts/sets/$set_arg"
[ -f "$set_file" ] || { echo "run_set: error: no set '$set_arg' (looked in launch_scripts/sets/)" >&2; exit 2; }
set_name="$(basename "$set_file")"

declare -a names=()
declare -A cmd=() kind=() pid=() restarts=() restart_at=() gave_up=() delay_s=() background=()
capture_name=""
set_rt_priority=""
line_no=0
while IFS= read -r raw || [ -n "$raw" ]; do
  line_no=$((line_no + 1))
  line="${raw%%#*}"
  [[ "$line" =~ ^[[:space:]]*$ ]] && continue
  read -r word name rest <<<"$line"
  case "$word" in
    require)
      if ! command -v "$name" >/dev/null 2>&1; then
        echo "run_set: error: set '$set_name' needs $name (${rest:-no description}), which is not built or installed." >&2
        exit 3
      fi ;;
    capture) capture_name="$(bash -c "echo $name")" ;;   # expands ${VAR:-default}
    run|finite|background)
      [ -n "$rest" ] || { echo "run_set: error: $set_file:$line_no: '$word $name' has no command" >&2; exit 2; }
      names+=("$name"); kind[$name]="$word"; restarts[$name]=0; gave_up[$name]=0
      # background: a `run` process off the real-time path (never SCHED_FIFO, nice 10).
      if [ "$word" = background ]; then kind[$name]=run; background[$name]=1; fi
      if [[ "$rest" =~ ^delay=([0-9.]+)[[:space:]]+(.*)$ ]]; then
        delay_s[$name]="${BASH_REMATCH[1]}"; rest="${BASH_REMATCH[2]}"
      fi
      cmd[$name]="$rest" ;;
    realtime)
      nadir_valid_rt_priority "$name" ||
        { echo "run_set: error: $set_file:$line_no: 'realtime $name': a priority in [1, 98]" >&2; exit 2; }
      set_rt_priority="$name" ;;
    *) echo "run_set: error: $set_file:$line_no: unknown word '$word' (require, capture, realtime, run, background, finite)" >&2; exit 2 ;;
  esac
done <"$set_file"
((${#names[@]})) || { echo "run_set: error: $set_file starts no process" >&2; exit 2; }

# Real-time priority: --rt-priority P insists (an error where SCHED_FIFO is
# refused), --rt-priority off declines, and otherwise the set's `realtime P`
# is taken where the machine grants it, with a note where it does not.
unset NADIR_RT_PRIORITY   # set below only
if [ "$rt_priority" = off ]; then
  rt_priority=""
elif [ -n "$rt_priority" ]; then
  nadir_valid_rt_priority "$rt_priority" ||
    { echo "run_set: error: --rt-priority must be an integer in [1, 98] or off, got '$rt_priority'" >&2; exit 2; }
  if ((!print_commands)) && ! chrt -f "$rt_priority" true 2>/dev/null; then
    echo "run_set: error: --rt-priority $rt_priority: SCHED_FIFO not permitted here (needs root or CAP_SYS_NICE; in nadir_in_netns export NADIR_NETNS_KEEP_CAPS=1)" >&2
    exit 2
  fi
elif [ -n "$set_rt_priority" ]; then
  if ((print_commands)) || chrt -f "$set_rt_priority" true 2>/dev/null; then
    rt_priority="$set_rt_priority"
    ((print_commands)) || echo "[run_set] set '$set_name' runs its processes at real-time priority $rt_priority (SCHED_FIFO)"
  else
    echo "[run_set] note: set '$set_name' asks for real-time priority $set_rt_priority (SCHED_FIFO), which this machine refuses (needs root or CAP_SYS_NICE): running with ordinary scheduling, higher latency (--rt-priority off silences this)"
  fi
fi
[ -n "$rt_priority" ] && export NADIR_RT_PRIORITY="$rt_priority"

if ((print_commands)); then
  [ -n "$rt_priority" ] && echo "realtime $rt_priority"
  [ -n "$capture_name" ] && echo "capture $capture_name"
  for n in "${names[@]}"; do
    expanded="$(bash -c "echo ${cmd[$n]}")" ||
      { echo "run_set: error: set '$set_name': cannot expand the command of $n" >&2; exit 2; }
    echo "${kind[$n]} $n $expanded"
  done
  exit 0
fi

logger_pid=""
capture_dir=""
if ((capture_enabled)) && [ -n "$capture_name" ]; then
  capture_dir="${NADIR_CAPTURE_DIR:-$NADIR_ROOT/logs/$(nadir_utc_stamp)-$capture_name}"
  mkdir -p "$capture_dir"
  url="$LCM_DEFAULT_URL"
  ${rt_priority:+chrt -f "$rt_priority"} lcm-logger --quiet --lcm-url="$url" --flush-interval=200 "$capture_dir/capture.lcmlog" \
    > >(sed -u "s/^/[lcm-logger] /") 2>&1 &
  logger_pid=$!
  echo "[run_set] capturing into $capture_dir/capture.lcmlog"
  sleep 0.3
fi

# State of this run of the set only: a restarted process continues from it,
# a new run of the set never does.
if [ -n "$capture_dir" ]; then
  export NADIR_STATE_DIR="$capture_dir"
else
  export NADIR_STATE_DIR="$NADIR_ROOT/logs/state/$(nadir_utc_stamp)-$set_name-$$"
fi
mkdir -p "$NADIR_STATE_DIR"

start() {
  local n="$1" pre="" rt=""
  [ -n "${delay_s[$n]:-}" ] && [ "${restarts[$n]}" -eq 0 ] && pre="sleep ${delay_s[$n]}; "
  [ -n "$rt_priority" ] && [ "${kind[$n]}" = run ] && rt="chrt -f $rt_priority "
  [ -n "${background[$n]:-}" ] && rt="nice -n 10 "
  bash -c "${pre}exec ${rt}${cmd[$n]}" > >(sed -u "s/^/[$n] /") 2>&1 &
  pid[$n]=$!
  echo "[run_set] started $n (pid ${pid[$n]}): ${cmd[$n]}"
}

stopping=0
stop_all() {
  stopping=1
  echo "[run_set] stopping set '$set_name'"
  # In reverse order of start, each stopped before the next is asked: a
  # driver lets go of its device (the camera capture of the fake camera)
  # while the device still answers.
  local n p i k
  for ((i = ${#names[@]} - 1; i >= 0; i--)); do
    n="${names[$i]}"; p="${pid[$n]:-}"
    [ -n "$p" ] || continue
    kill -TERM "$p" 2>/dev/null
    for ((k = 0; k < 50; k++)); do
      kill -0 "$p" 2>/dev/null || break
      sleep 0.1
    done
    if kill -0 "$p" 2>/dev/null; then
      echo "[run_set] $n did not stop within 5 s; killing it"
      kill -KILL "$p" 2>/dev/null
    fi
    wait "$p" 2>/dev/null
  done
  if [ -n "$logger_pid" ]; then
    sleep 0.5   # let the logger drain what the processes sent last
    kill -INT "$logger_pid" 2>/dev/null; wait "$logger_pid" 2>/dev/null
    echo "[run_set] capture: $capture_dir/capture.lcmlog"
  fi
  echo "[run_set] set '$set_name' stopped"
}
trap 'stop_all; exit 0' INT TERM

for n in "${names[@]}"; do start "$n"; done
start_s=$SECONDS
status=0
while :; do
  sleep 0.2
  if [ -n "$duration" ] && ((SECONDS - start_s >= duration)); then
    echo "[run_set] --duration $duration s reached"
    break
  fi
  finished=""
  for n in "${names[@]}"; do
    p="${pid[$n]:-}"
    if [ -n "$p" ] && ! kill -0 "$p" 2>/dev/null; then
      wait "$p"; code=$?
      pid[$n]=""
      if [ "${kind[$n]}" = finite ]; then
        echo "[run_set] $n finished (exit $code)"
        finished="$n"; status=$code
        continue
      fi
      r=$((restarts[$n] + 1)); restarts[$n]=$r
      if ((r > max_restarts)); then
        echo "[run_set] !!!!!!!! GIVING UP on $n: it died $r times (last exit $code); the rest of the set keeps running !!!!!!!!" >&2
        gave_up[$n]=1; status=1
        continue
      fi
      delay=$((1 << (r - 1))); ((delay > 30)) && delay=30
      echo "[run_set] $n died (exit $code); restart $r/$max_restarts in $delay s" >&2
      restart_at[$n]=$((SECONDS + delay))
    elif [ -z "$p" ] && [ "${kind[$n]}" = run ] && ((gave_up[$n] == 0)) && [ -n "${restart_at[$n]:-}" ] &&
         ((SECONDS >= restart_at[$n])); then
      restart_at[$n]=""
      start "$n"
    fi
  done
  if [ -n "$finished" ]; then
    sleep "$grace_s"   # let the pipeline finish the last messages
    break
  fi
done
stop_all
exit "$status"
