/* Bare-metal start-up for the QEMU MPS2 boards (Cortex-M3 AN385, Cortex-M4F AN386): the vector
 * table, a reset handler that sets up C (copies .data, zeroes .bss), enables the FPU on the M4
 * and fixes its arithmetic modes, calls main() and hands main's return value to the emulator
 * as its exit status; plus the semihosting calls (semihost.h). Small on purpose: this is what a
 * CMSIS start-up file does, without the vendor names. */
#include <stdint.h>

#include "semihost.h"

extern uint32_t __stack_top, __data_start, __data_end, __data_load, __bss_start, __bss_end;
extern int main(void);

void Reset_Handler(void) __attribute__((noreturn));
void Fault_Handler(void) __attribute__((noreturn));

/* Initial stack pointer, then the 15 system exception vectors (reset .. SysTick). Any fault or
 * unexpected exception ends the run with status 100 instead of hanging the emulator. */
__attribute__((section(".isr_vector"), used)) static const struct {
    uint32_t *stack;
    void (*handler[15])(void);
} vectors = {
    &__stack_top,
    {Reset_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler,
     0, 0, 0, 0, Fault_Handler, Fault_Handler, 0, Fault_Handler, Fault_Handler}};

void Reset_Handler(void)
{
    uint32_t *src = &__data_load, *dst = &__data_start;
    while (dst < &__data_end) {
        *dst++ = *src++;
    }
    for (dst = &__bss_start; dst < &__bss_end; ++dst) {
        *dst = 0u;
    }
#if defined(__ARM_FP)
    /* Cortex-M4F: grant full access to CP10/CP11 (the FPU) in CPACR, then wait for it. */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    /* FPSCR = 0: round to nearest even, flush-to-zero OFF (FZ, bit 24: subnormals are computed
     * in full, as NumPy/Rust float32 on the host do), default-NaN OFF (DN, bit 25). FPDSCR
     * (0xE000EF3C) holds the same modes for exception handlers' FP contexts; set them too.
     * Both are 0 at reset already; saying so here makes the tests independent of the boot
     * ROM and documents what a firmware start-up must not change. */
    *(volatile uint32_t *)0xE000EF3Cu &= ~((1u << 26) | (1u << 25) | (1u << 24) | (3u << 22));
#if defined(GYRO_FLUSH_TO_ZERO)
    /* Only for the tests' negative control: FZ = 1 must change the float32 bits. */
    __asm__ volatile("vmsr fpscr, %0" : : "r"(1u << 24) : "memory");
#else
    __asm__ volatile("vmsr fpscr, %0" : : "r"(0u) : "memory");
#endif
#endif
    sh_exit((uint32_t)main());
}

void Fault_Handler(void)
{
    sh_exit(100u);
}

static int sh_call(uint32_t op, void *arg)
{
    register uint32_t r0 __asm__("r0") = op;
    register void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return (int)r0;
}

int sh_open(const char *name, uint32_t mode)
{
    uint32_t len = 0u, block[3];
    while (name[len] != '\0') {
        ++len;
    }
    block[0] = (uint32_t)(uintptr_t)name;
    block[1] = mode;
    block[2] = len;
    return sh_call(0x01u, block); /* SYS_OPEN */
}

uint32_t sh_read(int handle, void *buf, uint32_t len)
{
    uint32_t block[3];
    block[0] = (uint32_t)handle;
    block[1] = (uint32_t)(uintptr_t)buf;
    block[2] = len;
    return (uint32_t)sh_call(0x06u, block); /* SYS_READ: returns the bytes not read */
}

void sh_write(int handle, const void *buf, uint32_t len)
{
    uint32_t block[3];
    block[0] = (uint32_t)handle;
    block[1] = (uint32_t)(uintptr_t)buf;
    block[2] = len;
    if (sh_call(0x05u, block) != 0) { /* SYS_WRITE: returns the bytes not written */
        sh_exit(3u);
    }
}

void sh_exit(uint32_t status)
{
    /* SYS_EXIT_EXTENDED {ADP_Stopped_ApplicationExit, status}: QEMU exits with status. */
    uint32_t block[2];
    block[0] = 0x20026u;
    block[1] = status;
    for (;;) {
        (void)sh_call(0x20u, block);
    }
}
