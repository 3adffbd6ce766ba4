// Counted: a double that counts its arithmetic by kind, so that hand-written code templated on
// the scalar (planar_reference.hpp, the dense LDL^T of work_counts.cpp) can be counted on the
// same terms as dyngen's traces: add counts add and sub, as generator/emit.hpp's OpCounts does.
// Conversions from double are free; constants are model data, as they are in a trace. The
// results are those of double, bit for bit.
#pragma once

#include <cmath>

#include "dyngen/sincos.hpp"

namespace dyngen::bench {

struct OpTally {
  long add = 0, mul = 0, div = 0, neg = 0, sin = 0, cos = 0, sqrt = 0;
  long total() const { return add + mul + div + neg + sin + cos + sqrt; }
};

/// The counters of this thread, reset by CountScope.
inline thread_local OpTally op_tally;

/// Counts the operations of its lifetime: op_tally is zeroed on entry, read with counts().
class CountScope {
 public:
  CountScope() { op_tally = {}; }
  const OpTally& counts() const { return op_tally; }
};

struct Counted {
  double value = 0;
  Counted() = default;
  Counted(double x) : value(x) {}  // NOLINT: implicit, so that literals read as in double code
};

inline Counted operator+(Counted a, Counted b) {
  ++op_tally.add;
  return a.value + b.value;
}
inline Counted operator-(Counted a, Counted b) {
  ++op_tally.add;
  return a.value - b.value;
}
inline Counted operator*(Counted a, Counted b) {
  ++op_tally.mul;
  return a.value * b.value;
}
inline Counted operator/(Counted a, Counted b) {
  ++op_tally.div;
  return a.value / b.value;
}
inline Counted operator-(Counted a) {
  ++op_tally.neg;
  return -a.value;
}
// dyngen::sincos, the runtime's and the generated code's sin and cos, so that Counted computes
// the bits double does
inline Counted sin(Counted a) {
  ++op_tally.sin;
  double s, c;
  dyngen::sincos(a.value, s, c);
  return s;
}
inline Counted cos(Counted a) {
  ++op_tally.cos;
  double s, c;
  dyngen::sincos(a.value, s, c);
  return c;
}
inline Counted sqrt(Counted a) {
  ++op_tally.sqrt;
  return std::sqrt(a.value);
}

}  // namespace dyngen::bench
