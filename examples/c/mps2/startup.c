/* Start-up for QEMU's mps2-an386 (Cortex-M4F) with newlib and semihosting (librdimon):
 * vector table, reset handler (data, bss, FPU), main, exit through semihosting. Used by
 * firmware/check to run examples/c/fig7.c on the emulated microcontroller. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

extern uint32_t __data_load, __data_start, __data_end, __bss_start, __bss_end, __stack_top;
extern int main(void);
extern void initialise_monitor_handles(void);

void Reset_Handler(void);
void Fault_Handler(void);

__attribute__((section(".isr_vector"), used)) static void (*const vectors[16])(void) = {
    (void (*)(void))(&__stack_top), /* initial SP */
    Reset_Handler,                  /* reset */
    Fault_Handler,                  /* NMI */
    Fault_Handler,                  /* HardFault */
    Fault_Handler,                  /* MemManage */
    Fault_Handler,                  /* BusFault */
    Fault_Handler,                  /* UsageFault */
};

void Reset_Handler(void) {
    /* CPACR: full access to CP10 and CP11 (the FPU) before any float instruction. */
    *(volatile uint32_t *)0xE000ED88 |= 0xFu << 20;
    __asm volatile("dsb\n isb");
    memcpy(&__data_start, &__data_load, (size_t)((char *)&__data_end - (char *)&__data_start));
    memset(&__bss_start, 0, (size_t)((char *)&__bss_end - (char *)&__bss_start));
    initialise_monitor_handles();
    exit(main());
}

/* A fault ends the emulation through semihosting with a non-zero status. */
void Fault_Handler(void) {
    exit(99);
}
