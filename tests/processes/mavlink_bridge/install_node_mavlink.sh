#!/usr/bin/env bash
# Installs node-mavlink (the independent MAVLink implementation the bridge's
# codec is tested against) from the npm registry into BUILD_DIR/node_mavlink,
# once. Usage: install_node_mavlink.sh BUILD_DIR
set -euo pipefail
[ "${1:-}" = "-h" ] || [ "${1:-}" = "--help" ] && { sed -n '2,4p' "$0" | sed 's/^# \{0,1\}//'; exit 0; }
dir="${1:?usage: install_node_mavlink.sh BUILD_DIR}/node_mavlink"
version=2.3.0
command -v node >/dev/null && command -v npm >/dev/null ||
  { echo "install_node_mavlink: error: node and npm are needed (launch_scripts/setup.sh installs them)" >&2; exit 1; }
if [ -f "$dir/node_modules/node-mavlink/package.json" ] &&
   grep -q "\"version\": \"$version\"" "$dir/node_modules/node-mavlink/package.json"; then
  exit 0
fi
mkdir -p "$dir"
[ -f "$dir/package.json" ] || echo '{"name": "nadir-node-mavlink", "private": true}' >"$dir/package.json"
npm install --prefix "$dir" --no-audit --no-fund --loglevel=error "node-mavlink@$version" || {
  echo "install_node_mavlink: error: npm install node-mavlink@$version into $dir failed (registry reachable?)" >&2
  exit 1
}
