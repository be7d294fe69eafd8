#!/usr/bin/env bash
# Writes systemd units that start a process set on the aircraft as run_set.sh
# starts it: one service per `run` process of the set (the same command and
# arguments, from `run_set.sh SET --print-commands`), one for the capture
# (lcm-logger), and a target that pulls them all in.
#
# Usage: systemd_units.sh SET OUT_DIR [--bin-dir DIR] [--user USER] [--rt-priority P]
#                         [--lcm-url URL] [--bus-interface IFACE] [--state-dir DIR] [--log-dir DIR]
#   SET            a set of launch_scripts/sets/ (e.g. vehicle) or a set file
#   OUT_DIR        where the units go (install_systemd.sh: /etc/systemd/system)
#   --bin-dir      where the nadir_* programs are (default: this checkout's build/bin)
#   --user         the unprivileged user every unit runs as (default: nadir)
#   --rt-priority  SCHED_FIFO priority for the processes and the logger (1-98,
#                  or off; default: the set's `realtime P` line, e.g. 20 for
#                  vehicle and hil). systemd sets it; the process keeps
#                  CAP_SYS_NICE and no other capability.
#   --lcm-url      the vehicle bus (default: multicast on this host only, TTL 0)
#   --bus-interface the interface the bus's multicast group is routed through
#                  (default lo: one computer; the group is neither joined nor
#                  sent on the vehicle network). A oneshot unit
#                  nadir-SET-bus.service sets the route before the set starts.
#   --state-dir    NADIR_STATE_DIR: state a restarted process continues from
#                  (default /run/nadir: kept across restarts, new at each boot)
#   --log-dir      where the capture goes (default /var/log/nadir)
# Units: nadir-SET-NAME.service, nadir-SET-capture.service, nadir-SET-bus.service,
# nadir-SET.target.
# Every service: Restart=on-failure, the user's own groups only (plus dialout
# for the serial bridges), no new privileges, the system and home folders
# read-only (the checkout and its config are read where they are), its own
# /tmp, only IPv4/Unix/netlink sockets, writes only to its state or log folder.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

usage() { sed -n '2,30p' "$0" | sed 's/^# \{0,1\}//'; }
die() { echo "systemd_units: error: $*" >&2; exit 2; }
set_arg="" out_dir="" bin_dir="$NADIR_BIN" user=nadir rt_priority="" lcm_url="$LCM_DEFAULT_URL"
state_dir=/run/nadir log_dir=/var/log/nadir bus_interface=lo
while (($#)); do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --bin-dir) bin_dir="$2"; shift 2 ;;
    --user) user="$2"; shift 2 ;;
    --rt-priority) rt_priority="$2"; shift 2 ;;
    --lcm-url) lcm_url="$2"; shift 2 ;;
    --bus-interface) bus_interface="$2"; shift 2 ;;
    --state-dir) state_dir="$2"; shift 2 ;;
    --log-dir) log_dir="$2"; shift 2 ;;
    -*) die "unknown option $1" ;;
    *) if [ -z "$set_arg" ]; then set_arg="$1"; elif [ -z "$out_dir" ]; then out_dir="$1"; else die "unexpected $1"; fi
       shift ;;
  esac
done
[ -n "$set_arg" ] && [ -n "$out_dir" ] || { usage >&2; exit 2; }
[[ "$user" =~ ^[a-z_][a-z0-9_-]*$ ]] || die "--user '$user' is not a user name"
[ "$user" != root ] || die "--user root: the units run unprivileged"
if [ -n "$rt_priority" ] && [ "$rt_priority" != off ]; then
  nadir_valid_rt_priority "$rt_priority" || die "--rt-priority must be an integer in [1, 98] or off, got '$rt_priority'"
