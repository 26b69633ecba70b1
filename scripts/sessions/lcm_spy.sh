#!/usr/bin/env bash
# The real lcm-spy (Java, needs a display) with igms's types on the classpath,
# so it decodes every igms message. Runs inside the private network namespace.
#   scripts/sessions/lcm_spy.sh [--lcm-url URL]
# Debian's /usr/bin/lcm-spy passes -Xincgc, which Java 17 refuses: call java directly.
set -euo pipefail
cd "$(dirname "$0")/../.."
jar=build/lcmtypes/igms_lcmtypes.jar
if [[ ! -f $jar ]]; then
  echo "lcm_spy.sh: $jar is missing: build with a JDK and liblcm-java installed (scripts/setup/setup.sh does both)" >&2
  exit 2
fi
if [[ -z "${DISPLAY:-}" ]]; then
  echo "lcm_spy.sh: lcm-spy is a window and there is no DISPLAY; use build/tools/igms-spy in a terminal" >&2
  exit 2
fi
url="udpm://239.255.76.67:7667?ttl=0"
if [[ "${1:-}" == "--lcm-url" ]]; then url=$2; fi
if [[ "${IGMS_IN_NETNS:-}" != "1" ]]; then exec scripts/netns_run.sh "$0" "$@"; fi
cp="/usr/share/java/lcm.jar:$jar"
[[ -f /usr/share/java/jchart2d.jar ]] && cp="$cp:/usr/share/java/jchart2d.jar"
exec java -Djava.net.preferIPv4Stack=true -cp "$cp" lcm.spy.Spy --lcm-url="$url"
