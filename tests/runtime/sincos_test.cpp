// dyngen::sincos (sincos.hpp) against MPFR: the error in ulps of sin and cos, double and float,
// over dense random samples, every binade up to DBL_MAX, the doubles nearest to multiples of
// pi/2 (where argument reduction cancels) and to odd multiples of pi/4 (where the quadrant
// changes), and the special values. The bounds are the measured maxima plus a small margin.
#include "dyngen/sincos.hpp"

#include <gtest/gtest.h>
#include <mpreal.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace dyngen {
namespace {

using mpfr::mpreal;

/// MPFR's sin and cos are correctly rounded to this precision, so the reference is within
/// 2^-128 relative, far below the ulp fractions measured.
constexpr mp_prec_t ref_bits = 128;
constexpr double dbl_max = std::numeric_limits<double>::max();
constexpr double pi = 3.141592653589793;

/// Bounds, in ulps. Double: measured 0.732 here, 0.766 over 10^7 more random arguments in
/// [-pi, pi] (a throwaway run), plus a small margin. Float: measured 0.50000 here; the float is
/// the double result rounded, within 2^-36 relative before, so 0.5 + 2^-11 bounds it.
constexpr double double_bound = 0.78;
constexpr double float_bound = 0.5 + 0x1p-11;

/// |got - exact| in ulps of the exact value's binade, for a format of p bits whose smallest
/// normal binade is 2^emin (ulps are constant over the subnormals).
double ulp_error(double got, const mpreal& exact, int p, int emin) {
  if (exact == 0) return got == 0 ? 0.0 : std::numeric_limits<double>::infinity();
  const long binade = std::max<long>(mpfr_get_exp(exact.mpfr_srcptr()) - 1, emin);
  mpreal diff = abs(mpreal(got, ref_bits) - exact);
  return mpfr::ldexp(diff, static_cast<mp_exp_t>(p - 1 - binade)).toDouble();
}

/// The largest errors over a set of arguments, and where.
struct MaxError {
  double sin = 0, cos = 0;
  double sin_at = 0, cos_at = 0;
  long count = 0;

