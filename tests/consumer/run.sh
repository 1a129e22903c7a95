#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Consumer tests (scripts/test.sh stage `consumers`): the library used the way a user uses it,
# from outside the source tree, compared with the same program built inside the project.
#
#  host (release preset, installed to a temporary prefix):
#   0. the installed apps find their data files when the prefix is moved (tests/apps/relocate.sh);
#   1. find_package(cdpr 0.1 REQUIRED COMPONENTS core control host) -- tests/consumer/package
#      (state_bits.c plain, with the host preset, and closed by lib/control's tracker); also
#      every other component linked once (CDPR_CONSUMER_ALL) and the docs' example
#      examples/quickstart.c built and run against the package;
#   2. pkg-config cdpr-core, cdpr-control, cdpr-host: cc $(pkg-config --cflags) state_bits.c
#      $(pkg-config --libs);
#      every .pc file validated and resolved;
#   2b. the capacities recorded in cdpr-core.pc and cdprConfig.cmake, and a consumer compiled
#      with other capacities or another real type refused at compile time naming both values;
#   3. the libraries built shared (CDPR_SHARED=ON): SONAMEs, only cdpr_* exported, and 1.'s
#      consumer linked against them;
#   each prints the state bits of state_bits.c, byte-identical to build/release's
#   tests/consumer/cdpr-consumer-{host,core}.
#  Cortex-M7 (cortex-m7 preset, installed to its own prefix), tests/consumer/firmware, Release:
#   a consumer compiled against the installed headers with other capacities refused (as 2b);
#   4. the installed package;  5. add_subdirectory(<src>/lib/core and lib/control);
#   each: 0 FMA instructions (vfma/vfms/vfnma/vfnms) in the libcdpr_core.a and
#   libcdpr_control.a it links, and the
#   output under QEMU mps2-an500 byte-identical to build/cortex-m7's cdpr-consumer-core.
#
# Reuses (and brings up to date) build/release and build/cortex-m7; everything else lives in
# a temporary directory, removed at the end (CDPR_CONSUMER_KEEP=1 keeps it). Exit status 0
# when every check passed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
src=$PWD
jobs=${CDPR_JOBS:-2}
work=$(mktemp -d "${TMPDIR:-/tmp}/cdpr-consumers.XXXXXX")
if [[ ${CDPR_CONSUMER_KEEP:-0} != 1 ]]; then
    trap 'rm -rf "$work"' EXIT
else
    echo "consumers: keeping $work"
fi
failed=0
ok() { echo "consumers: PASS $*"; }
bad() {
    echo "consumers: FAIL $*" >&2
    failed=1
}
# same <what> <expected file> <actual file>
same() {
    if cmp -s "$2" "$3"; then
        ok "$1 ($(wc -l <"$3") lines identical)"
    else
        bad "$1: output differs"
        diff "$2" "$3" | head -n 10 >&2 || true
    fi
}
# fma_count <archive>: fused multiply-add instructions in the disassembly.
fma_count() {
    arm-none-eabi-objdump -d "$1" | grep -cE 'vfn?m[as]' || true
}
qemu_m7() {
    timeout 120 qemu-system-arm -M mps2-an500 -semihosting -nographic -kernel "$1"
}
quiet() {
    local log=$work/log.txt
    if ! "$@" >"$log" 2>&1; then
        cat "$log" >&2
        return 1
    fi
}

# refused <what> <needle> <needle> <command...>: the command (a compile against the installed
# headers with other capacities or another real type than the library's) must fail, and its
# messages must name both values (the two needles).
refused() {
    local what=$1 a=$2 b=$3
    shift 3
    if "$@" >"$work/refused.txt" 2>&1; then
        bad "$what: compiled although the library was built otherwise"
    elif grep -q -- "$a" "$work/refused.txt" && grep -q -- "$b" "$work/refused.txt"; then
        ok "$what: refused at compile time, both values named"
    else
        bad "$what: refused, but the messages do not name '$a' and '$b'"
        head -n 5 "$work/refused.txt" >&2
    fi
}

# ---- host: release build installed to a prefix --------------------------------------------
host=$work/prefix-host
quiet cmake --preset release
quiet cmake --build --preset release -j "$jobs"
quiet cmake --install build/release --prefix "$host"
build/release/tests/consumer/cdpr-consumer-host >"$work/ref-host.txt"
build/release/tests/consumer/cdpr-consumer-core >"$work/ref-core.txt"
build/release/tests/consumer/cdpr-consumer-control >"$work/ref-control.txt"

