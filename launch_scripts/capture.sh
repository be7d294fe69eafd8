#!/usr/bin/env bash
# lcm-logger capture of every channel into logs/<UTC time>-<name>/capture.lcmlog.
# Usage: capture.sh [NAME] [--lcm-url URL]   (Ctrl-C stops)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
name="capture"
url="$LCM_DEFAULT_URL"
while (($#)); do
  case "$1" in
    -h|--help) sed -n '2,3p' "$0"; exit 0 ;;
    --lcm-url) url="$2"; shift 2 ;;
    *) name="$1"; shift ;;
  esac
done
dir="$NADIR_ROOT/logs/$(nadir_utc_stamp)-$name"
mkdir -p "$dir"
echo "capture: $dir/capture.lcmlog on $url"
exec lcm-logger --quiet --lcm-url="$url" --flush-interval=200 "$dir/capture.lcmlog"
