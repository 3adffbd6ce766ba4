// How large the numbers of a traced program get: every live node's value at sampled states,
// computed as the generated code computes it, in one pass over the graph, against the range of
// its scalar (docs/numerics.md, "Range").
#pragma once

#include "dyngen/model.hpp"
#include "trace.hpp"

namespace dyngen::gen {

/// The states of the estimate are those the generated check draws (templates/check.cpp.in):
/// typical ones, q within +-3.2 (rad, or m for prismatic joints and free positions), v within
/// +-10 and a and tau within +-100, and extreme ones, q within +-1e6, v within +-1e3 and a and
/// tau within +-1e4; free and ball joints' quaternions of unit length. This many of each kind.
inline constexpr int range_samples = 8;

/// What the values reach at one kind of state.
struct Range {
  long double largest = 0;         // the largest finite |value| of a live node
  int overflow = -1;               // the first live node that is not finite at one of the
                                   // states (beyond the scalar's range); -1: none
  long double overflow_value = 0;  // what it would be there without the scalar's range
};

struct RangeEstimate {
  Range typical, extreme;
};

/// The estimate for the program traced from model (the model it was traced from).
template <class T>
RangeEstimate estimate_range(const Program<T>& program, const Model<double>& model);

}  // namespace dyngen::gen
