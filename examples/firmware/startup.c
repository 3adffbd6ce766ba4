/* The least a Cortex-M needs to run under qemu (mps2-an386 = Cortex-M4F, mps2-an500 =
 * Cortex-M7, mps2-an505 = Cortex-M33): the vector table, .data copied and .bss cleared, the FPU switched on, and ARM
 * semihosting for output and the exit code. No C library. A program may define
 * systick_handler; the others' faults print "fault" and exit with status 3. */
extern unsigned _sidata[], _sdata[], _edata[], _sbss[], _ebss[], _estack[];
int main(void);
void reset_handler(void);
void fault_handler(void);
void systick_handler(void) __attribute__((weak, alias("fault_handler")));
void sh_write(const char* text);
void sh_exit(int code);

__attribute__((section(".vectors"), used)) void (*const vectors[16])(void) = {
    (void (*)(void))_estack, reset_handler, fault_handler, fault_handler, fault_handler,
    fault_handler, fault_handler, 0, 0, 0, 0, fault_handler, fault_handler, 0, fault_handler,
    systick_handler};

static int semihost(int operation, const void* argument) {
  register int r0 __asm__("r0") = operation;
  register const void* r1 __asm__("r1") = argument;
  __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

void sh_write(const char* text) { semihost(0x04, text); /* SYS_WRITE0 */ }

void sh_exit(int code) {
  const unsigned block[2] = {0x20026u, (unsigned)code}; /* ADP_Stopped_ApplicationExit */
  semihost(0x20, block);                                /* SYS_EXIT_EXTENDED */
  for (;;) {
  }
}

void fault_handler(void) {
  sh_write("fault\n");
  sh_exit(3);
}

void reset_handler(void) {
  /* volatile: a plain loop may be turned into a call of memcpy or memset, which is not here */
  volatile unsigned* dst = _sdata;
  const volatile unsigned* src = _sidata;
  while (dst < _edata) *dst++ = *src++;
  for (dst = _sbss; dst < _ebss;) *dst++ = 0;
#if defined(__ARM_FP)
  *(volatile unsigned*)0xE000ED88u |= 0xFu << 20; /* CPACR: full access to CP10 and CP11 */
  __asm__ volatile("dsb\n\tisb" ::: "memory");
#endif
  sh_exit(main());
}
