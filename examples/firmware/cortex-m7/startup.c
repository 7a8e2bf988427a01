/* Minimal Cortex-M7 start-up: vector table, copy .data, clear .bss, switch the
 * FPU on, run static constructors, call main. Enough for a linked image whose
 * size and symbols can be checked; a vehicle's board support package has its own. */
#include <stdint.h>

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;
extern void (*__init_array_start[])(void);
extern void (*__init_array_end[])(void);
int main(void);

void Reset_Handler(void);
void Default_Handler(void);

void Default_Handler(void) {
  for (;;) {
  }
}

/* The 16 system exceptions of ARMv7-M; a real part adds its interrupts. */
__attribute__((section(".isr_vector"), used)) static void (*const vector_table[16])(void) = {
    (void (*)(void))(&_estack), Reset_Handler,   Default_Handler, Default_Handler,
    Default_Handler,            Default_Handler, Default_Handler, 0,
    0,                          0,               0,               Default_Handler,
    Default_Handler,            0,               Default_Handler, Default_Handler,
};

void Reset_Handler(void) {
  /* CP10 and CP11 full access (CPACR), before any floating-point instruction. */
  volatile uint32_t* const cpacr = (volatile uint32_t*)0xE000ED88u;
  *cpacr |= 0xFu << 20;
  __asm volatile("dsb\n\tisb" ::: "memory");

  for (uint32_t *src = &_sidata, *dst = &_sdata; dst < &_edata;) *dst++ = *src++;
  for (uint32_t* dst = &_sbss; dst < &_ebss;) *dst++ = 0;
  for (void (**f)(void) = __init_array_start; f < __init_array_end; ++f) (*f)();

  main();
  for (;;) {
  }
}