  void print(const char* what) const {
    std::printf(
        "measured %s (%ld arguments): max error sin %.5f ulp (x = %a), cos %.5f ulp (x = %a)\n",
        what, count, sin, sin_at, cos, cos_at);
  }
};

/// Errors of dyngen::sincos over xs (finite), F = double or float.
template <class F>
MaxError measure(const std::vector<F>& xs) {
  constexpr int p = std::numeric_limits<F>::digits;
  constexpr int emin = std::numeric_limits<F>::min_exponent - 1;
  MaxError m;
  mpreal x(0, ref_bits), s(0, ref_bits), c(0, ref_bits);
  for (const F xi : xs) {
    F si, ci;
    sincos(xi, si, ci);
    x = static_cast<double>(xi);
    mpfr_sin_cos(s.mpfr_ptr(), c.mpfr_ptr(), x.mpfr_srcptr(), MPFR_RNDN);
    const double es = ulp_error(si, s, p, emin), ec = ulp_error(ci, c, p, emin);
    if (!(es <= m.sin)) m.sin = es, m.sin_at = xi;  // a NaN result counts as the worst
    if (!(ec <= m.cos)) m.cos = ec, m.cos_at = xi;
  }
  m.count = static_cast<long>(xs.size());
  return m;
}

std::vector<double> uniform(double lo, double hi, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> dist(lo, hi);
  std::vector<double> xs(n);
  for (double& x : xs) x = dist(rng);
  return xs;
}

double from_bits(std::uint64_t u) {
  double x;
  std::memcpy(&x, &u, sizeof x);
  return x;
}

/// n doubles of each sign in every binade, the subnormals included: random significands.
std::vector<double> every_binade(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> xs;
  for (std::uint64_t e = 0; e < 2047; ++e) {
    for (int k = 0; k < n; ++k) {
      std::uint64_t mantissa = rng() >> 12;
      if (e == 0) mantissa >>= rng() % 52;  // spread over the subnormal binades
      for (std::uint64_t sign : {0, 1}) xs.push_back(from_bits(sign << 63 | e << 52 | mantissa));
    }
  }
  return xs;
}

/// The double nearest to k pi/4.
double nearest_multiple_of_pio4(long k) {
  const mpreal v = mpfr::const_pi(ref_bits + 64) * k / 4;
  return v.toDouble();
}

/// Doubles x = m 2^(E-52), m in [2^52, 2^53), close to multiples of pi/2: the `keep` of the
/// binade [2^E, 2^(E+1)) nearest to one among the candidates tried, with |x - n pi/2|. x 2/pi
/// = m alpha + an integer, alpha = 2^(E-52) 2/pi mod 1, and the denominators q of alpha's
/// continued-fraction convergents give the smallest |q alpha - p| for their size; the smallest
/// multiples of each q in [2^52, 2^53) are the candidates.
std::vector<std::pair<double, double>> near_multiples_of_pio2(int E, int keep) {
  const mp_prec_t prec = std::max(E, 0) + 256;  // alpha to 2^-190, beyond q^-2 for q < 2^53
  const mpreal two_over_pi = 2 / mpfr::const_pi(prec);
  mpreal alpha = mpfr::ldexp(two_over_pi, E - 52);
  alpha -= floor(alpha);
  const std::uint64_t m_lo = std::uint64_t{1} << 52, m_hi = std::uint64_t{1} << 53;
  std::vector<std::pair<double, double>> candidates;  // (x, |x - n pi/2|)
  auto try_multiples = [&](std::uint64_t q) {
    for (std::uint64_t c = (m_lo + q - 1) / q, k = 0; k < 2 && c <= (m_hi - 1) / q; ++c, ++k) {
      const std::uint64_t m = c * q;
      mpreal t = alpha * mpreal(static_cast<unsigned long long>(m), prec);
      t -= round(t);
      candidates.push_back({std::ldexp(static_cast<double>(m), E - 52),
                            (abs(t) * mpfr::const_pi(prec) / 2).toDouble()});
    }
  };
  std::uint64_t q_prev = 0, q = 1;  // q_{-1}, q_0
  mpreal frac = alpha;
  while (frac != 0) {
    const mpreal v = 1 / frac;
    const mpreal a = floor(v);
    frac = v - a;
    if (a >= static_cast<double>(m_hi)) break;
    const std::uint64_t ai = a.toULLong();
    if (ai > (m_hi - 1 - q_prev) / q) break;
    const std::uint64_t q_next = ai * q + q_prev;
    q_prev = q;
    q = q_next;
    try_multiples(q);
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const auto& a, const auto& b) { return a.second < b.second; });
  if (static_cast<int>(candidates.size()) > keep) candidates.resize(keep);
  return candidates;
}

std::vector<double> with_negatives(std::vector<double> xs) {
  const std::size_t n = xs.size();
  for (std::size_t i = 0; i < n; ++i) xs.push_back(-xs[i]);
  return xs;
}

TEST(Sincos, DenseRanges) {
  struct Range {
    const char* name;
    double half_width;
    int n;
  };
  std::uint64_t seed = 1;
  for (const Range& r : {Range{"[-pi, pi]", pi, 200000}, Range{"[-100, 100]", 100, 100000},
                         Range{"[-1e6, 1e6]", 1e6, 100000}}) {
    const MaxError m = measure(uniform(-r.half_width, r.half_width, r.n, seed++));
    m.print(r.name);
    EXPECT_LE(m.sin, double_bound) << r.name << " at x = " << m.sin_at;
    EXPECT_LE(m.cos, double_bound) << r.name << " at x = " << m.cos_at;
  }
}

TEST(Sincos, EveryBinade) {
  const MaxError m = measure(every_binade(12, 7));
  m.print("every binade, both signs, subnormal to DBL_MAX");
  EXPECT_LE(m.sin, double_bound) << "at x = " << m.sin_at;
  EXPECT_LE(m.cos, double_bound) << "at x = " << m.cos_at;
}

