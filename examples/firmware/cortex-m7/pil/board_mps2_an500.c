/* The board of QEMU's `-M mps2-an500` (ARM's MPS2 FPGA board with the AN500
 * image: a Cortex-M7 with FPU, 4 MiB ZBT SSRAM at 0x00000000 holding the
 * image, 4 MiB at 0x20000000 for data, CMSDK APB peripherals at 0x40000000,
 * a 25 MHz system clock): UART0 at 0x40004000 as the link to the host,
 * receiving by interrupt (UART0 RX is external interrupt 0) so that the CPU
 * sleeps (WFI) between frames, and SysTick on the processor clock as the
 * tick counter, interrupting every 10 ms to extend its 24 bits. On an
 * STM32F7/H7 this file is what changes (the clock tree, a USART and its
 * interrupt), with the MEMORY of the linker script. */
#include "board.h"

#define REG(addr) (*(volatile uint32_t*)(addr))

#define SYSCLK_HZ 25000000u
#define UART0 0x40004000u
#define UART_DATA REG(UART0 + 0x00u)
#define UART_STATE REG(UART0 + 0x04u) /* bit 0: TX full, bit 1: RX full */
#define UART_CTRL REG(UART0 + 0x08u)  /* bit 0: TX on, bit 1: RX on, bit 3: RX interrupt */
#define UART_INTCLEAR REG(UART0 + 0x0Cu)
#define UART_BAUDDIV REG(UART0 + 0x10u)
#define NVIC_ISER0 REG(0xE000E100u)
#define SYST_CSR REG(0xE000E010u)
#define SYST_RVR REG(0xE000E014u)
#define SYST_CVR REG(0xE000E018u)
#define CPUID REG(0xE000ED00u)
#define ICSR REG(0xE000ED04u)
#define MVFR0 REG(0xE000EF40u)

#define TICK_PERIOD (SYSCLK_HZ / 100u) /* SysTick reload: 10 ms */
#define RX_SIZE 1024u                   /* a power of two */

static volatile uint32_t periods; /* SysTick wraps */
static volatile uint8_t rx[RX_SIZE];
static volatile uint32_t rx_head, rx_tail;

void SysTick_Handler(void) { ++periods; }

/* External interrupt 0: UART0 RX. */
void UART0RX_Handler(void) {
  /* QEMU hands the next byte over as soon as DATA is read: a full ring
   * leaves it in the UART, for board_read() to take. */
  while ((UART_STATE & 2u) && rx_head - rx_tail < RX_SIZE) rx[rx_head++ % RX_SIZE] = (uint8_t)UART_DATA;
  UART_INTCLEAR = 2u;
}

void board_init(void) {
  UART_BAUDDIV = 16u; /* 1.5625 Mbaud at 25 MHz; QEMU's link does not pace by it */
  UART_CTRL = 1u | 2u | 8u;
  NVIC_ISER0 = 1u << 0;
  SYST_RVR = TICK_PERIOD - 1u;
  SYST_CVR = 0u;
  SYST_CSR = 7u; /* processor clock, interrupt, on */
}

uint32_t board_tick_hz(void) { return SYSCLK_HZ; }

uint32_t board_ticks(void) {
  uint32_t p, v, pending;
  do { /* a SysTick interrupt taken between the reads changes `periods` */
    p = periods;
    v = SYST_CVR;
    pending = ICSR & (1u << 26); /* a wrap not yet counted (in a handler) */
  } while (p != periods);
  if (pending && v > TICK_PERIOD / 2u) ++p;
  return p * TICK_PERIOD + (TICK_PERIOD - 1u - v);
}

int board_read(uint32_t since, uint32_t timeout) {
  for (;;) {
    if (rx_tail != rx_head) return rx[rx_tail++ % RX_SIZE];
    /* What a full ring left in the UART; masked, so that the interrupt
     * cannot take the byte between the test and the read. */
    __asm volatile("cpsid i" ::: "memory");
    const int left = (UART_STATE & 2u) && rx_tail == rx_head ? (int)(uint8_t)UART_DATA : -1;
    __asm volatile("cpsie i" ::: "memory");
    if (left >= 0) return left;
    if (timeout != 0u && board_ticks() - since >= timeout) return -1;
    /* Sleeps until an interrupt: a byte, or at the latest the next SysTick
     * (10 ms), which also covers a byte whose interrupt came between the
     * test above and the WFI. (Not the usual cpsid/wfi/cpsie, which
     * closes that gap: under QEMU 7.2 the board, so written, never woke
     * for the host's first frame.) */
    __asm volatile("wfi" ::: "memory");
  }
}

void board_write(const uint8_t* data, uint32_t length) {
  for (uint32_t i = 0; i < length; ++i) {
    while (UART_STATE & 1u) {
    }
    UART_DATA = data[i];
  }
}

uint32_t board_cpuid(void) { return CPUID; }
uint32_t board_mvfr0(void) { return MVFR0; }

extern uint32_t _sstack, _estack;
#define STACK_PAINT 0xA5A5A5A5u /* startup.c's */

uint32_t board_stack_size(void) { return (uint32_t)((&_estack - &_sstack) * 4); }

uint32_t board_stack_used(void) {
  const uint32_t* w = &_sstack;
  while (w < &_estack && *w == STACK_PAINT) ++w;
  return (uint32_t)((&_estack - w) * 4);
}
