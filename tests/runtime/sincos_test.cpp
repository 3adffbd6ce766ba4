// dyngen::sincos (sincos.hpp, sincos.h) against MPFR: the error in ulps of sin and cos, double
// and float, over dense random samples, every binade up to the largest value, the arguments
// nearest to multiples of pi/2 (where argument reduction cancels) and to odd multiples of pi/4
// (where the quadrant changes), and the special values; for float also every argument of the fast
// path, against the double function. The bounds are the measured maxima plus a small margin.
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
/// [-pi, pi] (a throwaway run), plus a small margin. Float: measured 0.849 over every float of
/// the fast path (FloatFastPathEveryArgument) and 0.849 over every 13th float above it (a throwaway run; the test takes every 61st).
constexpr double double_bound = 0.78;
constexpr double float_bound = 0.86;

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

/// Numbers of `digits` significant bits x = m 2^(E-digits+1), m in [2^(digits-1), 2^digits),
/// close to multiples of pi/2: the `keep` of the binade [2^E, 2^(E+1)) nearest to one among the
/// candidates tried, with |x - n pi/2|. x 2/pi = m alpha + an integer, alpha = 2^(E-digits+1)
/// 2/pi mod 1, and the denominators q of alpha's continued-fraction convergents give the
/// smallest |q alpha - p| for their size; the smallest multiples of each q in the range of m are
/// the candidates.
std::vector<std::pair<double, double>> near_multiples_of_pio2(int E, int keep, int digits = 53) {
  const mp_prec_t prec = std::max(E, 0) + 256;  // alpha to 2^-190, beyond q^-2 for q < 2^53
  const mpreal two_over_pi = 2 / mpfr::const_pi(prec);
  mpreal alpha = mpfr::ldexp(two_over_pi, E - digits + 1);
  alpha -= floor(alpha);
  const std::uint64_t m_lo = std::uint64_t{1} << (digits - 1), m_hi = std::uint64_t{1} << digits;
  std::vector<std::pair<double, double>> candidates;  // (x, |x - n pi/2|)
  auto try_multiples = [&](std::uint64_t q) {
    for (std::uint64_t c = (m_lo + q - 1) / q, k = 0; k < 2 && c <= (m_hi - 1) / q; ++c, ++k) {
      const std::uint64_t m = c * q;
      mpreal t = alpha * mpreal(static_cast<unsigned long long>(m), prec);
      t -= round(t);
      candidates.push_back({std::ldexp(static_cast<double>(m), E - digits + 1),
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
    const std::uint64_t n_fast = dyngen_sc_reduce_fast(x, &rh_fast, &rl_fast) & 3;
    const std::uint64_t n_huge = dyngen_sc_reduce_huge(x, &rh_huge, &rl_huge);
    ASSERT_EQ(n_fast, n_huge) << "x = " << x;
    const double diff = (rh_fast - rh_huge) + (rl_fast - rl_huge);
    EXPECT_LE(std::fabs(diff), 0x1p-125 + 0x1p-104 * std::fabs(rh_fast)) << "x = " << x;
  }
}

float float_from_bits(std::uint32_t u) {
  float x;
  std::memcpy(&x, &u, sizeof x);
  return x;
}

TEST(Sincos, Float) {
  // Every 10007th float bit pattern (427,520 finite floats, every binade, both signs), the floats
  // nearest to k pi/2, and in every binade the floats nearest to a multiple of pi/2, among them
  // the nearest of all floats (|r| = 2^-29.2 at 0x1.f37c8ap+95, which sincos.h's reduction of
  // huge floats is sized for) and the nearest below the fast path's bound (2^-27.8 at
  // 0x1.f9cbe2p+7).
  std::vector<float> xs;
  for (std::uint64_t u = 0; u < (std::uint64_t{1} << 32); u += 10007) {
    const float x = float_from_bits(static_cast<std::uint32_t>(u));
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
  double min_r = 1, min_r_below_bound = 1;
  float min_r_at = 0, min_r_below_bound_at = 0;
  for (int E = -1; E <= 127; ++E) {
    for (const auto& [x, r] : near_multiples_of_pio2(E, 4, 24)) {
      xs.push_back(static_cast<float>(x));
      if (r < min_r) min_r = r, min_r_at = static_cast<float>(x);
      if (x < 0x1p8 && r < min_r_below_bound)
        min_r_below_bound = r, min_r_below_bound_at = static_cast<float>(x);
    }
  }
  std::printf("measured smallest |x - n pi/2| of a float: 2^%.2f at %a, below 2^8: 2^%.2f at %a\n",
              std::log2(min_r), min_r_at, std::log2(min_r_below_bound), min_r_below_bound_at);
  EXPECT_EQ(min_r_at, 0x1.f37c8ap+95f);
  EXPECT_NEAR(std::log2(min_r), -29.21, 0.01);
  EXPECT_EQ(min_r_below_bound_at, 0x1.f9cbe2p+7f);
  EXPECT_NEAR(std::log2(min_r_below_bound), -27.83, 0.01);
  xs.push_back(std::numeric_limits<float>::max());
  const std::size_t n = xs.size();
  for (std::size_t i = 0; i < n; ++i) xs.push_back(-xs[i]);
  const MaxError hard = measure(xs);
  hard.print("float, nearest to k pi/2 (k <= 20000) and to multiples of pi/2 in every binade");
  EXPECT_LE(hard.sin, float_bound) << "at x = " << hard.sin_at;
  EXPECT_LE(hard.cos, float_bound) << "at x = " << hard.cos_at;
}

/// The float error in ulps against the double sincos, whose own error (0.78 double ulp) is
/// 2^-29 of a float ulp: close enough to MPFR to judge every float, and 50 times faster.
double float_ulps_against_double(float got, double exact) {
  if (exact == 0) return got == 0 ? 0.0 : std::numeric_limits<double>::infinity();
  const int binade = std::max(std::ilogb(exact), -126);
  return std::fabs(static_cast<double>(got) - exact) * std::ldexp(1.0, 23 - binade);
}

/// Raises m to the float error of sincos(x) against the double function.
void measure_against_double(float x, MaxError& m) {
  float s, c;
  sincos(x, s, c);
  double sd, cd;
  sincos(static_cast<double>(x), sd, cd);
  const double es = float_ulps_against_double(s, sd), ec = float_ulps_against_double(c, cd);
  if (!(es <= m.sin)) m.sin = es, m.sin_at = x;
  if (!(ec <= m.cos)) m.cos = ec, m.cos_at = x;
  ++m.count;
}

TEST(Sincos, FloatFastPathEveryArgument) {
  // Every positive float from 2^-12 to the fast path's bound 2^8 (226 million; below 2^-12 sin
  // rounds to x and cos to 1, checked in FloatTiny), and every 7th negative one: the whole fast
  // path, by exhaustion.
  MaxError m;
  const std::uint32_t lo = 0x39800000u, hi = 0x43800000u;  // 2^-12, 2^8
  for (std::uint32_t u = lo; u < hi; ++u) measure_against_double(float_from_bits(u), m);
  for (std::uint32_t u = lo; u < hi; u += 7) measure_against_double(-float_from_bits(u), m);
  m.print("float fast path, every argument, against double");
  EXPECT_LE(m.sin, float_bound) << "at x = " << m.sin_at;
  EXPECT_LE(m.cos, float_bound) << "at x = " << m.cos_at;
}

TEST(Sincos, FloatAboveTheFastPath) {
  // Every 61st float from 2^8 to FLT_MAX (the Payne-Hanek path in integers), against the double
  // function; and that reduction against the double one's on the same floats.
  MaxError m;
  double worst_r = 0;
  float r_at = 0;
  for (std::uint32_t u = 0x43800000u; u < 0x7F800000u; u += 61) {
    const float x = float_from_bits(u);
    measure_against_double(x, m);
    float rh, rl;
    double dh, dl;
    const std::uint32_t nf = dyngen_sc_reduce_hugef(x, &rh, &rl);
    const std::uint64_t nd = dyngen_sc_reduce_huge(x, &dh, &dl);
    ASSERT_EQ(nf, nd) << "x = " << x;
    const double er = std::fabs((static_cast<double>(rh) + rl - dh) - dl) / std::fabs(dh);
    if (!(er <= worst_r)) worst_r = er, r_at = x;
  }
  m.print("float above 2^8, every 61st, against double");
  std::printf("measured float reduction above 2^8: within 2^%.1f relative (x = %a)\n",
              std::log2(worst_r), r_at);
  EXPECT_LE(m.sin, float_bound) << "at x = " << m.sin_at;
  EXPECT_LE(m.cos, float_bound) << "at x = " << m.cos_at;
  EXPECT_LE(worst_r, 0x1p-30) << "at x = " << r_at;
}

TEST(Sincos, FloatFastReductionEveryArgument) {
  // The float reduction against the double one for every float from pi/4 to 2^8: the same
  // quadrant, and rh + rl within 2^-40 relative (sincos.h's bound).
  double worst = 0;
  float at = 0;
  for (std::uint32_t u = 0x3F490FDBu; u < 0x43800000u; ++u) {
    const float x = float_from_bits(u);
    float rh, rl;
    double dh, dl;
    const std::uint32_t nf = dyngen_sc_reduce_fastf(x, &rh, &rl);
    const std::uint64_t nd = dyngen_sc_reduce_fast(x, &dh, &dl);
    // Where x 2/pi is within rounding of a half-integer, the two may pick neighbouring n, and
    // r differs by pi/2 (hi + lo, as in sincos.h)
    const int step = static_cast<int>((nf - nd) & 3);
    ASSERT_TRUE(step == 0 || ((step == 1 || step == 3) && std::fabs(dh) > 0.785)) << "x = " << x;
    const double k = step == 0 ? 0.0 : step == 1 ? 1.0 : -1.0;
    const double r = (dh - k * dyngen_sc_pio2_hi) + (dl - k * dyngen_sc_pio2_lo);
    const double err = std::fabs((static_cast<double>(rh) + rl - (dh - k * dyngen_sc_pio2_hi)) -
                                 (dl - k * dyngen_sc_pio2_lo)) /
                       std::fabs(r);
    if (!(err <= worst)) worst = err, at = x;
  }
  std::printf("measured float fast reduction: within 2^%.1f relative (x = %a)\n", std::log2(worst),
              at);
  EXPECT_LE(worst, 0x1p-40) << "at x = " << at;
}

TEST(Sincos, FloatTiny) {
  // Below 2^-12, sin x rounds to x and cos x to 1, subnormals included.
  for (std::uint32_t u = 0; u < 0x39800000u; u += 997) {
    for (const float x : {float_from_bits(u), -float_from_bits(u)}) {
      float s, c;
      sincos(x, s, c);
      EXPECT_EQ(std::memcmp(&s, &x, sizeof s), 0) << "x = " << x;
      EXPECT_EQ(c, 1.0f) << "x = " << x;
    }
  }
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
