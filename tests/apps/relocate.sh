#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# An installation works wherever its prefix is moved: install BUILD_DIR to a temporary prefix,
# move the prefix, then run the moved cdpr-sim on the moved installation's scenario. It must
# use the moved share/cdpr/scripts/plot_sim.gp (found relative to the executable; its --help
# names the default script) and write the figures; the installed scenario that names a robot file
# by a relative path runs, the installed sweep expands and checks, the installed Python package
# builds and steps a plant; the moved cdpr-lcm-spy (where built) finds
# the moved types jar and lcm-spy's lookup finds the types in it.
# Usage: relocate.sh BUILD_DIR WORK_DIR     (exit 77: skipped, no gnuplot)
set -eu
build=$1
w=$2
command -v gnuplot >/dev/null || { echo "SKIPPED: gnuplot not found"; exit 77; }
rm -rf "$w"
mkdir -p "$w"
cmake --install "$build" --prefix "$w/installed" >"$w/install.txt" 2>&1 ||
    { cat "$w/install.txt"; echo "FAIL: cmake --install $build"; exit 1; }
mv "$w/installed" "$w/moved"
sim=$w/moved/bin/cdpr-sim
[ -x "$sim" ] || { echo "FAIL: $sim not installed"; exit 1; }

script=$w/moved/bin/../share/cdpr/scripts/plot_sim.gp
"$sim" --help >"$w/help.txt"
grep -qF "$script" "$w/help.txt" ||
    { cat "$w/help.txt"; echo "FAIL: the default plot script is not $script"; exit 1; }

"$sim" "$w/moved/share/cdpr/scenarios/paper-line.yaml" --out "$w/out" --duration 1 --quiet \
    2>"$w/err.txt" || { cat "$w/err.txt"; echo "FAIL: cdpr-sim exited $?"; exit 1; }
if grep -q "^cdpr-sim: warning" "$w/err.txt"; then
    cat "$w/err.txt"
    echo "FAIL: cdpr-sim warned (plot script or gnuplot)"
    exit 1
fi
for f in figure5.png tensions.png timeseries.csv summary.json; do
    [ -s "$w/out/$f" ] || { echo "FAIL: $w/out/$f missing or empty"; exit 1; }
done
# A shipped scenario that names a robot file by a relative path, and a shipped sweep (checked,
# not run), from the moved prefix.
"$sim" "$w/moved/share/cdpr/scenarios/example-rig-circle.yaml" --out "$w/rig" --duration 0.5 \
    --quiet --no-plot 2>"$w/rig.txt" || { cat "$w/rig.txt"; echo "FAIL: the installed example-rig-circle.yaml"; exit 1; }
if [ -x "$w/moved/bin/cdpr-sweep" ] && /usr/bin/python3 -c 'import ruamel.yaml' 2>/dev/null; then
    "$w/moved/bin/cdpr-sweep" "$w/moved/share/cdpr/sweeps/paper-wind.yaml" --out "$w/sweep" \
        --dry-run >"$w/sweep.txt" 2>&1 || { cat "$w/sweep.txt"; echo "FAIL: the installed sweep"; exit 1; }
fi

# The Python package (where built): from the moved prefix, with that prefix's Python folder on
# PYTHONPATH (a prefix other than /usr and /usr/local is not on Debian python3's path).
pkg=$(find "$w/moved" -path '*/cdprlib/__init__.py' | head -n 1)
if [ -n "$pkg" ]; then
    PYTHONPATH=$(dirname "$(dirname "$pkg")") /usr/bin/python3 -c '
import sys, cdprlib
p = cdprlib.Plant(sys.argv[1])
p.step(p.control())
assert cdprlib.__file__.startswith(sys.argv[2]), cdprlib.__file__
' "$w/moved/share/cdpr/scenarios/paper-line.yaml" "$w/moved" >"$w/py.txt" 2>&1 ||
        { cat "$w/py.txt"; echo "FAIL: the installed cdprlib"; exit 1; }
fi

# lcm-spy's wrapper, where the build made the Java types: the moved share/cdpr/java jar.
spy=$w/moved/bin/cdpr-lcm-spy
if [ -x "$spy" ]; then
    [ "$("$spy" --classpath | sed 's/.*://')" = "$w/moved/bin/../share/cdpr/java/cdpr_lcmtypes.jar" ] ||
        { "$spy" --classpath; echo "FAIL: cdpr-lcm-spy does not use the moved jar"; exit 1; }
    "$spy" --check >"$w/spy.txt" 2>&1 || { cat "$w/spy.txt"; echo "FAIL: cdpr-lcm-spy --check"; exit 1; }
fi
echo "PASS: the installation moved to $w/moved runs and plots with its own $script"
