/* SPDX-License-Identifier: BSD-3-Clause */
/// @file startup.c
/// Reset and fault handling for bare-metal executables on QEMU's MPS2 boards (mps2-an500:
/// Cortex-M7, mps2-an386: Cortex-M4), used by the unit tests and the firmware example.
///
/// A Cortex-M core reads its initial stack pointer and reset address from the vector table at
/// address 0 (link.ld puts .isr_vector there). The reset handler does what newlib's crt0 cannot
/// know about this board: it turns the FPU on and copies initialised data from its load address
/// to RAM. It then enters newlib's rdimon crt0 (`_start`), which zeroes .bss, opens the
/// semihosting stdio handles, runs main and passes its return value to exit(); under QEMU
/// with -semihosting that value becomes QEMU's exit status, so ctest sees failures.
///
/// Faults print their name over semihosting and stop QEMU with a failure status at once,
/// instead of spinning until ctest's timeout.
#include <stdint.h>

/* Symbols defined by tests/target/link.ld. */
extern uint32_t __data_load__[];
extern uint32_t __data_start__[];
extern uint32_t __data_end__[];
extern uint32_t __stack[];

/* newlib's semihosting crt0 (rdimon-crt0.o, linked by --specs=rdimon.specs). */
extern void _start(void) __attribute__((noreturn));

void Reset_Handler(void) __attribute__((noreturn));
void SysTick_Handler(void);

/* System Control Block registers (ARMv7-M Architecture Reference Manual, B3.2). */
#define SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)

/* Semihosting operations (ARM "Semihosting for AArch32 and AArch64", v2.0). */
enum { SH_SYS_WRITE0 = 0x04, SH_SYS_EXIT = 0x18 };
enum { ADP_STOPPED_RUNTIME_ERROR_UNKNOWN = 0x20023 };

static uint32_t semihost(uint32_t op, uint32_t arg)
{
    /* The debugger (here QEMU) intercepts BKPT 0xAB on M-profile cores: r0 holds the
     * operation, r1 its argument, r0 the result. */
    register uint32_t r0 __asm__("r0") = op;
    register uint32_t r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

static void fault_exit(const char *what) __attribute__((noreturn));
static void fault_exit(const char *what)
{
    (void)semihost(SH_SYS_WRITE0, (uint32_t)(uintptr_t)what);
    /* AArch32 SYS_EXIT takes the reason code itself; anything but ApplicationExit makes
     * QEMU exit with status 1. */
    (void)semihost(SH_SYS_EXIT, ADP_STOPPED_RUNTIME_ERROR_UNKNOWN);
    for (;;) {
    }
}

static void nmi_handler(void)
{
    fault_exit("\n*** NMI\n");
}
static void hardfault_handler(void)
{
    fault_exit("\n*** HardFault\n");
}
static void memmanage_handler(void)
{
    fault_exit("\n*** MemManage fault\n");
}
static void busfault_handler(void)
{
    fault_exit("\n*** BusFault\n");
}
static void usagefault_handler(void)
{
    fault_exit("\n*** UsageFault (e.g. an FPU instruction with the FPU off)\n");
}
static void unexpected_handler(void)
{
    fault_exit("\n*** unexpected exception\n");
}

/* The firmware example overrides this; the tests never enable SysTick. */
__attribute__((weak)) void SysTick_Handler(void)
{
    unexpected_handler();
}

void Reset_Handler(void)
{
    /* Full access to coprocessors 10 and 11 (the FPU) for privileged and user code. Until
     * this is done, the first floating-point instruction raises a UsageFault. crt0 and main
     * are compiled with -mfloat-abi=hard, so it must happen before them. */
    SCB_CPACR |= (0xFu << 20);
    __asm__ volatile("dsb\n\tisb" ::: "memory");

    /* .data is stored after the code (load address) and lives in RAM (run address). */
    const uint32_t *src = __data_load__;
    for (uint32_t *dst = __data_start__; dst < __data_end__; ++dst, ++src) {
        *dst = *src;
    }
    _start();
}

typedef void (*vector_t)(void);

/* The 16 system exceptions of ARMv7-M; no device interrupt is used. Entry 0 is the initial
 * stack pointer, not a handler. */
__attribute__((section(".isr_vector"), used)) static const vector_t vectors[16] = {
    (vector_t)(uintptr_t)__stack, /* initial SP: top of RAM */
    Reset_Handler,
    nmi_handler,
    hardfault_handler,
    memmanage_handler,
    busfault_handler,
    usagefault_handler,
    0,
    0,
    0,
    0,
    unexpected_handler, /* SVCall */
    unexpected_handler, /* DebugMonitor */
    0,
    unexpected_handler, /* PendSV */
    SysTick_Handler,
};
