#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
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

# ctest runs as many tests at once as the machine has cores: no test depends on the machine's
# speed or load (they count periods and states; the LCM tests use memq or a udpm group in their
# own network namespace), so running them side by side is also a check of that.
ctest_jobs=$(nproc)
build_and_test() {
    cmake --preset "$1" && cmake --build --preset "$1" && ctest --preset "$1" -j "$ctest_jobs"
}

# Every tracked source file carries its SPDX licence identifier (LICENSE: BSD-3-Clause).
stage "spdx: licence identifiers (scripts/spdx.sh)" scripts/spdx.sh
stage "debug: configure, build, ctest" build_and_test debug
# Uses the debug tree's file list; fails when any file differs from .clang-format's style.
stage "format-check" cmake --build --preset debug --target format-check
stage "asan: configure, build, ctest" build_and_test asan
# The optimised build users run (-O2; the core -O3) and a second compiler: every target built
# with clang under the same strict warnings, every test run.
stage "release: configure, build, ctest" build_and_test release
stage "clang: configure, build everything, ctest" build_and_test clang
# Firmware targets (cmake/toolchains): the core and its target-capable unit tests, cross-built
# with arm-none-eabi-gcc and run under QEMU through ctest. Cortex-M7 with the double FPU on
# mps2-an500; Cortex-M4 with the single FPU on mps2-an386, core in float.
stage "cortex-m7: configure, build, ctest on QEMU mps2-an500" build_and_test cortex-m7
stage "cortex-m4 (float): configure, build, ctest on QEMU mps2-an386" build_and_test cortex-m4
# The library as users consume it (tests/consumer/run.sh): the release and cortex-m7 trees
# above installed to temporary prefixes; out-of-tree consumers through find_package, pkg-config
# and, on the Cortex-M7, the installed package and add_subdirectory(lib/core <binary-dir>),
# each bit-identical to the project's own build, the M7 ones without fused multiply-adds.
stage "consumers: installed package, pkg-config, firmware routes (tests/consumer)" \
    tests/consumer/run.sh
# Code/data size and worst-case stack of the step path from those two builds.
stage "footprint (docs/firmware.md)" scripts/footprint.sh

# Static analysis of the library and app sources (tests are exercised dynamically instead).
mapfile -t cdpr_sources < <(git ls-files 'lib/*.c' 'apps/*.c')
stage "cppcheck" cppcheck --enable=warning,style,portability,performance --std=c99 \
    --error-exitcode=1 --inline-suppr --quiet -I lib/core/include -I build/debug/lib/core/include \
    -I lib/control/include -I lib/gsl/include \
    "${cdpr_sources[@]}"
# .clang-tidy holds the check set and the reasons for each exclusion. The firmware example is
# a cross-only source (no entry in the host compile database): the cortex builds compile it
# with the strict warnings, cppcheck above reads it.
mapfile -t cdpr_tidy_sources < <(printf '%s\n' "${cdpr_sources[@]}" | grep -v '^apps/firmware-example/')
stage "clang-tidy" clang-tidy --quiet -p build/debug "${cdpr_tidy_sources[@]}"
# libFuzzer on the LCM winch-command decoder + validator (tests/lcm/fuzz_lcm_command.c, with
# ASan + UBSan): in the clang tree above (the target exists only when the compiler is clang),
# the seeds written by fuzz_lcm_seeds plus what earlier runs added to build/clang/fuzz-corpus,
# 60 s.
# libFuzzer exits non-zero on a crash, leak, sanitizer report, slow input (> 10 s) or broken
# contract check (the target aborts); the input is then in build/clang/fuzz-findings/.
fuzz_lcm() {
    local dir=build/clang
    cmake --preset clang >/dev/null &&
        cmake --build --preset clang --target fuzz_lcm_command fuzz_lcm_seeds &&
        mkdir -p "$dir/fuzz-corpus" "$dir/fuzz-findings" &&
        "$dir/tests/lcm/fuzz_lcm_seeds" "$dir/fuzz-corpus" || return 1
    "$dir/tests/lcm/fuzz_lcm_command" -max_total_time=60 -timeout=10 -print_final_stats=1 \
        -artifact_prefix="$dir/fuzz-findings/" "$dir/fuzz-corpus"
}
stage "fuzz: LCM command decoder + validator, libFuzzer 60 s (clang)" fuzz_lcm
# MISRA C:2012 screening of the firmware code (cppcheck's misra addon; rule numbers only):
# fails on a rule, or a count, beyond the deviations documented in docs/misra.md.
stage "misra (lib/core, lib/control; deviations in docs/misra.md)" scripts/misra.sh

# Line and branch coverage of the libraries (gcovr) from the coverage preset: one more full,
# instrumented build and ctest run, counters zeroed first so that a rerun measures one run.
# Fails when lib/core's line coverage is below 90 %. Reports in build/coverage/: core.txt
# (per file: lines, then branches, then the summary), index.html (annotated lib/core),
# host.txt, lcm.txt and rt.txt. The numbers are quoted in README.md and docs/development.md.
coverage() {
    local dir=build/coverage st=0 summary
    # CompilerIdC: CMake's compiler-identification program, not ours (and never run).
    local opts=(--root . --object-directory "$dir" --exclude 'tests/' --exclude 'build/'
        --exclude-directories '.*/CompilerIdC$' --exclude-unreachable-branches)
    cmake --preset coverage && cmake --build --preset coverage || return 1
    find "$dir" -name '*.gcda' -delete
    ctest --preset coverage -j "$ctest_jobs" || st=1
    summary=$(gcovr "${opts[@]}" --filter 'lib/core/' --txt "$dir/core.txt" \
        --html-details "$dir/index.html" --html-title 'cdpr lib/core coverage' \
        --print-summary --fail-under-line 90) || st=1
    gcovr "${opts[@]}" --filter 'lib/core/' --branches --txt "$dir/core-branches.txt" || st=1
    cat "$dir/core-branches.txt" >>"$dir/core.txt"
    printf '%s\n' "lib/core (the stage fails below 90 % of lines):" "$summary" >>"$dir/core.txt"
    cat "$dir/core.txt"
    for lib in control host lcm rt; do
        if [[ -d lib/$lib ]]; then
            echo "lib/$lib:"
            gcovr "${opts[@]}" --filter "lib/$lib/" --txt "$dir/$lib.txt" --print-summary || st=1
        fi
    done
    return $st
}
stage "coverage: configure, build, ctest, gcovr (lib/core lines >= 90 %)" coverage

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
