#!/usr/bin/env bash
# Installs the independent Foxglove clients the bridge and the MCAP writer are
# tested against, from the npm registry into BUILD_DIR/node_foxglove, once:
# @foxglove/ws-protocol (a WebSocket client), @mcap/core (an MCAP reader) and
# ws (for the tests' raw "bad client"), ajv (validates the JSON schemas and the
# messages against them) and @foxglove/schemas (the well-known schemas).
# Usage: install_node_foxglove.sh BUILD_DIR
set -euo pipefail
[ "${1:-}" = "-h" ] || [ "${1:-}" = "--help" ] && { sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'; exit 0; }
dir="${1:?usage: install_node_foxglove.sh BUILD_DIR}/node_foxglove"
packages=("@foxglove/ws-protocol@0.8" "@mcap/core@2" "ws@8" "ajv@8" "@foxglove/schemas@2.1")
command -v node >/dev/null && command -v npm >/dev/null ||
  { echo "install_node_foxglove: error: node and npm are needed (launch_scripts/setup.sh installs them)" >&2; exit 1; }
if [ -f "$dir/node_modules/@foxglove/ws-protocol/package.json" ] &&
   [ -f "$dir/node_modules/@mcap/core/package.json" ] && [ -f "$dir/node_modules/ws/package.json" ] && [ -f "$dir/node_modules/ajv/package.json" ] &&
   [ -f "$dir/node_modules/@foxglove/schemas/package.json" ]; then
  exit 0
fi
mkdir -p "$dir"
[ -f "$dir/package.json" ] || echo '{"name": "nadir-node-foxglove", "private": true}' >"$dir/package.json"
npm install --prefix "$dir" --no-audit --no-fund --loglevel=error "${packages[@]}" || {
  echo "install_node_foxglove: error: npm install ${packages[*]} into $dir failed (registry reachable?)" >&2
  exit 1
}
