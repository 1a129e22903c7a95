# SPDX-License-Identifier: BSD-3-Clause
# Cortex-M7 with the double-precision FPU (fpv5-d16): the core computes in double, as on the
# host. Emulated by QEMU's mps2-an500 board (Cortex-M7 FPGA image for the MPS2).
#
#   cmake --preset cortex-m7      (or: cmake -DCMAKE_TOOLCHAIN_FILE=<this file> ...)

set(CDPR_ARM_CPU_FLAGS "-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb")
set(CDPR_QEMU_MACHINE mps2-an500)
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi-common.cmake)
