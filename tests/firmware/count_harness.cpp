// One call of a generated function between two markers, for scripts/cortex_m_count.sh, which
// counts the instructions qemu executes between them; the stack below the call site is painted
// first and the bytes the call overwrote are printed ("stack N"). DYNGEN_HEADER,
// DYNGEN_NAMESPACE, SCALAR as in harness.cpp; CALL is the call, on the arrays below (any robot
// with nv <= 64), or nothing, for the size of the image without it.
#include DYNGEN_HEADER

#include "measure.hpp"

namespace robot = DYNGEN_NAMESPACE;

extern "C" __attribute__((noinline)) void marker_begin() { __asm__ volatile(""); }
extern "C" __attribute__((noinline)) void marker_end() { __asm__ volatile(""); }

SCALAR q[64], v[64], a[64], tau[64], out[64], M[64 * 64];

int main() {
  for (int k = 0; k < robot::nq; ++k) q[k] = static_cast<SCALAR>(k % 7 - 3) / 4;
  for (int k = 0; k < robot::nv; ++k) v[k] = a[k] = tau[k] = static_cast<SCALAR>(k % 5 - 2) / 2;
  unsigned stack = 0;
  FIRMWARE_MEASURED(marker_begin(); CALL; marker_end(), stack);
  firmware::print_count("stack ", stack);
  return 0;
}
