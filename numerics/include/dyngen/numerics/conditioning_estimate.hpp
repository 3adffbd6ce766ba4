// What the conditioning estimate (conditioning.hpp) finds, apart from how it is computed: a
// light header for code that reports the estimate without computing it (the generator's
// interface), since the computation instantiates Eigen's eigensolvers wherever it is included.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace dyngen::numerics {

/// Up to this many velocity entries cond(M) is computed from the dense M, O(nv^3) in long double
/// (about 0.3 s per sample at 200); above it, by power iterations with RNEA (M x) and ABA
/// (M^-1 x), O(nv) each, at no more than `large_robot_samples` states.
inline constexpr int dense_conditioning_limit = 200;
inline constexpr int large_robot_samples = 4;

struct Conditioning {
  int samples = 0;
  bool cond_M_lower_bound = false;  // cond(M) from power iterations, which approach it from below
  double cond_M_median = 0;  // lambda_max / lambda_min of M(q), median over the samples
  double cond_M_max = 0;     // ... largest
  double pivot_min = 1;      // smallest D_i / max|IA_i| over joints and samples (ABA); for a
                             // free joint the smallest eigenvalue of IA_i instead of D_i
  std::string pivot_joint;   // the joint where it was found
  double inertia_range = 1;  // largest / smallest max|IA_i| over bodies and samples (ABA)
  bool factorised = false;   // mimic joints: the pivots are those of M = L^T D L, D_c / M_cc
  int float_unrepresentable = 0;  // non-zero model constants outside float's normal range

  /// Decimal digits that rounding errors may be amplified by: log10 of the larger of cond(M)
  /// and 1 / pivot_min. An upper bound for any of the algorithms.
  double digits_lost() const { return std::log10(std::max(cond_M_max, 1.0 / pivot_min)); }

  /// Decimal digits ABA loses to cancellation in its pivots, -log10(pivot_min): the estimate
  /// that tracks ABA's measured error (docs/numerics.md); 0 when the pivots were not measured.
  /// Infinite when a pivot is not positive: ABA is undefined there.
  double aba_digits_lost() const {
    return pivot_min > 0 ? std::max(0.0, -std::log10(pivot_min))
                         : std::numeric_limits<double>::infinity();
  }
};

/// Decimal digits of a scalar type's unit roundoff: 15.95 for double, 7.22 for float.
template <class S>
double digits_of() {
  return -std::log10(std::numeric_limits<S>::epsilon() / 2);
}

}  // namespace dyngen::numerics
