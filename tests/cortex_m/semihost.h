/* Minimal Arm semihosting (Arm "Semihosting for AArch32 and AArch64", v2): the few calls the
 * target tests need, through `bkpt 0xAB` (M-profile). QEMU serves them with
 * -semihosting-config enable=on,target=native: files are opened relative to QEMU's working
 * directory. No C library is involved. */
#ifndef GYRO_SEMIHOST_H
#define GYRO_SEMIHOST_H

#include <stddef.h>
#include <stdint.h>

/* Opens a host file; mode 1 = "rb", 5 = "wb". Returns the handle, or -1. */
int sh_open(const char *name, uint32_t mode);

/* Reads exactly len bytes; returns 0, or the number of bytes missing (end of file). */
uint32_t sh_read(int handle, void *buf, uint32_t len);

/* Writes len bytes; exits with status 3 if the host cannot take them. */
void sh_write(int handle, const void *buf, uint32_t len);

/* Stops the emulator; QEMU exits with this status (SYS_EXIT_EXTENDED). */
void sh_exit(uint32_t status) __attribute__((noreturn));

#endif