TEST(Sincos, NearMultiplesOfPiOver2) {
  // The doubles nearest to k pi/2 and their neighbours, for small k and around the fast
  // reduction's bound 2^21.
  std::vector<double> xs;
  auto around = [&](long k) {
    const double x = nearest_multiple_of_pio4(2 * k);
    for (double y : {std::nextafter(x, 0.0), x, std::nextafter(x, 2 * x)}) xs.push_back(y);
  };
  for (long k = 1; k <= 20000; ++k) around(k);
  for (long k = 1335000; k <= 1335200; ++k) around(k);  // k pi/2 ~ 2^21
  const MaxError small = measure(with_negatives(xs));
  small.print("nearest doubles to k pi/2, k <= 20000 and k pi/2 ~ 2^21");
  EXPECT_LE(small.sin, double_bound) << "at x = " << small.sin_at;
  EXPECT_LE(small.cos, double_bound) << "at x = " << small.cos_at;

  // In every binade from [0.5, 1) to [2^1023, DBL_MAX], the doubles found nearest to a
  // multiple of pi/2; the smallest |x - n pi/2| over all doubles is known to be ~4.69e-19 at
  // 6381956970095103 * 2^797 (Muller, Elementary Functions), which the search must find.
  std::vector<double> hard;
  double min_r = 1, min_r_at = 0;
  for (int E = -1; E <= 1023; ++E) {
    for (const auto& [x, r] : near_multiples_of_pio2(E, 4)) {
      hard.push_back(x);
      if (r < min_r) min_r = r, min_r_at = x;
    }
  }
  const double worst = 6381956970095103.0 * 0x1p797;
  EXPECT_EQ(min_r_at, worst);
  EXPECT_NEAR(min_r, 4.687e-19, 0.001e-19);
  std::printf("measured smallest |x - n pi/2| found: %.4g = 2^%.2f at x = %a\n", min_r,
              std::log2(min_r), min_r_at);
  const MaxError m = measure(with_negatives(hard));
  m.print("nearest doubles to multiples of pi/2 in every binade");
  EXPECT_LE(m.sin, double_bound) << "at x = " << m.sin_at;
  EXPECT_LE(m.cos, double_bound) << "at x = " << m.cos_at;
}

TEST(Sincos, NearOddMultiplesOfPiOver4) {
  // Where x 2/pi rounds to the next quadrant: r is about +-pi/4 on either side.
  std::vector<double> xs;
  for (long k = 0; k <= 4000; ++k) {
    double x = nearest_multiple_of_pio4(2 * k + 1);
    for (int i = 0; i < 2; ++i) x = std::nextafter(x, 0.0);
    for (int i = 0; i < 5; ++i, x = std::nextafter(x, dbl_max)) xs.push_back(x);
  }
  const MaxError m = measure(with_negatives(xs));
  m.print("around (2k+1) pi/4");
  EXPECT_LE(m.sin, double_bound) << "at x = " << m.sin_at;
  EXPECT_LE(m.cos, double_bound) << "at x = " << m.cos_at;
}

TEST(Sincos, SpecialValues) {
  double s, c;
  for (double zero : {0.0, -0.0}) {
    sincos(zero, s, c);
    EXPECT_EQ(s, 0.0);
    EXPECT_EQ(std::signbit(s), std::signbit(zero));
    EXPECT_EQ(c, 1.0);
  }
  // Below 2^-26.5, sin x rounds to x and cos x to 1, subnormals included.
  for (double x : {0x1p-1074, 0x1p-1060, 0x1.8p-1023, 0x1p-1022, 1e-300, 1e-100, 1e-20, 1e-9,
                   0x1.fffffffffffffp-28}) {
    for (double y : {x, -x}) {
      sincos(y, s, c);
      EXPECT_EQ(s, y);
      EXPECT_EQ(c, 1.0);
    }
  }
  constexpr double inf = std::numeric_limits<double>::infinity();
  for (double x : {inf, -inf, std::numeric_limits<double>::quiet_NaN()}) {
    sincos(x, s, c);
    EXPECT_TRUE(std::isnan(s)) << x;
    EXPECT_TRUE(std::isnan(c)) << x;
  }
  float sf, cf;
  for (float x : {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                  std::numeric_limits<float>::quiet_NaN()}) {
    sincos(x, sf, cf);
    EXPECT_TRUE(std::isnan(sf)) << x;
    EXPECT_TRUE(std::isnan(cf)) << x;
  }
  sincos(-0.0f, sf, cf);
  EXPECT_TRUE(sf == 0.0f && std::signbit(sf));
  EXPECT_EQ(cf, 1.0f);
  // The largest, and either side of the fast reduction's bound.
  const MaxError m = measure(with_negatives({dbl_max, std::nextafter(dbl_max, 0.0), 0x1p21,
                                             std::nextafter(0x1p21, 0.0), 0x1p20, 0x1p1023}));
  m.print("DBL_MAX and around 2^21");
  EXPECT_LE(m.sin, double_bound);
  EXPECT_LE(m.cos, double_bound);
}