# 0. the installed apps find their data relative to themselves: the release build installed to
#    a prefix that is then moved; the moved cdpr-sim plots with the moved plot_sim.gp
#    (tests/apps/relocate.sh, also the ctest app_install_relocated).
reloc_rc=0
sh tests/apps/relocate.sh build/release "$work/relocated" >"$work/relocated.txt" 2>&1 || reloc_rc=$?
if [[ $reloc_rc == 0 ]]; then
    ok "installed prefix moved: cdpr-sim finds share/cdpr/scripts/plot_sim.gp and writes figures"
elif [[ $reloc_rc == 77 ]]; then
    echo "consumers: SKIP relocated installation ($(tail -n 1 "$work/relocated.txt"))"
else
    bad "relocated installation: $(tail -n 1 "$work/relocated.txt")"
fi

# 1. find_package
b=$work/package
if quiet cmake -S tests/consumer/package -B "$b" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$host" -DCDPR_CONSUMER_ALL=ON -DCDPR_CONSUMER_EXAMPLES="$src/examples" &&
    quiet cmake --build "$b" -j "$jobs"; then
    if grep -q "^cdpr_DIR:PATH=$host/" "$b/CMakeCache.txt"; then
        ok "find_package found the installed package ($(grep '^cdpr_DIR' "$b/CMakeCache.txt"))"
    else
        bad "find_package did not use $host: $(grep '^cdpr_DIR' "$b/CMakeCache.txt")"
    fi
    "$b/cdpr-consumer-host" >"$work/package.txt" || bad "find_package consumer exited $?"
    same "find_package(cdpr COMPONENTS core host) consumer == in-project cdpr-consumer-host" \
        "$work/ref-host.txt" "$work/package.txt"
    "$b/cdpr-consumer-control" >"$work/package-control.txt" ||
        bad "find_package control consumer exited $?"
    same "find_package(cdpr COMPONENTS control) consumer == in-project cdpr-consumer-control" \
        "$work/ref-control.txt" "$work/package-control.txt"
    if "$b/cdpr-quickstart" >"$work/quickstart.txt"; then
        ok "the docs' example (examples/quickstart.c) builds against the package and runs"
    else
        bad "examples/quickstart.c against the installed package exited non-zero"
    fi
    if "$b/cdpr-consumer-all" >"$work/all.txt"; then
        ok "all components (gsl, lcm, lcmtypes, rt) link and run: $(cat "$work/all.txt")"
    else
        bad "cdpr-consumer-all exited non-zero"
    fi
else
    bad "find_package consumer: configure or build failed"
fi
# A component that is not installed is reported, and fails a REQUIRED find.
if cmake -S tests/consumer/package -B "$work/package-bad" -G Ninja \
    -DCMAKE_PREFIX_PATH="$work/prefix-m7-not-yet" >/dev/null 2>&1; then
    bad "find_package(cdpr REQUIRED) succeeded without an installed package"
else
    ok "find_package(cdpr REQUIRED) fails without an installed package"
fi

# 2. pkg-config
pc_dir=$(dirname "$(find "$host" -name cdpr-core.pc | head -n 1)")
export PKG_CONFIG_PATH=$pc_dir
pc_ok=1
for m in cdpr-core cdpr-control cdpr-host cdpr-design cdpr-lcm cdpr-rt cdpr-gsl; do
    if ! pkg-config --validate "$m" || ! pkg-config --exists --print-errors "$m"; then
        bad "pkg-config $m does not validate or resolve"
        pc_ok=0
    fi
done
[[ $pc_ok == 1 ]] && ok "pkg-config: cdpr-core cdpr-control cdpr-host cdpr-design cdpr-lcm cdpr-rt cdpr-gsl validate and resolve"
read -r -a pc_cflags <<<"$(pkg-config --cflags cdpr-core)"
read -r -a pc_libs <<<"$(pkg-config --libs cdpr-core)"
if cc -O2 -Wall -Wextra -Werror "${pc_cflags[@]}" tests/consumer/state_bits.c "${pc_libs[@]}" \
    -o "$work/pkgconfig-core"; then
    "$work/pkgconfig-core" >"$work/pkgconfig.txt" || bad "pkg-config consumer exited $?"
    same "pkg-config cdpr-core consumer == in-project cdpr-consumer-core" \
        "$work/ref-core.txt" "$work/pkgconfig.txt"
else
    bad "pkg-config consumer: compile or link failed"
fi
read -r -a pc_cflags <<<"$(pkg-config --cflags cdpr-control)"
read -r -a pc_libs <<<"$(pkg-config --libs cdpr-control)"
if cc -O2 -Wall -Wextra -Werror -DCDPR_CONSUMER_CONTROL "${pc_cflags[@]}" \
    tests/consumer/state_bits.c "${pc_libs[@]}" -o "$work/pkgconfig-control"; then
    "$work/pkgconfig-control" >"$work/pkgconfig-control.txt" ||
        bad "pkg-config control consumer exited $?"
    same "pkg-config cdpr-control consumer == in-project cdpr-consumer-control" \
        "$work/ref-control.txt" "$work/pkgconfig-control.txt"