fi
[[ "$bin_dir" = /* ]] || die "--bin-dir '$bin_dir' must be an absolute path"
[[ "$state_dir" =~ ^/run/[A-Za-z0-9._-]+$ ]] || die "--state-dir '$state_dir' must be a folder directly under /run"
[[ "$log_dir" =~ ^/var/log/[A-Za-z0-9._-]+$ ]] || die "--log-dir '$log_dir' must be a folder directly under /var/log"
[ -d "$bin_dir" ] || die "--bin-dir $bin_dir does not exist (build first: launch_scripts/setup.sh)"
logger="$(command -v lcm-logger)" || die "lcm-logger is not installed (Debian liblcm-bin)"
ip_tool="$(command -v ip)" || die "ip is not installed (Debian iproute2)"
[[ "$bus_interface" =~ ^[A-Za-z0-9._-]+$ ]] || die "--bus-interface '$bus_interface' is not an interface name"
[[ "$lcm_url" =~ ^udpm://([0-9.]+):([0-9]+) ]] || die "--lcm-url '$lcm_url' must be udpm://GROUP:PORT[?OPTIONS]"
bus_group="${BASH_REMATCH[1]}"

commands="$(PATH="$bin_dir:$PATH" NADIR_STATE_DIR="$state_dir" "$NADIR_ROOT/launch_scripts/run_set.sh" "$set_arg" \
  ${rt_priority:+--rt-priority "$rt_priority"} --print-commands)"
# The priority the set asks for (its `realtime` line, first), unless given here.
rt_priority=""
if [[ "$commands" =~ (^|$'\n')realtime\ ([0-9]+) ]]; then rt_priority="${BASH_REMATCH[2]}"; fi
set_name="$(basename "$set_arg")"
target="nadir-$set_name.target"
mkdir -p "$out_dir"

# [Service] lines every unit shares. `extra` adds the unit's own.
common_service() {
  local groups="$1"
  cat <<EOF
User=$user
Group=$user
${groups:+SupplementaryGroups=$groups
}Environment=LCM_DEFAULT_URL=$lcm_url
Environment=NADIR_STATE_DIR=$state_dir
EnvironmentFile=-/etc/nadir/environment
RuntimeDirectory=${state_dir#/run/}
RuntimeDirectoryPreserve=yes
Restart=on-failure
RestartSec=1
NoNewPrivileges=yes
ProtectSystem=strict
ProtectHome=read-only
PrivateTmp=yes
ProtectKernelTunables=yes
ProtectKernelModules=yes
ProtectKernelLogs=yes
ProtectControlGroups=yes
ProtectClock=yes
ProtectHostname=yes
RestrictNamespaces=yes
RestrictSUIDSGID=yes
LockPersonality=yes
RestrictAddressFamilies=AF_INET AF_UNIX AF_NETLINK
EOF
  if [ -n "$rt_priority" ]; then
    cat <<EOF
CPUSchedulingPolicy=fifo
CPUSchedulingPriority=$rt_priority
CapabilityBoundingSet=CAP_SYS_NICE
AmbientCapabilities=CAP_SYS_NICE
EOF
  else
    cat <<EOF
CapabilityBoundingSet=
RestrictRealtime=yes
EOF
  fi
}

# A unit's ExecStart: the set's command with the program's full path.
exec_start() {
  local program="$1"; shift
  local path
  path="$(PATH="$bin_dir:$PATH" command -v "$program")" || die "$program is not in $bin_dir nor on PATH"
  echo "ExecStart=$path${*:+ $*}"
}

units=()
while read -r kind name rest; do
  case "$kind" in
    realtime) ;;  # read above
    capture)
      unit="nadir-$set_name-capture.service"
      {
        echo "# Generated by launch_scripts/systemd_units.sh $set_name: lcm-logger capture."
        echo "[Unit]"
        echo "Description=nadir $set_name: lcm-logger capture of every channel"
        echo "PartOf=$target"
        echo "After=nadir-$set_name-bus.service"
        echo "Requires=nadir-$set_name-bus.service"
        echo "[Service]"
        echo "Type=simple"
        echo "LogsDirectory=${log_dir#/var/log/}"
        echo "WorkingDirectory=$log_dir"
        # -i: a new numbered file at each start, never over an old capture.
        echo "ExecStart=$logger --quiet --flush-interval=200 -i $log_dir/$name.lcmlog"
        common_service ""
        echo "ReadWritePaths=$log_dir"
      } >"$out_dir/$unit"
      units+=("$unit") ;;
    run)
      read -r program args <<<"$rest"
      unit="nadir-$set_name-$name.service"
      groups=""
      [[ "$program" =~ (ins_bridge|mavlink_bridge)$ ]] && groups=dialout  # serial devices
      {
        echo "# Generated by launch_scripts/systemd_units.sh $set_name: as run_set.sh starts '$name'."
        echo "[Unit]"
        echo "Description=nadir $set_name: $name"
        echo "PartOf=$target"
        echo "After=nadir-$set_name-capture.service nadir-$set_name-bus.service"
        echo "Requires=nadir-$set_name-bus.service"
        echo "[Service]"
        echo "Type=simple"
        exec_start "$program" $args
        common_service "$groups"
        echo "ReadWritePaths=$state_dir"
      } >"$out_dir/$unit"
      units+=("$unit") ;;
    finite)
      die "set '$set_name': '$name' runs to completion (finite); a vehicle service runs until stopped" ;;
    *) die "unexpected line from run_set.sh --print-commands: $kind $name" ;;
  esac
done <<<"$commands"

# The bus's multicast route decides on which interface the processes join the
# group and send (LCM 1.3 has no interface setting of its own).
unit="nadir-$set_name-bus.service"
{
  echo "# Generated by launch_scripts/systemd_units.sh $set_name: the vehicle bus's route."
  echo "[Unit]"
  echo "Description=nadir $set_name: route the LCM bus $bus_group through $bus_interface"
  echo "PartOf=$target"
  echo "After=network.target"
  echo "[Service]"
  echo "Type=oneshot"
  echo "RemainAfterExit=yes"
  echo "ExecStart=$ip_tool link set $bus_interface multicast on"
  echo "ExecStart=$ip_tool route replace $bus_group/32 dev $bus_interface"
  echo "CapabilityBoundingSet=CAP_NET_ADMIN"
  echo "NoNewPrivileges=yes"
  echo "ProtectSystem=strict"
  echo "ProtectHome=yes"
  echo "PrivateTmp=yes"
} >"$out_dir/$unit"
units+=("$unit")

{
  echo "# Generated by launch_scripts/systemd_units.sh $set_name."
  echo "[Unit]"
  echo "Description=nadir process set '$set_name'"
  echo "Wants=${units[*]}"
  echo "After=network-online.target"
  echo "[Install]"
  echo "WantedBy=multi-user.target"
} >"$out_dir/$target"
echo "systemd_units: wrote $target and ${#units[@]} service(s) into $out_dir"
