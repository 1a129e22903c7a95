#!/usr/bin/env bash
# Builds and tests the project the way CI does: Debug, then AddressSanitizer+UBSan, plus
# static checks. Every stage runs even after a failure, so the summary is complete; the exit
# status is non-zero if any stage failed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/setup.sh

results=()
failed=0

# stage <name> <command...>: runs the command and records PASS/FAIL with its duration.
stage() {
    local name=$1 start=$SECONDS
    shift
    echo "==== $name"
    if "$@"; then
        results+=("PASS  $name ($((SECONDS - start)) s)")
    else
        results+=("FAIL  $name ($((SECONDS - start)) s)")
        failed=1
    fi
}

build_and_test() {
    cmake --preset "$1" && cmake --build --preset "$1" && ctest --preset "$1"
}

stage "debug: configure, build, ctest" build_and_test debug
# Uses the debug tree's file list; fails when any file differs from .clang-format's style.
stage "format-check" cmake --build --preset debug --target format-check
stage "asan: configure, build, ctest" build_and_test asan
# Firmware targets (cmake/toolchains): the core and its target-capable unit tests, cross-built
# with arm-none-eabi-gcc and run under QEMU through ctest. Cortex-M7 with the double FPU on
# mps2-an500; Cortex-M4 with the single FPU on mps2-an386, core in float.
stage "cortex-m7: configure, build, ctest on QEMU mps2-an500" build_and_test cortex-m7
stage "cortex-m4 (float): configure, build, ctest on QEMU mps2-an386" build_and_test cortex-m4
# Code/data size and worst-case stack of the step path from those two builds.
stage "footprint (docs/firmware.md)" scripts/footprint.sh

# Static analysis of the library and app sources (tests are exercised dynamically instead).
mapfile -t cdpr_sources < <(git ls-files 'lib/*.c' 'apps/*.c')
stage "cppcheck" cppcheck --enable=warning,style,portability,performance --std=c99 \
    --error-exitcode=1 --inline-suppr --quiet -I lib/core/include -I lib/gsl/include \
    "${cdpr_sources[@]}"
# .clang-tidy holds the check set and the reasons for each exclusion. The firmware example is
# a cross-only source (no entry in the host compile database): the cortex builds compile it
# with the strict warnings, cppcheck above reads it.
mapfile -t cdpr_tidy_sources < <(printf '%s\n' "${cdpr_sources[@]}" | grep -v '^apps/firmware-example/')
stage "clang-tidy" clang-tidy --quiet -p build/debug "${cdpr_tidy_sources[@]}"
# Later stages (coverage) go here.

echo
echo "==== summary"
printf '%s\n' "${results[@]}"
# Unity reports skipped cases as IGNORE lines with a reason; ctest counts those binaries as
# passed, so list them here to keep them visible.
for preset in debug asan cortex-m7 cortex-m4; do
    log="build/$preset/Testing/Temporary/LastTest.log"
    if [[ -f $log ]] && grep -q ':IGNORE' "$log"; then
        echo "ignored test cases ($preset):"
        grep ':IGNORE' "$log" | sed 's/^/  /'
    fi
done
if [[ $failed -ne 0 ]]; then
    echo "RESULT: FAILED"
    exit 1
fi
echo "RESULT: OK"
