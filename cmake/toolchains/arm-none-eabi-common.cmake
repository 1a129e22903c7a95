# SPDX-License-Identifier: BSD-3-Clause
# Shared part of the arm-none-eabi toolchain files (included by arm-none-eabi-m7.cmake and
# arm-none-eabi-m4.cmake after they set CDPR_ARM_CPU_FLAGS and CDPR_QEMU_MACHINE).
#
# Bare metal: no operating system, newlib as the C library. Only cdpr_core and the tests that
# can run on a target are built (see the top-level CMakeLists.txt and tests/CMakeLists.txt).

set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
# CMake derives ar, ranlib, nm, objcopy, objdump and size from the compiler's prefix.

# A bare-metal executable cannot link without a startup file and a linker script, which a
# compiler check does not have: let CMake's checks build a static library instead.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

# -fno-math-errno: with errno semantics GCC must call sqrt() (to set EDOM), so sqrt never
#   becomes the FPU's vsqrt instruction. The core never reads errno.
# No -ffreestanding: it implies -fno-builtin, which also stops sqrt from being inlined, and we
#   link newlib's libm anyway.
# -ffp-contract=off is set for every build in the top-level CMakeLists.txt (reproducibility:
#   no fused multiply-add on the M7/M4 FPUs either).
# -fstack-usage, -fcallgraph-info=su: per-function stack frames (.su) and the static call
#   graph with frame sizes (.ci) next to each object; scripts/footprint.sh turns them into the
#   worst-case stack of the step path (docs/firmware.md). They do not change the code.
set(CMAKE_C_FLAGS_INIT "${CDPR_ARM_CPU_FLAGS} -fno-math-errno -fstack-usage -fcallgraph-info=su")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${CDPR_ARM_CPU_FLAGS}")

# Search headers and libraries in the cross environment only; programs on the host.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# ctest runs every test executable through QEMU. The test ELF follows -kernel; its vector
# table (tests/target/startup.c) is read at reset, semihosting carries stdout and main's
# return value becomes QEMU's exit status. -nographic: no window, no serial console needed.
find_program(CDPR_QEMU_SYSTEM_ARM qemu-system-arm)
if(CDPR_QEMU_SYSTEM_ARM)
    set(CMAKE_CROSSCOMPILING_EMULATOR
        "${CDPR_QEMU_SYSTEM_ARM};-M;${CDPR_QEMU_MACHINE};-semihosting;-nographic;-kernel")
endif()
