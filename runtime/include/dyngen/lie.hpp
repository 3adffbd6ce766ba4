// The C++ face of lie.h: the coefficients of the rotations' exponential and logarithm as
// functions of t^2, which the generated code calls directly. For double and float these are
// lie.h's (so the bits are the generated code's); for other scalars (MPFR in the tests) the
// closed forms, and below t^2 = 1e-6 the same series, in that scalar's arithmetic.
#pragma once

#include <cmath>

// lie.h calls sincos.h's functions and needs it first
// clang-format off
#include "dyngen/sincos.h"
#include "dyngen/lie.h"
// clang-format on

namespace dyngen {

inline double half_cos(double t2) noexcept { return dyngen_half_cos(t2); }
inline float half_cos(float t2) noexcept { return dyngen_half_cosf(t2); }
inline double half_sinc(double t2) noexcept { return dyngen_half_sinc(t2); }
inline float half_sinc(float t2) noexcept { return dyngen_half_sincf(t2); }
inline double exp_c(double t2) noexcept { return dyngen_exp_c(t2); }
inline float exp_c(float t2) noexcept { return dyngen_exp_cf(t2); }
inline double exp_d(double t2) noexcept { return dyngen_exp_d(t2); }
inline float exp_d(float t2) noexcept { return dyngen_exp_df(t2); }
inline double exp_e(double t2) noexcept { return dyngen_exp_e(t2); }
inline float exp_e(float t2) noexcept { return dyngen_exp_ef(t2); }
inline double log_alpha(double t2) noexcept { return dyngen_log_alpha(t2); }
inline float log_alpha(float t2) noexcept { return dyngen_log_alphaf(t2); }
inline double log_factor(double s2, double c) noexcept { return dyngen_log_factor(s2, c); }
inline float log_factor(float s2, float c) noexcept { return dyngen_log_factorf(s2, c); }

namespace detail {

/// lie.h's series (n double coefficients) at t2 in S.
template <class S>
S lie_series(const double* c, int n, const S& t2) {
  S y(c[n - 1]);
  for (int k = n - 2; k >= 0; --k) y = S(c[k]) + t2 * y;
  return y;
}

inline constexpr double lie_generic_series_below = 1e-6;

}  // namespace detail

template <class S>
S half_cos(const S& t2) {
  using std::cos, std::sqrt;
  return cos(sqrt(t2) / S(2));
}

template <class S>
S half_sinc(const S& t2) {
  using std::sin, std::sqrt;
  if (t2 < S(detail::lie_generic_series_below))
    return detail::lie_series(dyngen_lie_half_sinc_series, 12, t2);
  const S t = sqrt(t2);
  return sin(t / S(2)) / t;
}

template <class S>
S exp_c(const S& t2) {
  using std::sin, std::sqrt;
  if (t2 < S(detail::lie_generic_series_below))
    return detail::lie_series(dyngen_lie_exp_c_series, 12, t2);
  const S t = sqrt(t2);
  return (t - sin(t)) / (t2 * t);
}

template <class S>
S exp_d(const S& t2) {
  using std::cos, std::sqrt;
  if (t2 < S(detail::lie_generic_series_below))
    return detail::lie_series(dyngen_lie_exp_d_series, 12, t2);
  return (t2 + S(2) * cos(sqrt(t2)) - S(2)) / (S(2) * t2 * t2);
}

template <class S>
S exp_e(const S& t2) {
  using std::cos, std::sin, std::sqrt;
  if (t2 < S(detail::lie_generic_series_below))
    return detail::lie_series(dyngen_lie_exp_e_series, 12, t2);
  const S t = sqrt(t2);
  return (S(2) * t - S(3) * sin(t) + t * cos(t)) / (S(2) * t2 * t2 * t);
}

template <class S>
S log_alpha(const S& t2) {
  using std::cos, std::sin, std::sqrt;
  if (t2 < S(detail::lie_generic_series_below))
    return detail::lie_series(dyngen_lie_log_alpha_series, 20, t2);
  const S t = sqrt(t2);
  return S(1) / t2 - cos(t / S(2)) / (S(2) * t * sin(t / S(2)));
}

template <class S>
S log_factor(const S& s2, const S& c) {
  using std::atan2, std::sqrt;
  const S s = sqrt(s2), a = c < S(0) ? S(-c) : c;
  const S k = s2 > S(0) ? S(S(2) * atan2(s, a) / s) : S(S(2) / a);
  return c < S(0) ? S(-k) : k;
}

}  // namespace dyngen