TEST(Sincos, ReductionsAgree) {
  // Both reductions apply on [2^20, 2^21). Each gives r = rh + rl within about 2^-130 plus
  // the double-double's own 2^-104 relative, and they must give the same quadrant: they could
  // differ only where x 2/pi is within 2^-31 of a half-integer, which these samples do not meet.
  std::vector<double> xs = uniform(0x1p20, 0x1p21, 20000, 11);
  for (long k = 400000; k < 400100; ++k) xs.push_back(nearest_multiple_of_pio4(4 * k));
  for (double x : xs) {
    double rh_fast, rl_fast, rh_huge, rl_huge;
    const std::uint64_t n_fast = sincos_detail::reduce_fast(x, rh_fast, rl_fast) & 3;
    const std::uint64_t n_huge = sincos_detail::reduce_huge(x, rh_huge, rl_huge);
    ASSERT_EQ(n_fast, n_huge) << "x = " << x;
    const double diff = (rh_fast - rh_huge) + (rl_fast - rl_huge);
    EXPECT_LE(std::fabs(diff), 0x1p-125 + 0x1p-104 * std::fabs(rh_fast)) << "x = " << x;
  }
}

TEST(Sincos, Float) {
  // Every 10007th float bit pattern (427,520 finite floats, every binade, both signs), the floats
  // nearest to k pi/2, and the float nearest to a multiple of pi/2 below 2^21.
  std::vector<float> xs;
  for (std::uint64_t u = 0; u < (std::uint64_t{1} << 32); u += 10007) {
    const std::uint32_t bits = static_cast<std::uint32_t>(u);
    float x;
    std::memcpy(&x, &bits, sizeof x);
    if (std::isfinite(x)) xs.push_back(x);
  }
  const MaxError strided = measure(xs);
  strided.print("float, every 10007th bit pattern");
  EXPECT_LE(strided.sin, float_bound) << "at x = " << strided.sin_at;
  EXPECT_LE(strided.cos, float_bound) << "at x = " << strided.cos_at;

  xs.clear();
  for (long k = 1; k <= 20000; ++k) {
    const float x = static_cast<float>(nearest_multiple_of_pio4(2 * k));
    for (float y : {std::nextafter(x, 0.0f), x, std::nextafter(x, 2 * x)}) xs.push_back(y);
  }
  xs.push_back(0x1.f9cbe2p+7f);  // |x - n pi/2| = 2^-27.8, the smallest below 2^21
  xs.push_back(std::numeric_limits<float>::max());
  const std::size_t n = xs.size();
  for (std::size_t i = 0; i < n; ++i) xs.push_back(-xs[i]);
  const MaxError hard = measure(xs);
  hard.print("float, nearest to k pi/2, k <= 20000");
  EXPECT_LE(hard.sin, float_bound) << "at x = " << hard.sin_at;
  EXPECT_LE(hard.cos, float_bound) << "at x = " << hard.cos_at;
}

// The generated code's joint_trig calls the array form, the runtime the scalar one: they must
// agree to the bit, on the fast path and on the arguments the array form redoes after it.
template <class T>
void expect_array_matches_scalar() {
  using L = std::numeric_limits<T>;
  std::mt19937_64 rng(5);
  std::vector<T> x;
  for (int k = 0; k < 1000; ++k)
    x.push_back(static_cast<T>(std::ldexp(static_cast<double>(rng() >> 11) * 0x1p-53 - 0.5,
                                          static_cast<int>(rng() % 40) - 10)));
  for (const T special : {T(0), -T(0), T(0x1p21), T(-0x1p21), T(1e30), L::max(), L::infinity(),
                          -L::infinity(), L::quiet_NaN(), L::denorm_min()})
    x.insert(x.begin() + static_cast<long>(rng() % x.size()), special);
  std::vector<T> s(x.size()), c(x.size());
  sincos(x.data(), s.data(), c.data(), static_cast<int>(x.size()));
  int huge = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    T s1, c1;
    sincos(x[k], s1, c1);
    huge += !(std::fabs(x[k]) < T(0x1p21));
    EXPECT_EQ(std::memcmp(&s1, &s[k], sizeof s1), 0) << "sin at " << x[k];
    EXPECT_EQ(std::memcmp(&c1, &c[k], sizeof c1), 0) << "cos at " << x[k];
  }
  EXPECT_GE(huge, 100) << "the redone arguments are covered";
}

TEST(Sincos, ArrayFormMatchesScalarBitForBit) {
  expect_array_matches_scalar<double>();
  expect_array_matches_scalar<float>();
}

}  // namespace
}  // namespace dyngen
