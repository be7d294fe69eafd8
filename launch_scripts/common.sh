# Sourced by the launch scripts: paths, and the private network namespace.
NADIR_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
NADIR_BUILD="${NADIR_BUILD:-$NADIR_ROOT/build}"
NADIR_BIN="$NADIR_BUILD/bin"
export NADIR_ROOT
export PATH="$NADIR_BIN:$PATH"
# The live LCM URL: multicast with TTL 0 (stays on the host) and a 4 MB
# receive buffer for image bursts. Set LCM_DEFAULT_URL to override.
export LCM_DEFAULT_URL="${LCM_DEFAULT_URL:-udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304}"

# Runs a command inside a private network namespace whose loopback carries
# multicast: LCM udpm traffic never reaches a real network.
nadir_in_netns() {
  # Inside a user namespace (what the tests expect, e.g. the Slurm test's
  # setgroups=deny). NADIR_NETNS_KEEP_CAPS=1 as root: a plain network
  # namespace, so that CAP_SYS_NICE survives for run_set.sh --rt-priority.
  local flags=-rn
  [ "${NADIR_NETNS_KEEP_CAPS:-0}" = 1 ] && [ "$(id -u)" = 0 ] && flags=-n
  unshare "$flags" bash -c 'ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo && export NADIR_IN_NETNS=1 && exec "$@"' _ "$@"
}

nadir_utc_stamp() { date -u +%Y%m%dT%H%M%SZ; }

# nadir_config_with_attitude_policy POLICY OUT: writes OUT, a copy of
# config/default.yaml with vo_solver.sync.attitude_policy and
# yaw_fusion.attitude_policy set to POLICY (propagate | interpolate); point
# NADIR_CONFIG at it for a whole set.
nadir_config_with_attitude_policy() {
  local policy="$1" out="$2"
  sed -E "s/^( +attitude_policy:) [a-z]+/\1 $policy/" "$NADIR_ROOT/config/default.yaml" >"$out"
  [ "$(grep -cE "^ +attitude_policy: $policy( |$)" "$out")" = 2 ] ||
    { echo "error: could not set both attitude_policy keys to '$policy' in $out" >&2; return 1; }
}

# nadir_valid_rt_priority P: true when P is a SCHED_FIFO priority nadir uses
# (an integer in [1, 98]; 99 is left to the kernel's own threads).
nadir_valid_rt_priority() {
  [[ "$1" =~ ^[0-9]+$ ]] && (($1 >= 1 && $1 <= 98))
}
