/* Prints 1 when the processor has AVX2 as GCC's target_clones resolver asks it, else 0: what the
 * loader chooses between a generated function's clones (DYNGEN_DISPATCH). */
#include <stdio.h>

int main(void) {
  __builtin_cpu_init();
  printf("%d\n", __builtin_cpu_supports("avx2") ? 1 : 0);
  return 0;
}
