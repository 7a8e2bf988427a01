/* Minimal Cortex-M7 start-up: vector table, switch the FPU on, paint the
 * stack (so that the deepest use can be read back), copy .data, clear .bss,
 * run static constructors, call main. Handlers a program does not define
 * are Default_Handler (weak aliases): the image of main.c defines none, the
 * processor-in-the-loop task (pil/) SysTick_Handler and its UART's. A
 * vehicle's board support package has its own. */
#include <stdint.h>

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _sstack, _estack;
extern void (*__init_array_start[])(void);
extern void (*__init_array_end[])(void);
int main(void);

void Reset_Handler(void);
void Default_Handler(void);
void SysTick_Handler(void) __attribute__((weak, alias("Default_Handler")));
void UART0RX_Handler(void) __attribute__((weak, alias("Default_Handler")));

void Default_Handler(void) {
  for (;;) {
  }
}

/* The 16 system exceptions of ARMv7-M, then external interrupt 0 (UART0 RX
 * on the MPS2 boards); a real part lists all of its interrupts. */
__attribute__((section(".isr_vector"), used)) static void (*const vector_table[17])(void) = {
    (void (*)(void))(&_estack), Reset_Handler,   Default_Handler, Default_Handler,
    Default_Handler,            Default_Handler, Default_Handler, 0,
    0,                          0,               0,               Default_Handler,
    Default_Handler,            0,               Default_Handler, SysTick_Handler,
    UART0RX_Handler,
};

void Reset_Handler(void) {
  /* CP10 and CP11 full access (CPACR), before any floating-point instruction. */
  volatile uint32_t* const cpacr = (volatile uint32_t*)0xE000ED88u;
  *cpacr |= 0xFu << 20;
  __asm volatile("dsb\n\tisb" ::: "memory");

  /* Every free stack word below this frame gets the pattern that
   * board_stack_used() (pil/board_mps2_an500.c) looks for. */
  uint32_t* sp;
  __asm volatile("mov %0, sp" : "=r"(sp));
  for (volatile uint32_t* w = &_sstack; w < sp - 8;) *w++ = 0xA5A5A5A5u;

  for (uint32_t *src = &_sidata, *dst = &_sdata; dst < &_edata;) *dst++ = *src++;
  for (uint32_t* dst = &_sbss; dst < &_ebss;) *dst++ = 0;
  for (void (**f)(void) = __init_array_start; f < __init_array_end; ++f) (*f)();

  main();
  for (;;) {
  }
}
