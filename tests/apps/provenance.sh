#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Provenance of cdpr-sim's outputs, checked against independent sources: summary.json's
# "version" and "git_describe" against `cdpr-sim --version`, "scenario_sha256" against
# coreutils' sha256sum of the scenario file, "build_type" against the build's, "integrator"
# rkf45; timeseries.csv starts with the same values as "# key: value" comment lines, then the
# column header.
# Usage: provenance.sh EXE SOURCE_DIR BUILD_TYPE WORK_DIR
set -eu
sim=$1
src=$2
build_type=$3
w=$4
command -v sha256sum >/dev/null || { echo "SKIPPED: sha256sum not found"; exit 77; }
rm -rf "$w"
mkdir -p "$w"
cp "$src/scenarios/paper-line.yaml" "$w/scenario.yaml"
"$sim" "$w/scenario.yaml" --out "$w/out" --duration 0.1 --no-plot --quiet 2>/dev/null
sha=$(sha256sum "$w/scenario.yaml" | cut -d ' ' -f 1)
# "NAME VERSION (git DESCRIBE)"
version=$("$sim" --version | cut -d ' ' -f 2)
describe=$("$sim" --version | sed -n 's/.*(git \(.*\))$/\1/p')
[ -n "$build_type" ] || build_type=null
fail=0
key() { # key NAME VALUE: summary.json has "NAME": "VALUE" (or null) and the CSV "# NAME: VALUE"
    if [ "$2" = null ]; then json="\"$1\": null,"; else json="\"$1\": \"$2\","; fi
    grep -qxF "  $json" "$w/out/summary.json" || { echo "FAIL: summary.json lacks $json"; fail=1; }
    grep -qxF "# $1: $2" "$w/out/timeseries.csv" || { echo "FAIL: CSV lacks '# $1: $2'"; fail=1; }
}
key version "$version"
key git_describe "$describe"
key build_type "$build_type"
key scenario "$w/scenario.yaml"
key scenario_sha256 "$sha"
key integrator rkf45
# The comments come first, then the header (what readers take as the column names).
first=$(grep -vn '^#' "$w/out/timeseries.csv" | head -n 1)
[ "${first%%:*}" -eq 7 ] || { echo "FAIL: the header is line ${first%%:*}, expected 7"; fail=1; }
case ${first#*:} in t_s,x_m,*) ;; *) echo "FAIL: header '${first#*:}'"; fail=1 ;; esac
# A different file, a different hash.
printf '# edited\n' >>"$w/scenario.yaml"
"$sim" "$w/scenario.yaml" --out "$w/out2" --duration 0.1 --no-plot --quiet 2>/dev/null
sha2=$(sha256sum "$w/scenario.yaml" | cut -d ' ' -f 1)
grep -qF "\"scenario_sha256\": \"$sha2\"," "$w/out2/summary.json" && [ "$sha2" != "$sha" ] ||
    { echo "FAIL: the edited scenario's hash"; fail=1; }
[ "$fail" -eq 0 ] || exit 1
echo "PASS: provenance of summary.json and timeseries.csv (sha256 $sha)"
