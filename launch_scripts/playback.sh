#!/usr/bin/env bash
# Plays a log into live LCM for watching in lcm-spy (open loop, may drop:
# never the regression path; use nadir_replay for that).
# Usage: playback.sh FILE [--speed X] [--lcm-url URL]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
file=""
speed=1.0
url="$LCM_DEFAULT_URL"
while (($#)); do
  case "$1" in
    -h|--help) sed -n '2,4p' "$0"; exit 0 ;;
    --speed) speed="$2"; shift 2 ;;
    --lcm-url) url="$2"; shift 2 ;;
    *) file="$1"; shift ;;
  esac
done
[ -n "$file" ] || { echo "playback: error: name a log file" >&2; exit 2; }
[ -r "$file" ] || { echo "playback: error: cannot read $file" >&2; exit 2; }
exec lcm-logplayer --speed="$speed" --lcm-url="$url" "$file"