else
    bad "pkg-config cdpr-control consumer: compile or link failed"
fi
read -r -a pc_cflags <<<"$(pkg-config --cflags cdpr-host)"
read -r -a pc_libs <<<"$(pkg-config --libs cdpr-host)"
if cc -O2 -Wall -Wextra -Werror -DCDPR_CONSUMER_HOST "${pc_cflags[@]}" tests/consumer/state_bits.c \
    "${pc_libs[@]}" -o "$work/pkgconfig-host"; then
    "$work/pkgconfig-host" >"$work/pkgconfig-host.txt" || bad "pkg-config host consumer exited $?"
    same "pkg-config cdpr-host consumer == in-project cdpr-consumer-host" \
        "$work/ref-host.txt" "$work/pkgconfig-host.txt"
else
    bad "pkg-config cdpr-host consumer: compile or link failed"
fi
# 2b. the capacities travel with the package: the .pc variables, the CMake package's
#     variables, and a consumer compiled with other values is refused naming both.
pc_caps="$(pkg-config --variable=max_cables cdpr-core) $(pkg-config --variable=max_segments cdpr-core) $(pkg-config --variable=real cdpr-core)"
cfg=$(find "$host" -name cdprConfig.cmake | head -n 1)
if [[ $pc_caps == "8 64 double" ]] && grep -q '^set(cdpr_MAX_CABLES 8)$' "$cfg" &&
    grep -q '^set(cdpr_MAX_SEGMENTS 64)$' "$cfg"; then
    ok "capacities recorded: cdpr-core.pc max_cables/max_segments/real = $pc_caps, cdprConfig.cmake 8 x 64"
else
    bad "capacities not recorded as built (pkg-config: '$pc_caps'; $cfg)"
fi
read -r -a pc_cflags <<<"$(pkg-config --cflags cdpr-core)"
refused "host consumer with -DCDPR_MAX_SEGMENTS=16" "char\[16\]" "char\[64\]" \
    cc -O2 "${pc_cflags[@]}" -DCDPR_MAX_SEGMENTS=16 -c tests/consumer/state_bits.c -o "$work/x.o"
refused "host consumer with -DCDPR_MAX_CABLES=6" "char\[6\]" "char\[8\]" \
    cc -O2 "${pc_cflags[@]}" -DCDPR_MAX_CABLES=6 -c tests/consumer/state_bits.c -o "$work/x.o"
refused "host consumer with -DCDPR_REAL_IS_FLOAT" "CDPR_REAL_IS_FLOAT" "built in double" \
    cc -O2 "${pc_cflags[@]}" -DCDPR_REAL_IS_FLOAT -c tests/consumer/state_bits.c -o "$work/x.o"
unset PKG_CONFIG_PATH

