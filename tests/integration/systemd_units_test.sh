#!/usr/bin/env bash
# The vehicle's systemd units (launch_scripts/systemd_units.sh):
# - systemd-analyze verify accepts every unit and the target;
# - each service starts exactly the command run_set.sh starts for that
#   process (same program, same arguments), and the target wants them all;
# - every service runs as the unprivileged user with the hardening options,
#   and only the real-time ones keep a capability, CAP_SYS_NICE;
# - bad arguments are clear errors;
# - a process started as the real-time units start it (unprivileged user,
#   SCHED_FIFO, bounding and ambient set CAP_SYS_NICE only) runs with exactly
#   that: checked where the machine grants real-time priority, skipped with a
#   message where it refuses it (e.g. inside a user namespace).
set -uo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
source "$root/launch_scripts/common.sh"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
command -v systemd-analyze >/dev/null || fail "systemd-analyze is missing (Debian systemd; launch_scripts/setup.sh --tests)"

units="$work/units"
"$root/launch_scripts/systemd_units.sh" vehicle "$units" --rt-priority 20 || fail "systemd_units.sh vehicle failed"
ls "$units"
systemd-analyze verify --man=no "$units"/*.service "$units"/*.target || fail "systemd-analyze verify"

# The same processes with the same arguments as run_set.sh.
NADIR_STATE_DIR=/run/nadir "$root/launch_scripts/run_set.sh" vehicle --print-commands >"$work/set.txt" ||
  fail "run_set.sh --print-commands"
cat "$work/set.txt"
wanted="$(sed -n 's/^Wants=//p' "$units/nadir-vehicle.target")"
n_run=0
while read -r kind name program args; do
  [ "$kind" = run ] || continue
  n_run=$((n_run + 1))
  unit="$units/nadir-vehicle-$name.service"
  [ -f "$unit" ] || fail "no unit for $name"
  [[ " $wanted " == *" nadir-vehicle-$name.service "* ]] || fail "the target does not want $name"
  exec_line="$(sed -n 's/^ExecStart=//p' "$unit")"
  expected="$(command -v "$program")${args:+ $args}"
  [ "$exec_line" = "$expected" ] || fail "$name: ExecStart '$exec_line', run_set.sh starts '$expected'"
  for option in "User=nadir" "Restart=on-failure" "NoNewPrivileges=yes" "ProtectSystem=strict" \
                "CapabilityBoundingSet=CAP_SYS_NICE" "AmbientCapabilities=CAP_SYS_NICE" \
                "CPUSchedulingPolicy=fifo" "CPUSchedulingPriority=20" "PrivateTmp=yes"; do
    grep -qxF "$option" "$unit" || fail "$name: no $option"
  done
done <"$work/set.txt"
((n_run == 5)) || fail "expected the vehicle set's 5 processes, got $n_run"
grep -q "^ExecStart=.*lcm-logger .*-i /var/log/nadir/vehicle.lcmlog" "$units/nadir-vehicle-capture.service" ||
  fail "the capture unit does not run lcm-logger into /var/log/nadir"
grep -qE "^ExecStart=.*ip route replace 239.255.76.67/32 dev lo$" "$units/nadir-vehicle-bus.service" ||
  fail "the bus unit does not route the LCM group through lo"
[[ " $wanted " == *" nadir-vehicle-bus.service "* ]] || fail "the target does not want the bus route"
grep -qxF "SupplementaryGroups=dialout" "$units/nadir-vehicle-ins_bridge.service" || fail "ins_bridge: not in dialout"
! grep -q "^SupplementaryGroups" "$units/nadir-vehicle-tracker.service" || fail "tracker: has extra groups"

# The vehicle set asks for real-time priority 20 itself (its `realtime` line).
"$root/launch_scripts/systemd_units.sh" vehicle "$work/asked" >/dev/null || fail "systemd_units.sh without --rt-priority"
grep -qxF "CPUSchedulingPriority=20" "$work/asked/nadir-vehicle-tracker.service" ||
  fail "the vehicle set's realtime 20 did not reach the units"
grep -qxF "CapabilityBoundingSet=CAP_SYS_NICE" "$work/asked/nadir-vehicle-tracker.service" ||
  fail "a real-time unit must keep CAP_SYS_NICE only"

# Without real-time priority no capability at all, and no real-time scheduling.
"$root/launch_scripts/systemd_units.sh" vehicle "$work/plain" --rt-priority off >/dev/null ||
  fail "systemd_units.sh --rt-priority off"
grep -qxF "CapabilityBoundingSet=" "$work/plain/nadir-vehicle-tracker.service" || fail "plain unit keeps capabilities"
grep -qxF "RestrictRealtime=yes" "$work/plain/nadir-vehicle-tracker.service" || fail "plain unit may take real-time"
systemd-analyze verify --man=no "$work/plain"/*.service || fail "systemd-analyze verify (plain)"

# Bad arguments.
out="$("$root/launch_scripts/systemd_units.sh" vehicle "$work/bad" --user root 2>&1)" && fail "--user root accepted"
echo "$out" | grep -q "run unprivileged" || fail "--user root: unclear message: $out"
out="$("$root/launch_scripts/systemd_units.sh" vehicle "$work/bad" --rt-priority 99 2>&1)" && fail "--rt-priority 99 accepted"
echo "$out" | grep -q "\[1, 98\]" || fail "--rt-priority 99: unclear message: $out"
out="$("$root/launch_scripts/systemd_units.sh" sim "$work/bad" 2>&1)" && fail "a set with a finite process accepted"
echo "$out" | grep -q "finite" || fail "finite process: unclear message: $out"

# A process as the real-time units run it: CAP_SYS_NICE and nothing else.
if [ "$(id -u)" = 0 ] && chrt -f 20 true 2>/dev/null && command -v setpriv >/dev/null; then
  setpriv --reuid=65534 --regid=65534 --clear-groups --bounding-set=-all,+sys_nice --inh-caps=-all,+sys_nice \
    --ambient-caps=-all,+sys_nice chrt -f 20 "$(command -v nadir_tracker)" --lcm-url memq:// >"$work/tracker.txt" 2>&1 &
  pid=$!
  sleep 1
  kill -0 "$pid" 2>/dev/null || { cat "$work/tracker.txt"; fail "the tracker did not start as the unit starts it"; }
  status="$(cat /proc/$pid/status)"
  policy="$(chrt -p "$pid")"
  kill -TERM "$pid"; wait "$pid"
  echo "$status" | grep -E "^(Uid|Cap(Eff|Prm|Bnd|Amb)):"
  echo "$policy"
  sys_nice=0000000000800000  # 1 << CAP_SYS_NICE (23)
  for set in CapEff CapPrm CapBnd CapAmb; do
    echo "$status" | grep -qE "^$set:[[:space:]]+$sys_nice$" || fail "$set is not CAP_SYS_NICE alone"
  done
  echo "$status" | grep -qE "^Uid:[[:space:]]+65534" || fail "not running as the unprivileged user"
  echo "$policy" | grep -q "SCHED_FIFO" || fail "not SCHED_FIFO: $policy"
  echo "real-time process: SCHED_FIFO 20 as uid 65534 with CAP_SYS_NICE only"
else
  echo "SKIPPED the real-time part: this machine refuses SCHED_FIFO here ($(chrt -f 20 true 2>&1 || true))"
fi
echo "PASS"
