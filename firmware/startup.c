// SPDX-License-Identifier: MIT
// Start-up code for the firmware images and the on-target tests: the
// Cortex-M vector table and a reset handler that enables the FPU (when the
// build uses it), copies .data from flash, zeroes .bss and calls main().
//
// GF_FW_SEMIHOSTING: the test images. The reset handler also opens the
// semihosting file handles (newlib's rdimon) so that printf reaches the
// host, and hands main's return value to exit(), which ends QEMU with that
// exit code. A fault ends QEMU with exit code 3. Without it (the footprint
// images) nothing of the C library is called: main's return parks the core.
#include <stdint.h>

#ifdef GF_FW_SEMIHOSTING
#include <stdlib.h>
void initialise_monitor_handles(void);
#endif

int main(void);
void Reset_Handler(void);
void Fault_Handler(void);

// From the linker script.
extern uint32_t __data_load__[], __data_start__[], __data_end__[];
extern uint32_t __bss_start__[], __bss_end__[], __stack_top__[];

void Reset_Handler(void)
{
#if defined(__ARM_FP)
    // CPACR: full access to coprocessors 10 and 11 (the FPU), before any
    // floating-point instruction runs.
    volatile uint32_t *const cpacr = (volatile uint32_t *)0xE000ED88u;
    *cpacr |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
#endif
    const uint32_t *src = __data_load__;
    for (uint32_t *dst = __data_start__; dst < __data_end__;) {
        *dst++ = *src++;
    }
    for (uint32_t *dst = __bss_start__; dst < __bss_end__;) {
        *dst++ = 0;
    }
#ifdef GF_FW_SEMIHOSTING
    initialise_monitor_handles();
    exit(main());
#else
    (void)main();
    for (;;) {
        __asm__ volatile("wfi");
    }
#endif
}

#ifdef GF_FW_SEMIHOSTING
// newlib's exit() runs __libc_fini_array, which calls _fini; crti.o, left
// out by -nostartfiles, would have defined it. Nothing to finalize here.
void _fini(void);
void _fini(void)
{
}
#endif

void Fault_Handler(void)
{
#ifdef GF_FW_SEMIHOSTING
    _Exit(3);
#else
    for (;;) {
    }
#endif
}

// The first 16 entries (the core's own exceptions); the images use no
// peripheral interrupts. Entry 0 is the initial stack pointer.
typedef void (*gf_fw_vector)(void);
__attribute__((section(".isr_vector"), used))
const gf_fw_vector gf_fw_vectors[16] = {
    (gf_fw_vector)(uintptr_t)__stack_top__,
    Reset_Handler,
    Fault_Handler, // NMI
    Fault_Handler, // HardFault
    Fault_Handler, // MemManage
    Fault_Handler, // BusFault
    Fault_Handler, // UsageFault
    0,
    0,
    0,
    0,
    Fault_Handler, // SVCall
    Fault_Handler, // DebugMon
    0,
    Fault_Handler, // PendSV
    Fault_Handler, // SysTick
};