# 3. shared libraries (CDPR_SHARED=ON, the release preset's flags; libraries only): SONAMEs,
# only cdpr_* symbols exported, and the find_package consumer linked against them.
b=$work/shared
shared=$work/prefix-shared
if quiet cmake -S . -B "$b" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_FLAGS_RELEASE="-O2 -DNDEBUG" \
    -DCDPR_SHARED=ON -DCDPR_BUILD_TESTS=OFF -DCDPR_BUILD_APPS=OFF -DCDPR_WERROR=ON &&
    quiet cmake --build "$b" -j "$jobs" && quiet cmake --install "$b" --prefix "$shared"; then
    so_ok=1
    for lib in core control gsl host lcm lcmtypes rt; do
        so=$(find "$shared" -name "libcdpr_$lib.so.0" | head -n 1)
        if [[ -z $so ]]; then
            bad "shared: libcdpr_$lib.so.0 not installed"
            so_ok=0
            continue
        fi
        soname=$(readelf -d "$so" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
        others=$(nm -D --defined-only "$so" | awk '$2 ~ /^[TDBRVW]$/ && $3 !~ /^cdpr_/' | wc -l)
        if [[ $soname != "libcdpr_$lib.so.0" || $others != 0 ]]; then
            bad "shared: $so has SONAME '$soname' and $others exported non-cdpr_ symbols"
            so_ok=0
        fi
    done
    [[ $so_ok == 1 ]] && ok "shared: libcdpr_{core,control,gsl,host,lcm,lcmtypes,rt}.so.0, only cdpr_* exported"
    bs=$work/package-shared
    if quiet cmake -S tests/consumer/package -B "$bs" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_PREFIX_PATH="$shared" && quiet cmake --build "$bs" -j "$jobs"; then
        if ldd "$bs/cdpr-consumer-host" | grep "libcdpr_host.so.0 => $shared/" >/dev/null; then
            "$bs/cdpr-consumer-host" >"$work/package-shared.txt" || bad "shared consumer exited $?"
            same "find_package consumer on the shared libraries == in-project cdpr-consumer-host" \
                "$work/ref-host.txt" "$work/package-shared.txt"
        else
            bad "shared consumer does not load $shared's libcdpr_host.so.0"
        fi
    else
        bad "find_package consumer on the shared libraries: configure or build failed"
    fi
else
    bad "shared build (CDPR_SHARED=ON): configure, build or install failed"
fi

# ---- Cortex-M7 -------------------------------------------------------------------------------
m7=$work/prefix-m7
quiet cmake --preset cortex-m7
quiet cmake --build --preset cortex-m7 -j "$jobs"
quiet cmake --install build/cortex-m7 --prefix "$m7"
qemu_m7 build/cortex-m7/tests/consumer/cdpr-consumer-core >"$work/ref-m7.txt"
qemu_m7 build/cortex-m7/tests/consumer/cdpr-consumer-control >"$work/ref-m7-control.txt"
n=$(fma_count build/cortex-m7/lib/core/libcdpr_core.a)
echo "consumers: the cortex-m7 preset's own libcdpr_core.a: $n FMA instructions"

# A firmware compiled against the installed M7 headers with other capacities: refused too.
m7_flags=(-mcpu=cortex-m7 -mthumb -mfpu=fpv5-d16 -mfloat-abi=hard -std=c99 -O2)
refused "Cortex-M7 consumer with -DCDPR_MAX_SEGMENTS=16" "char\[16\]" "char\[64\]" \
    arm-none-eabi-gcc "${m7_flags[@]}" -I"$m7/include" -DCDPR_MAX_SEGMENTS=16 \
    -c tests/consumer/state_bits.c -o "$work/x-m7.o"
refused "Cortex-M7 consumer with -DCDPR_REAL_IS_FLOAT" "CDPR_REAL_IS_FLOAT" "built in double" \
    arm-none-eabi-gcc "${m7_flags[@]}" -I"$m7/include" -DCDPR_REAL_IS_FLOAT \
    -c tests/consumer/state_bits.c -o "$work/x-m7.o"

toolchain=$src/cmake/toolchains/arm-none-eabi-m7.cmake
for route in package subdirectory; do
    b=$work/firmware-$route
    if ! quiet cmake -S tests/consumer/firmware -B "$b" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_TOOLCHAIN_FILE="$toolchain" -DCDPR_SOURCE_DIR="$src" \
        -DCDPR_CONSUMER_ROUTE=$route -DCMAKE_PREFIX_PATH="$m7" ||
        ! quiet cmake --build "$b" -j "$jobs"; then
        bad "Cortex-M7 $route consumer: configure or build failed"
        continue
    fi
    for archive in "$(cat "$b/CDPR_CORE_ARCHIVE.txt")" "$(cat "$b/CDPR_CONTROL_ARCHIVE.txt")"; do
        n=$(fma_count "$archive")
        if [[ $n == 0 ]]; then
            ok "Cortex-M7 $route consumer: 0 FMA instructions in ${archive#"$work"/}"
        else
            bad "Cortex-M7 $route consumer: $n FMA instructions in $archive"
        fi
    done
    if qemu_m7 "$b/state_bits.elf" >"$work/m7-$route.txt"; then
        same "Cortex-M7 $route consumer on QEMU == the cortex-m7 preset's cdpr-consumer-core" \
            "$work/ref-m7.txt" "$work/m7-$route.txt"
    else
        bad "Cortex-M7 $route consumer failed under QEMU"
    fi
    if qemu_m7 "$b/control_bits.elf" >"$work/m7-$route-control.txt"; then
        same "Cortex-M7 $route consumer with lib/control == the preset's cdpr-consumer-control" \
            "$work/ref-m7-control.txt" "$work/m7-$route-control.txt"
    else
        bad "Cortex-M7 $route consumer with lib/control failed under QEMU"
    fi
done

# Not a pass condition: whether the M7 and the x86-64 host compute the same bits.
if cmp -s "$work/ref-core.txt" "$work/ref-m7.txt"; then
    echo "consumers: note: Cortex-M7 and host outputs are identical"
else
    echo "consumers: note: Cortex-M7 and host outputs differ in" \
        "$(diff "$work/ref-core.txt" "$work/ref-m7.txt" | grep -c '^>' || true) lines (libm)"
fi

if [[ $failed != 0 ]]; then
    echo "consumers: FAILED"
    exit 1
fi
echo "consumers: OK"
