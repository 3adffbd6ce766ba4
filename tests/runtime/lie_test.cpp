// lie.h's coefficients of the rotations' exponential and logarithm against their closed forms in
// 256-bit MPFR, in double and float: over t^2 from 1e-12 to 100 (pi^2 for the logarithm's, whose
// closed form has a pole at 2 pi), densely around the cut-overs to the series (t^2 = 1 and 4),
// and at 0, where the closed forms are 0/0 and the series' first coefficient is the limit. The
// error is in units of the format's epsilon, relative to the value, or for cos(t/2) and
// sin(t/2)/t, which cross zero, to their envelopes 1 and min(1/2, 1/t) (near a zero the rounding
// of t itself dominates); the bounds are the measured maxima (printed) with a margin.
#include "dyngen/lie.hpp"

#include <gtest/gtest.h>
#include <mpreal.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace dyngen {
namespace {

using mpfr::mpreal;

constexpr mp_prec_t bits = 256;

struct Coefficient {
  std::string name;
  double (*of_double)(double);
  float (*of_float)(float);
  std::function<mpreal(const mpreal&)> exact;  // of t
  double t2_max;
  double (*envelope)(double t) = nullptr;  // the error's scale where it is not the value
};

std::vector<Coefficient> coefficients() {
  return {
      {"half_cos", half_cos, half_cos, [](const mpreal& t) { return cos(t / 2); }, 100,
       [](double) { return 1.0; }},
      {"half_sinc", half_sinc, half_sinc, [](const mpreal& t) { return sin(t / 2) / t; }, 100,
       [](double t) { return std::min(0.5, 1 / t); }},
      {"exp_c", exp_c, exp_c, [](const mpreal& t) { return (t - sin(t)) / (t * t * t); }, 100},
      {"exp_d", exp_d, exp_d,
       [](const mpreal& t) { return (t * t + 2 * cos(t) - 2) / (2 * pow(t, 4)); }, 100},
      {"exp_e", exp_e, exp_e,
       [](const mpreal& t) { return (2 * t - 3 * sin(t) + t * cos(t)) / (2 * pow(t, 5)); }, 100},
      {"log_alpha", log_alpha, log_alpha,
       [](const mpreal& t) { return 1 / (t * t) - (1 + cos(t)) / (2 * t * sin(t)); }, 9.8},
  };
}

/// t^2 from 1e-12 to t2_max, log-spaced, and the neighbours of the cut-overs.
std::vector<double> arguments(double t2_max) {
  std::vector<double> x;
  for (double e = -12; e <= std::log10(t2_max); e += 0.01) x.push_back(std::pow(10.0, e));
  for (const double cut : {1.0, 4.0}) {
    double below = cut, above = cut;
    for (int k = 0; k < 50; ++k) {
      x.push_back(below = std::nextafter(below, 0.0));
      x.push_back(above = std::nextafter(above, 10.0));
    }
    x.push_back(cut);
  }
  return x;
}

/// |got - exact| / (scale eps), scale |exact| by default
template <class F>
double error(F got, const mpreal& exact, double scale = 0) {
  const mpreal e = abs(mpreal(got, bits) - exact) / (scale > 0 ? mpreal(scale, bits) : abs(exact));
  return e.toDouble() / std::numeric_limits<F>::epsilon();
}

template <class F>
double worst_error(const Coefficient& c, F (*f)(F)) {
  double worst = 0, at = 0;
  for (const double x : arguments(c.t2_max)) {
    const F t2 = static_cast<F>(x);
    if (!(t2 > 0)) continue;
    const double e = error(f(t2), c.exact(sqrt(mpreal(t2, bits))),
                           c.envelope ? c.envelope(std::sqrt(static_cast<double>(t2))) : 0);
    if (e > worst) worst = e, at = t2;
  }
  std::printf("measured %s (%s): max error %.3g eps at t^2 = %.17g\n", c.name.c_str(),
              sizeof(F) == 8 ? "double" : "float", worst, at);
  return worst;
}

// measured at most 4.8 eps (exp_e in double, just past its cut-over to the closed form)
TEST(Lie, CoefficientsMatchMpfr) {
  for (const Coefficient& c : coefficients()) {
    EXPECT_LT(worst_error<double>(c, c.of_double), 6) << c.name;
    EXPECT_LT(worst_error<float>(c, c.of_float), 6) << c.name;
  }
}

TEST(Lie, CoefficientsAtZeroAreTheLimits) {
  EXPECT_EQ(half_cos(0.0), 1.0);
  EXPECT_EQ(half_sinc(0.0), 0.5);
  EXPECT_EQ(exp_c(0.0), dyngen_lie_exp_c_series[0]);
  EXPECT_EQ(exp_d(0.0), dyngen_lie_exp_d_series[0]);
  EXPECT_EQ(exp_e(0.0), dyngen_lie_exp_e_series[0]);
  EXPECT_EQ(log_alpha(0.0), 1.0 / 12);
  EXPECT_EQ(log_factor(0.0, 1.0), 2.0);
  EXPECT_EQ(log_factor(0.0, -1.0), -2.0);
  // the series' leading coefficients are 1/6, 1/24 and 1/120 rounded
  EXPECT_EQ(dyngen_lie_exp_c_series[0], 1.0 / 6);
  EXPECT_EQ(dyngen_lie_exp_d_series[0], 1.0 / 24);
  EXPECT_EQ(dyngen_lie_exp_e_series[0], 1.0 / 120);
}

// log(quaternion (c, u)) = k u for unit quaternions of every angle, both signs of c: k =
// 2 atan2(|u|, |c|) / |u|, negated for c < 0 (the shorter way round)
TEST(Lie, LogFactorMatchesMpfr) {
  double worst = 0;
  for (double e = -12; e <= 0; e += 0.01) {
    const double s2 = std::pow(10.0, e);
    for (const double sign : {1.0, -1.0}) {
      const double c = sign * std::sqrt(1 - s2);
      const mpreal s = sqrt(mpreal(s2, bits)), a = abs(mpreal(c, bits));
      const mpreal exact = sign * 2 * atan2(s, a) / s;
      worst = std::max(worst, error(log_factor(s2, c), exact));
      EXPECT_LT(error(log_factor(static_cast<float>(s2), static_cast<float>(c)),
                      mpreal(2, bits) * sign *
                          atan2(sqrt(mpreal(static_cast<float>(s2), bits)),
                                abs(mpreal(static_cast<float>(c), bits))) /
                          sqrt(mpreal(static_cast<float>(s2), bits))),
                4)
          << s2;
    }
  }
  std::printf("measured log_factor (double): max error %.3g eps\n", worst);
  EXPECT_LT(worst, 4);
}

}  // namespace
}  // namespace dyngen
