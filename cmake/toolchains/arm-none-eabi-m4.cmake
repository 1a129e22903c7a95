# SPDX-License-Identifier: BSD-3-Clause
# Cortex-M4 with the single-precision FPU (fpv4-sp-d16). Every double operation is a software
# library call there, so the core is built in float (CDPR_REAL_FLOAT -> CDPR_REAL_IS_FLOAT,
# the default this file sets; the cortex-m4 preset sets it too). Emulated by QEMU's
# mps2-an386 board (Cortex-M4 FPGA image for the MPS2).
#
#   cmake --preset cortex-m4      (or: cmake -DCMAKE_TOOLCHAIN_FILE=<this file> ...)

set(CDPR_ARM_CPU_FLAGS "-mcpu=cortex-m4 -mfpu=fpv4-sp-d16 -mfloat-abi=hard -mthumb")
set(CDPR_QEMU_MACHINE mps2-an386)
set(CDPR_REAL_FLOAT ON CACHE BOOL "Build the core with float instead of double")
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi-common.cmake)
