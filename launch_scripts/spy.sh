#!/usr/bin/env bash
# lcm-spy with every nadir type decoded. Runs java directly: the packaged
# lcm-spy wrapper passes -Xincgc (fatal on Java 17) and a fixed classpath.
# Usage: spy.sh [--lcm-url URL]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
url="$LCM_DEFAULT_URL"
while (($#)); do
  case "$1" in
    -h|--help) sed -n '2,4p' "$0"; exit 0 ;;
    --lcm-url) url="$2"; shift 2 ;;
    *) echo "spy: error: unknown option $1" >&2; exit 2 ;;
  esac
done
jar="$NADIR_BUILD/lcmtypes/nadir_types.jar"
[ -r "$jar" ] || { echo "spy: error: $jar is missing; run launch_scripts/setup.sh" >&2; exit 2; }
export JAVA_TOOL_OPTIONS="${JAVA_TOOL_OPTIONS:-} -XX:+IgnoreUnrecognizedVMOptions"
exec java -Djava.net.preferIPv4Stack=true -Xmx256m \
  -cp "/usr/share/java/lcm.jar:/usr/share/java/jchart2d.jar:$jar" lcm.spy.Spy --lcm-url="$url"
