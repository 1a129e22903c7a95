#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# cdpr-lcm-spy: LCM's lcm-spy with cdpr's message types on its class path (docs/realtime.md,
# "lcm-spy"). Debian bookworm's /usr/bin/lcm-spy cannot load them: it passes -Xincgc, which
# Java 17 refuses, and sets its own class path.
#
#   cdpr-lcm-spy [LCM-SPY OPTIONS]   lcm-spy itself (a window: needs a display), e.g.
#                                    cdpr-lcm-spy --lcm-url='udpm://239.255.76.67:7667?ttl=0'
#   cdpr-lcm-spy --check             no window: lcm-spy's own type lookup on this class path,
#                                    one line per cdpr type with its fingerprint
#   cdpr-lcm-spy --classpath         print the class path and exit
#
# The types jar (cdpr_lcmtypes.jar, built when javac and liblcm-java are installed:
# scripts/setup.sh) is $CDPR_LCMTYPES_JAR, else the installed <prefix>/share/cdpr/java/ one next
# to <prefix>/bin, else the build tree's <build>/lcmtypes/ one next to <build>/apps. LCM's
# lcm.jar and jchart2d.jar come from /usr/share/java (Debian: liblcm-java, libjchart2d-java).
# Exit status: lcm-spy's; --check: 0 every type found, 1 not; 3 a jar or java missing.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
jar=${CDPR_LCMTYPES_JAR:-}
if [ -z "$jar" ]; then
    for c in "$here/../share/cdpr/java/cdpr_lcmtypes.jar" "$here/../lcmtypes/cdpr_lcmtypes.jar"; do
        if [ -f "$c" ]; then
            jar=$c
            break
        fi
    done
fi
missing() {
    echo "cdpr-lcm-spy: $1" >&2
    exit 3
}
[ -n "$jar" ] && [ -f "$jar" ] ||
    missing "cdpr_lcmtypes.jar not found next to $here (built when javac and liblcm-java are installed: scripts/setup.sh); or set CDPR_LCMTYPES_JAR"
lcm_jar=/usr/share/java/lcm.jar
chart_jar=/usr/share/java/jchart2d.jar
[ -f "$lcm_jar" ] || missing "$lcm_jar not found (Debian: apt-get install liblcm-java)"
[ -f "$chart_jar" ] || missing "$chart_jar not found (Debian: apt-get install libjchart2d-java)"
command -v java >/dev/null 2>&1 || missing "java not found (Debian: apt-get install default-jdk-headless)"
cp=$lcm_jar:$chart_jar:$jar
case "${1:-}" in
--classpath)
    echo "$cp"
    exit 0
    ;;
--check)
    exec java -cp "$cp" "$(dirname "$jar")/SpyTypes.java" "$jar"
    ;;
-h | --help)
    sed -n '3,17s/^# \{0,1\}//p' "$0"
    exit 0
    ;;
esac
exec java -Djava.net.preferIPv4Stack=true -Xmx128m -cp "$cp" lcm.spy.Spy "$@"
