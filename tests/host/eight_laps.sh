#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Learning over laps and the planned transfer on the eight-cable robot (ctest
# eight_circle_laps_run): scenarios/paper-circle-laps.yaml (the paper's circle with its 1.47 m
# start offset, a 3 s transfer, winch tension feedback, learning over laps) with its robot
# replaced by robots/eight-50m.yaml, ten laps through cdpr-sim; check_laps.cmake then guards
# the laps (ctest eight_circle_laps). No design check at load: it refuses these gains on eight
# cables although this run converges (docs/validation.md §6a, an open finding).
# Usage: eight_laps.sh CDPR_SIM SOURCE_DIR WORK_DIR
set -eu
sim=$1
src=$2
w=$3
rm -rf "$w"
mkdir -p "$w"
awk -v robot="$src/robots/eight-50m.yaml" '
    /^robot:/ { print "robot:"; print "  file: " robot; skip = 1; next }
    skip && /^[a-z]/ { skip = 0 }
    !skip { print }' "$src/scenarios/paper-circle-laps.yaml" > "$w/eight-circle-laps.yaml"
grep -q "^  file: .*/robots/eight-50m.yaml$" "$w/eight-circle-laps.yaml" ||
    { echo "FAIL: the scenario copy has no eight-cable robot"; exit 1; }
"$sim" "$w/eight-circle-laps.yaml" --out "$w/out" --no-plot --quiet --unchecked-gains
