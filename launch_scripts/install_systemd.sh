#!/usr/bin/env bash
# Installs a process set as systemd services on the aircraft's computer, so
# that it starts at boot, restarts a process that fails and captures every
# channel: creates the unprivileged system user, writes the units
# (launch_scripts/systemd_units.sh) into /etc/systemd/system, an environment
# file /etc/nadir/environment (kept if present) and enables the set's target.
#
# Usage: install_systemd.sh [SET] [--user USER] [--rt-priority P] [--dry-run]
#   SET            default: vehicle
#   --user         default: nadir (created as a system user in group dialout
#                  for the serial devices)
#   --rt-priority  SCHED_FIFO priority for the set (1-98, or off; default: the
#                  set's own `realtime` line, 20 for vehicle and hil)
#   --dry-run      write the units into logs/systemd-SET/ and verify them;
#                  change nothing on the system
# Needs root (except --dry-run). Start now: systemctl start nadir-SET.target;
# watch: journalctl -u 'nadir-SET-*' -f.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

usage() { sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; }
die() { echo "install_systemd: error: $*" >&2; exit 2; }
set_name=vehicle user=nadir rt_priority= dry_run=0
while (($#)); do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --user) user="$2"; shift 2 ;;
    --rt-priority) rt_priority="$2"; shift 2 ;;
    --dry-run) dry_run=1; shift ;;
    -*) die "unknown option $1" ;;
    *) set_name="$1"; shift ;;
  esac
done
rt_args=()
[ -z "$rt_priority" ] || rt_args=(--rt-priority "$rt_priority")

if ((dry_run)); then
  out="$NADIR_ROOT/logs/systemd-$set_name"
  rm -rf "$out"
  "$NADIR_ROOT/launch_scripts/systemd_units.sh" "$set_name" "$out" --user "$user" "${rt_args[@]}"
  systemd-analyze verify --man=no "$out"/*.service "$out"/*.target
  echo "install_systemd: dry run: units in $out verified; nothing installed"
  exit 0
fi

[ "$(id -u)" = 0 ] || die "needs root (or --dry-run)"
if ! id "$user" >/dev/null 2>&1; then
  useradd --system --no-create-home --home-dir /nonexistent --shell /usr/sbin/nologin --groups dialout "$user"
  echo "install_systemd: created system user $user (group dialout)"
fi
mkdir -p /etc/nadir
if [ ! -f /etc/nadir/environment ]; then
  cat >/etc/nadir/environment <<EOF
# Environment of every nadir service (systemd EnvironmentFile).
# NADIR_ROOT=$NADIR_ROOT
# LCM_DEFAULT_URL=udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304
EOF
fi
"$NADIR_ROOT/launch_scripts/systemd_units.sh" "$set_name" /etc/systemd/system --user "$user" "${rt_args[@]}"
systemd-analyze verify --man=no /etc/systemd/system/nadir-"$set_name"*.service /etc/systemd/system/nadir-"$set_name".target
if [ -d /run/systemd/system ]; then
  systemctl daemon-reload
  systemctl enable "nadir-$set_name.target"
  echo "install_systemd: enabled nadir-$set_name.target (starts at boot; now: systemctl start nadir-$set_name.target)"
else
  echo "install_systemd: systemd is not running here: units written, enable with systemctl enable nadir-$set_name.target"
fi
