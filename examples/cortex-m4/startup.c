/* Minimal startup for a Cortex-M4F (QEMU's mps2-an386, or any M4 board after changing the
 * memory map in mps2_an386.ld): the vector table, a reset handler that copies .data, zeroes
 * .bss, turns the FPU on, opens the semihosting console and calls main(), then exit().
 *
 * Build (what tests/codegen/test_board.py and benchmarks/board.py do):
 *   arm-none-eabi-gcc -mcpu=cortex-m4 -mfpu=fpv4-sp-d16 -mfloat-abi=hard -mthumb -std=c99 -O2 \
 *       -nostartfiles --specs=rdimon.specs -T mps2_an386.ld startup.c main.c NAME.c -lm -o app.elf
 *   qemu-system-arm -M mps2-an386 -nographic -semihosting-config enable=on,target=native -kernel app.elf
 *
 * printf and exit go to the host through ARM semihosting (newlib's librdimon); on a board
 * without a debugger attached, link with --specs=nosys.specs instead and send output elsewhere.
 */
#include <stdint.h>
#include <stdlib.h>

extern int main(void);
extern void initialise_monitor_handles(void);

/* From the linker script. */
extern uint32_t __data_load__, __data_start__, __data_end__, __bss_start__, __bss_end__, __stack_top__;

void Reset_Handler(void);
void Default_Handler(void);

void Reset_Handler(void)
{
    uint32_t *src = &__data_load__, *dst = &__data_start__;
    while (dst < &__data_end__) {
        *dst++ = *src++;
    }
    for (dst = &__bss_start__; dst < &__bss_end__; ++dst) {
        *dst = 0u;
    }
    /* CPACR: full access to coprocessors 10 and 11 (the FPU), before any floating-point instruction. */
    *(volatile uint32_t *)0xE000ED88u |= (0xFu << 20);
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    initialise_monitor_handles();
    exit(main());
}

/* exit() runs newlib's __libc_fini_array, which calls _fini; with -nostartfiles there is no crti.o to
 * provide it (nor _init: this startup has no C++ constructors to run). */
void _init(void);
void _fini(void);
void _init(void) {}
void _fini(void) {}

void Default_Handler(void)
{
    exit(99); /* a fault: stop QEMU with a non-zero status rather than hang */
}

/* The first 16 entries of the Cortex-M vector table: initial stack pointer, reset, the faults. */
__attribute__((section(".vectors"), used)) static void (*const vectors[16])(void) = {
    (void (*)(void))(uintptr_t)&__stack_top__,
    Reset_Handler,
    Default_Handler, /* NMI */
    Default_Handler, /* HardFault */
    Default_Handler, /* MemManage */
    Default_Handler, /* BusFault */
    Default_Handler, /* UsageFault */
    0, 0, 0, 0,
    Default_Handler, /* SVCall */
    Default_Handler, /* DebugMon */
    0,
    Default_Handler, /* PendSV */
    Default_Handler, /* SysTick */
};
