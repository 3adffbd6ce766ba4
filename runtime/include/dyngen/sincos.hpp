// dyngen::sincos: the C++ face of sincos.h (sine and cosine of one angle together, double and
// float, about 1 ulp, the same bits on every IEEE-754 machine), which the generated code calls
// directly; sincos.h has the algorithm and its accuracy.
#pragma once

#include "dyngen/sincos.h"

namespace dyngen {

/// s = sin(x), c = cos(x), within 1 ulp for every double x.
inline void sincos(double x, double& s, double& c) noexcept { dyngen_sincos(x, &s, &c); }

/// s = sin(x), c = cos(x) for a float, computed in float arithmetic, within 1 ulp.
inline void sincos(float x, float& s, float& c) noexcept { dyngen_sincosf(x, &s, &c); }

/// s[k] = sin(x[k]), c[k] = cos(x[k]) for k < n: the same bits as n calls of the above, in
/// about half their time where the compiler vectorises the loop.
inline void sincos(const double* x, double* s, double* c, int n) noexcept {
  dyngen_sincos_array(x, s, c, n);
}
inline void sincos(const float* x, float* s, float* c, int n) noexcept {
  dyngen_sincosf_array(x, s, c, n);
}

}  // namespace dyngen
