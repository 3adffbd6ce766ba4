// One call of a generated function between two markers, for scripts/cortex_m_count.sh, which
// counts the instructions qemu executes between them; the stack below the call site is painted
// first and the bytes the call overwrote are printed ("stack N"). DYNGEN_HEADER,
// DYNGEN_NAMESPACE, SCALAR as in harness.cpp; CALL is the call, on the arrays below (any robot
// with nv <= 64), or nothing, for the size of the image without it.
#include DYNGEN_HEADER

namespace robot = DYNGEN_NAMESPACE;

extern "C" void sh_write(const char* text);
extern "C" __attribute__((noinline)) void marker_begin() { __asm__ volatile(""); }
extern "C" __attribute__((noinline)) void marker_end() { __asm__ volatile(""); }

SCALAR q[64], v[64], a[64], tau[64], out[64], M[64 * 64];

int main() {
  for (int k = 0; k < robot::nq; ++k) q[k] = static_cast<SCALAR>(k % 7 - 3) / 4;
  for (int k = 0; k < robot::nv; ++k) v[k] = a[k] = tau[k] = static_cast<SCALAR>(k % 5 - 2) / 2;
  unsigned* top;
  __asm__ volatile("mov %0, sp" : "=r"(top));
  volatile unsigned* const bottom = top - 16384;
  for (volatile unsigned* p = bottom; p < top; ++p) *p = 0xC0FFEE11u;
  marker_begin();
  CALL;
  marker_end();
  volatile unsigned* p = bottom;
  while (p < top && *p == 0xC0FFEE11u) ++p;
  unsigned used = static_cast<unsigned>(reinterpret_cast<volatile char*>(top) -
                                        reinterpret_cast<volatile char*>(p));
  char line[24] = "stack ";
  char digits[12];
  int n = 0, at = 6;
  do digits[n++] = static_cast<char>('0' + used % 10);
  while ((used /= 10) != 0);
  while (n > 0) line[at++] = digits[--n];
  line[at++] = '\n';
  line[at] = 0;
  sh_write(line);
  return 0;
}
