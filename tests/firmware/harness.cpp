// Runs a generated package's rnea, crba and aba on a fixed set of states and prints every
// output's bits in hex, one line per call: built for a Cortex-M (under qemu, with semihosting)
// and for the host, and the two printouts must be equal. The states come from integer
// arithmetic scaled by powers of two, so both builds read the same numbers. DYNGEN_HEADER names
// the package's header and DYNGEN_NAMESPACE its namespace, or for a C package (--lang c)
// DYNGEN_PREFIX its prefix and DYNGEN_NQ, DYNGEN_NV its size macros; SCALAR is its scalar; for
// a robot on a free joint, FREE_JOINT_Q is the index in q where its position starts. No library
// beyond the package.
//
// On the Cortex-M it also measures each function's stack: the 64 KiB below the stack pointer
// are painted before each call and searched for the deepest word it overwrote; the most over
// the states is printed as "stack NAME BYTES" after the outputs.
#include DYNGEN_HEADER

#include "measure.hpp"

namespace {

#if defined(DYNGEN_PREFIX)
#define DYNGEN_GLUE(prefix, name) prefix##_##name
#define DYNGEN_NAME(prefix, name) DYNGEN_GLUE(prefix, name)
#define FUNCTION(name) DYNGEN_NAME(DYNGEN_PREFIX, name)
constexpr int nq = DYNGEN_NQ, nv = DYNGEN_NV;
#else
#define FUNCTION(name) DYNGEN_NAMESPACE::name
constexpr int nq = DYNGEN_NAMESPACE::nq, nv = DYNGEN_NAMESPACE::nv;
#endif

unsigned state = 2463534242u;  // xorshift32

/// A number in [-range, range) with 24 significant bits or fewer: exact in float and double.
SCALAR next(int range_log2) {
  state ^= state << 13;
  state ^= state >> 17;
  state ^= state << 5;
  const int k = static_cast<int>(state >> 8) - (1 << 23);  // [-2^23, 2^23)
  SCALAR scale = 1;
  for (int e = 23 - range_log2; e > 0; --e) scale = scale / 2;
  return static_cast<SCALAR>(k) * scale;
}

#if defined(__arm__)
#define MEASURED(call, worst) FIRMWARE_MEASURED(call, worst)
unsigned stack_rnea = 0, stack_crba = 0, stack_aba = 0;
#else
#define MEASURED(call, worst) call
#endif

void print(const char* name, int index, const SCALAR* values, int count) {
  char line[16 + 17 * 64];
  char* out = line;
  for (const char* c = name; *c != 0; ++c) *out++ = *c;
  *out++ = ' ';
  *out++ = static_cast<char>('0' + index);
  for (int k = 0; k < count; ++k) {
    unsigned char bytes[sizeof(SCALAR)];
    __builtin_memcpy(bytes, &values[k], sizeof bytes);
    *out++ = ' ';
    for (int b = static_cast<int>(sizeof bytes) - 1; b >= 0; --b) {
      *out++ = "0123456789abcdef"[bytes[b] >> 4];
      *out++ = "0123456789abcdef"[bytes[b] & 15];
    }
    if (out - line > static_cast<long>(sizeof line) - 40) {
      *out = 0;
      sh_write(line);
      out = line;
    }
  }
  *out++ = '\n';
  *out = 0;
  sh_write(line);
}

}  // namespace

int main() {
  for (int s = 0; s < 8; ++s) {
    SCALAR q[nq], v[nv], a[nv], tau[nv], out[nv], M[nv * nv];
    // angles up to 4 (and, in the last state, up to 512: the large-argument path of sin and cos)
    for (SCALAR& x : q) x = next(s == 7 ? 9 : 2);
#if defined(FREE_JOINT_Q)
    // a unit quaternion, exactly: (+-1/2, +-1/2, +-1/2, +-1/2)
    const SCALAR half = static_cast<SCALAR>(0.5);
    for (int k = 0; k < 4; ++k) q[FREE_JOINT_Q + 3 + k] = next(0) < 0 ? -half : half;
#else
    static_assert(nq == nv, "a robot on a free joint needs FREE_JOINT_Q");
#endif
    for (SCALAR& x : v) x = next(1);
    for (SCALAR& x : a) x = next(2);
    for (SCALAR& x : tau) x = next(4);
    MEASURED(FUNCTION(rnea)(q, v, a, out), stack_rnea);
    print("rnea", s, out, nv);
    MEASURED(FUNCTION(crba)(q, M), stack_crba);
    print("crba", s, M, nv * nv);
    MEASURED(FUNCTION(aba)(q, v, tau, out), stack_aba);
    print("aba", s, out, nv);
  }
#if defined(__arm__)
  firmware::print_count("stack rnea ", stack_rnea);
  firmware::print_count("stack crba ", stack_crba);
  firmware::print_count("stack aba ", stack_aba);
#endif
  return 0;
}
