/* What the processor-in-the-loop task needs of a board: a byte link to the
 * host and a tick counter. One file per board implements it:
 * board_mps2_an500.c (QEMU's Cortex-M7 MPS2 system: CMSDK UART0, SysTick),
 * board_host.c (the same task as a host program on stdin/stdout). For an
 * STM32F7/H7, a board_stm32.c would set the clocks (RCC, PLL), a USART and
 * SysTick; the task, the framing, startup.c and sections.ld stay as they are. */
#ifndef NEUROV_PIL_BOARD_H
#define NEUROV_PIL_BOARD_H

#include <stdint.h>

void board_init(void);
/* Next received byte, or -1 once `timeout` ticks have passed since the tick
 * count `since` (timeout 0: wait for ever); sleeps while waiting where the
 * board can. */
int board_read(uint32_t since, uint32_t timeout);
void board_write(const uint8_t* data, uint32_t length);
/* A free-running 32-bit count at board_tick_hz() (wraps; compare by difference). */
uint32_t board_ticks(void);
uint32_t board_tick_hz(void);
/* The CPU's CPUID and MVFR0 registers (0 where there are none). */
uint32_t board_cpuid(void);
uint32_t board_mvfr0(void);
/* Bytes of the main stack ever used (stack painting; 0 where not measured),
 * and the bytes reserved for it. */
uint32_t board_stack_used(void);
uint32_t board_stack_size(void);

#endif
