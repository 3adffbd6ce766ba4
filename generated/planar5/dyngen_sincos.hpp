// dyngen::sincos: sine and cosine of one angle together, in about 60 additions and
// multiplications of doubles and a dozen integer bit operations, with the same bits wherever
// doubles are IEEE-754 binary64 evaluated as such (FLT_EVAL_METHOD 0: SSE2, not x87), rounding to
// nearest, and a*b+c is not contracted into an FMA (-ffp-contract=off).
//
// The runtime calls it for its joint angles and the generated code calls the same header (dyngen
// copies this file verbatim into every package), which is why it depends on nothing but the
// standard library, has a classic include guard rather than #pragma once (both copies may meet
// in one translation unit), and computes only with + - * and integer bit operations.
//
// Accuracy against MPFR (tests/runtime/sincos_test.cpp prints the measured maxima): double at
// most 0.77 ulp measured over the whole range (every binade, the hardest reductions, 10^7 random
// arguments in [-pi, pi]), float within 0.5 + 2^-11 ulp. sin(+-0) = +-0, cos(0) = 1,
// sin(x) = x for tiny and subnormal x, and both are NaN for +-inf and NaN.
//
// Algorithm: x = n pi/2 + r with |r| <= pi/4 (a little more where x 2/pi rounds across a
// half-integer), r carried as a double-double rh + rl; sin r and cos r by polynomials; the
// quadrant n mod 4 swaps them and sets the signs, by bit masks rather than a branch, so that the
// common path has a single, rarely taken branch: to the reduction of arguments beyond 2^21.
#ifndef DYNGEN_SINCOS_HPP
#define DYNGEN_SINCOS_HPP

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace dyngen {
namespace sincos_detail {

static_assert(std::numeric_limits<double>::is_iec559, "dyngen::sincos needs IEEE-754 doubles");

// ---- exact double-double steps. No FMA, so a product's error comes from Veltkamp's split.

/// s + e = a + b exactly (Knuth's TwoSum, no ordering needed).
inline void two_sum(double a, double b, double& s, double& e) noexcept {
  s = a + b;
  const double bb = s - a;
  e = (a - (s - bb)) + (b - bb);
}

/// hi + lo = a with hi holding the top 26 bits (Veltkamp; |a| < 2^995 so nothing overflows).
inline void split(double a, double& hi, double& lo) noexcept {
  const double t = 134217729.0 * a;  // 2^27 + 1
  hi = t - (t - a);
  lo = a - hi;
}

/// p + e = a * b exactly (Dekker's TwoProduct).
inline void two_prod(double a, double b, double& p, double& e) noexcept {
  double ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  p = a * b;
  e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}

inline std::uint64_t bits(double x) noexcept {
  std::uint64_t u;
  std::memcpy(&u, &x, sizeof u);
  return u;
}

inline double from_bits(std::uint64_t u) noexcept {
  double x;
  std::memcpy(&x, &u, sizeof x);
  return x;
}

// ---- fast reduction, |x| < kFastBound ------------------------------------------------------
//
// pi/2 = P1 + P2 + P3 + P4 + O(2^-159), P1..P3 with at most 32 significant bits, P4 a double
// (MPFR, 2000 bits: each part is the remainder rounded to nearest). For |x| < 2^21, n < 2^21, so
// n*P1, n*P2, n*P3 are exact and x - n*P1 is exact (Sterbenz); the two subtractions after it
// keep their rounding errors, so rh + rl is r within 2^-134 + 2^-104 |r| (n*P4's rounding, the
// omitted tail, the sum of the small terms). The smallest |r| of any double with n != 0 is
// 2^-60.9 (Muller, "Elementary Functions": 6381956970095103 * 2^797; the test finds it again),
// so r keeps 2^-73 relative accuracy; n = 0 gives r = x. Why 2^21: the products stay exact up
// to there, and joint angles are far below it.
inline constexpr double kFastBound = 0x1p21;
inline constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
inline constexpr double kP1 = 0x1.921fb544p+0;
inline constexpr double kP2 = 0x1.0b4611a6p-34;
inline constexpr double kP3 = 0x1.3198a2ep-69;
inline constexpr double kP4 = 0x1.b839a252049c1p-104;
// Adding 1.5 * 2^52 rounds a value below 2^51 to an integer, which lands in the low mantissa bits.
inline constexpr double kRoundShift = 0x1.8p52;

/// r = ax - n pi/2 as rh + rl, for 0 <= ax < kFastBound; returns n (mod 2^51).
///
/// The subtractions after t1 are Fast2Sums (s = a + b, e = (a - s) + b), exact here although
/// |a| >= |b| may fail: t1 is a multiple of 2^-52 (or n <= 1, where |t1| > |p2|), so when
/// |t1| < |p2| <= 2^-13, t1 - p2 is a multiple of 2^-65 below 2^-12, representable, and its
/// error is 0; likewise t2 - p3 (|p3| <= 2^-48, multiples of 2^-96). rh + rl is left
/// unnormalised (the kernel only needs |rl| small beside |rh|): |rl| <= 1.5 ulp(rh) when e2 or
/// e3 is nonzero, else |rl| = |n P4| <= 2^-82, below 2^-21 |rh|.
inline std::uint64_t reduce_fast(double ax, double& rh, double& rl) noexcept {
  const double shifted = ax * kTwoOverPi + kRoundShift;
  const double fn = shifted - kRoundShift;
  const double t1 = ax - fn * kP1;
  const double p2 = fn * kP2, p3 = fn * kP3;
  const double t2 = t1 - p2;
  const double e2 = (t1 - t2) - p2;
  rh = t2 - p3;
  rl = (e2 - fn * kP4) + ((t2 - rh) - p3);
  return bits(shifted);
}

// ---- huge arguments: Payne-Hanek ----------------------------------------------------------
//
// 2/pi = sum_j kTwoOverPiWords[j] 2^(-32(j+1)): its first 1280 bits, written by a throwaway MPFR
// program at 2000 bits (w = floor(f * 2^32), f -= w, repeated). Words up to index 36 are used
// (x = m 2^e with e <= 971).
inline constexpr std::uint32_t kTwoOverPiWords[40] = {
    0xA2F9836Eu, 0x4E441529u, 0xFC2757D1u, 0xF534DDC0u, 0xDB629599u, 0x3C439041u, 0xFE5163ABu,
    0xDEBBC561u, 0xB7246E3Au, 0x424DD2E0u, 0x06492EEAu, 0x09D1921Cu, 0xFE1DEB1Cu, 0xB129A73Eu,
    0xE88235F5u, 0x2EBB4484u, 0xE99C7026u, 0xB45F7E41u, 0x3991D639u, 0x835339F4u, 0x9C845F8Bu,
    0xBDF9283Bu, 0x1FF897FFu, 0xDE05980Fu, 0xEF2F118Bu, 0x5A0A6D1Fu, 0x6D367ECFu, 0x27CB09B7u,
    0x4F463F66u, 0x9E5FEA2Du, 0x7527BAC7u, 0xEBE5F17Bu, 0x3D0739F7u, 0x8A5292EAu, 0x6BFB5FB1u,
    0x1F8D5D08u, 0x56033046u, 0xFC7B6BABu, 0xF0CFBC20u, 0x9AF4361Du,
};
inline constexpr double kPio2Hi = 0x1.921fb54442d18p+0;  // pi/2 = kPio2Hi + kPio2Lo + O(2^-108)
inline constexpr double kPio2Lo = 0x1.1a62633145c07p-54;

/// Bits [pos, pos + 32) of the little-endian 32-bit limbs p.
inline std::uint32_t bits_at(const std::uint32_t* p, int pos) noexcept {
  const int limb = pos / 32, shift = pos % 32;
  if (shift == 0) return p[limb];
  return (p[limb] >> shift) | (p[limb + 1] << (32 - shift));
}

/// r = ax - n pi/2 as rh + rl for ax >= 2^20 (or inf, NaN); returns n mod 4.
///
/// ax = m 2^e with m < 2^53. Words j of 2/pi with e - 32(j+1) >= 2 only add multiples of 4 to
/// ax 2/pi, so the product starts at word j0 and takes 7 words: P = m * (224 bits) = ax 2/pi
/// * 2^F, F = 32(j0 + 7) - e in [191, 255], less the words left out, which weigh
/// < 2^(53-F) <= 2^-138. Bits F+1, F of P are n mod 4 and the 160 bits below F the fraction.
inline std::uint64_t reduce_huge(double ax, double& rh, double& rl) noexcept {
  if (!(ax <= std::numeric_limits<double>::max())) {  // inf or NaN: both results NaN
    rh = ax - ax;
    rl = 0.0;
    return 0;
  }
  const std::uint64_t u = bits(ax);
  const int e = static_cast<int>(u >> 52) - 1075;  // ax >= 2^21 is normal
  const std::uint64_t m = (u & ((std::uint64_t{1} << 52) - 1)) | (std::uint64_t{1} << 52);
  const int j0 = e > 2 ? (e - 2) / 32 : 0;

  std::uint32_t p[9] = {};  // P, little-endian limbs
  const std::uint64_t m_limbs[2] = {m & 0xFFFFFFFFu, m >> 32};
  for (int i = 0; i < 2; ++i) {
    std::uint64_t carry = 0;
    for (int k = 0; k < 7; ++k) {
      const std::uint64_t t = m_limbs[i] * kTwoOverPiWords[j0 + 6 - k] + p[i + k] + carry;
      p[i + k] = static_cast<std::uint32_t>(t);
      carry = t >> 32;
    }
    p[i + 7] = static_cast<std::uint32_t>(carry);
  }

  const int F = 32 * (j0 + 7) - e;
  std::uint64_t n = bits_at(p, F) & 3;
  std::uint32_t f[5];  // the fraction, most significant limb first
  for (int k = 0; k < 5; ++k) f[k] = bits_at(p, F - 32 * (k + 1));
  // Round to the nearest n: a fraction >= 1/2 becomes fraction - 1, negated to its magnitude.
  const bool negative = (f[0] >> 31) != 0;
  if (negative) {
    n += 1;
    std::uint64_t borrow = 1;  // two's complement: ~f + 1, from the least significant limb
    for (int k = 4; k >= 0; --k) {
      const std::uint64_t t = std::uint64_t{~f[k]} + borrow;
      f[k] = static_cast<std::uint32_t>(t);
      borrow = t >> 32;
    }
  }
  // fraction = fh + fl (each limb is exact in a double; TwoSum from the smallest up)
  double fh = 0.0, fl = 0.0, scale = 0x1p-160;
  for (int k = 4; k >= 0; --k, scale *= 0x1p32) {
    double err;
    two_sum(fh, static_cast<double>(f[k]) * scale, fh, err);
    fl += err;
  }
  two_sum(fh, fl, fh, fl);
  // r = fraction * pi/2
  double ph, pl;
  two_prod(fh, kPio2Hi, ph, pl);
  pl += fh * kPio2Lo + fl * kPio2Hi;
  two_sum(ph, pl, rh, rl);
  if (negative) {
    rh = -rh;
    rl = -rl;
  }
  return n & 3;
}

// ---- polynomials on |r| <= pi/4 + 2^-20, z = r^2 ------------------------------------------
//
// sin r = r + r^3 S(z), cos r = 1 - z/2 + z^2 C(z). Coefficients: minimax (Remez exchange, a
// throwaway MPFR program at 300 bits) of the error relative to sin r, resp. cos r, with the
// leading coefficient fixed to the double nearest -1/6, resp. 1/24, and the others rounded to
// double afterwards. Measured in MPFR with these doubles, the polynomials' own relative error is
// below 2^-61 (sin) and 2^-62.7 (cos), under 0.003 ulp.
inline constexpr double kS0 = -0x1.5555555555555p-3;
inline constexpr double kS1 = 0x1.1111111111068p-7;
inline constexpr double kS2 = -0x1.a01a019ffe281p-13;
inline constexpr double kS3 = 0x1.71de3a33598bdp-19;
inline constexpr double kS4 = -0x1.ae642bd69331ep-26;
inline constexpr double kS5 = 0x1.6109616b4fb8p-33;
inline constexpr double kS6 = -0x1.9fc9cea5975cbp-41;
inline constexpr double kC0 = 0x1.5555555555555p-5;
inline constexpr double kC1 = -0x1.6c16c16c16289p-10;
inline constexpr double kC2 = 0x1.a01a019e23bdap-16;
inline constexpr double kC3 = -0x1.27e4f8f7626b2p-22;
inline constexpr double kC4 = 0x1.1eea7dad5e23cp-29;
inline constexpr double kC5 = -0x1.8ff3a5d184c24p-37;

inline constexpr double kSplit = 0x1.8p26;  // x + kSplit - kSplit: x to a multiple of 2^-26

/// sin and cos of r = rh + rl, |rh| <= pi/4 + 2^-20, |rl| <= 1.5 ulp(rh) or 2^-21 |rh|.
///
/// The error that matters is the last addition's: the terms added to rh (sin) and to 1 - r^2/2
/// (cos) are small beside them and carry a few of their own ulps. cos needs 1 - r^2/2 exactly,
/// r^2/2 being up to 0.31 of the result: rh = ah + al with ah a multiple of 2^-26, so ah^2/2 is
/// a multiple of 2^-53 and w = 1 - ah^2/2, in [0.69, 1], is exact; the rest of r^2/2,
/// (ah + al/2) al, is small. rl enters to first order: sin(rh + rl) = sin rh + rl cos rh, with
/// w for cos rh (within 2%, on a term of at most 1.5 ulp: 0.03 ulp), and cos(rh + rl) = cos rh
/// - rh rl. The polynomials end in c0 + z q(z), rounded once, but take q by Estrin's scheme, for
/// a shorter dependency chain than Horner's.
inline void kernel(double rh, double rl, double& s, double& c) noexcept {
  const double z = rh * rh, z2 = z * z, z4 = z2 * z2;
  const double ps = kS0 + z * ((kS1 + z * kS2) + z2 * ((kS3 + z * kS4) + z2 * (kS5 + z * kS6)));
  const double pc = kC0 + z * ((kC1 + z * kC2) + z2 * (kC3 + z * kC4) + z4 * kC5);
  const double ah = (rh + kSplit) - kSplit;
  const double al = rh - ah;
  const double w = 1.0 - 0.5 * (ah * ah);
  s = rh + ((rh * z) * ps + rl * w);
  c = w + ((z2 * pc - rh * rl) - (ah + 0.5 * al) * al);
}

/// sin x and cos x from sr = sin r, cr = cos r and n, x = n pi/2 + r: sin x is sr, cr, -sr, -cr
/// and cos x is cr, -sr, -cr, sr for n mod 4 = 0..3, and sin is odd. With masks, not branches.
inline void to_quadrant(double x, std::uint64_t n, double sr, double cr, double& s,
                        double& c) noexcept {
  const std::uint64_t sign = std::uint64_t{1} << 63;
  const std::uint64_t sb = bits(sr), cb = bits(cr);
  const std::uint64_t swap = (sb ^ cb) & (0 - (n & 1));  // sb ^ swap = cb where n is odd
  const std::uint64_t sin_sign = ((n << 62) ^ bits(x)) & sign;
  const std::uint64_t cos_sign = ((n + 1) << 62) & sign;
  s = from_bits(sb ^ swap ^ sin_sign);
  c = from_bits(cb ^ swap ^ cos_sign);
}

/// sincos for |x| >= kFastBound, inf and NaN. Out of line: rarely taken, and it would otherwise
/// be copied into every call site.
[[gnu::noinline, gnu::cold]] inline void sincos_huge(double x, double& s, double& c) noexcept {
  double rh, rl, sr, cr;
  const std::uint64_t n = reduce_huge(std::fabs(x), rh, rl);
  kernel(rh, rl, sr, cr);
  to_quadrant(x, n, sr, cr, s, c);
}

// ---- float: in double, where a plain reduction and shorter polynomials leave 2^-36 -------
//
// r = (x - n P1) - n P2f with P2f = pi/2 - P1 rounded to double: x - n P1 is exact as above,
// and r is within 2^-65 + 2^-53 |r|; the smallest |r| of a float below 2^21 with n != 0 is
// 2^-27.8 (at 0x1.f9cbe2p+7, searched over all of them), so r is within 2^-37 relative.
// Polynomials: minimax as above, relative error 2^-37.5 (sin, degree 3 in z) and 2^-42.9 (cos,
// degree 3). The float is that double rounded once more: at most 0.5 + 2^-11 ulp.
inline constexpr double kP2f = 0x1.0b4611a626331p-34;
inline constexpr double kFS0 = -0x1.5555554c71cb9p-3;
inline constexpr double kFS1 = 0x1.1111086a5d3fap-7;
inline constexpr double kFS2 = -0x1.a00f7f256681ap-13;
inline constexpr double kFS3 = 0x1.6cd1f1e117e1fp-19;
inline constexpr double kFC0 = 0x1.5555554ed982cp-5;
inline constexpr double kFC1 = -0x1.6c16b82a130fp-10;
inline constexpr double kFC2 = 0x1.a010decf09ff6p-16;
inline constexpr double kFC3 = -0x1.241e9be0a5bbdp-22;

/// The double fast path, right for |x| < kFastBound; any other x gives some value, safely.
inline void sincos_fast(double x, double& s, double& c) noexcept {
  double rh, rl, sr, cr;
  const std::uint64_t n = reduce_fast(std::fabs(x), rh, rl);
  kernel(rh, rl, sr, cr);
  to_quadrant(x, n, sr, cr, s, c);
}

/// The float fast path, right for |x| < kFastBound; any other x gives some value, safely.
inline void sincos_fast(float x, float& s, float& c) noexcept {
  const double xd = x, ax = std::fabs(xd);
  const double shifted = ax * kTwoOverPi + kRoundShift;
  const double fn = shifted - kRoundShift;
  const double r = (ax - fn * kP1) - fn * kP2f;
  const double z = r * r, z2 = z * z;
  const double sr = r + (r * z) * ((kFS0 + z * kFS1) + z2 * (kFS2 + z * kFS3));
  const double cr = (1.0 - 0.5 * z) + z2 * ((kFC0 + z * kFC1) + z2 * (kFC2 + z * kFC3));
  double sd, cd;
  to_quadrant(xd, bits(shifted), sr, cr, sd, cd);
  s = static_cast<float>(sd);
  c = static_cast<float>(cd);
}

/// Floats from |x| >= kFastBound, inf and NaN: the double path, rounded.
[[gnu::noinline, gnu::cold]] inline void sincos_huge(float x, float& s, float& c) noexcept {
  double sd, cd;
  sincos_huge(static_cast<double>(x), sd, cd);
  s = static_cast<float>(sd);
  c = static_cast<float>(cd);
}

/// sincos of n values: the fast path over all of them, in a loop without branches that the
/// compiler can vectorise (GCC does at -O3), then the rare huge or non-finite ones again.
template <class T>
void sincos_array(const T* x, T* s, T* c, int n) noexcept {
  for (int k = 0; k < n; ++k) sincos_fast(x[k], s[k], c[k]);
  for (int k = 0; k < n; ++k)
    if (!(std::fabs(x[k]) < T(kFastBound))) sincos_huge(x[k], s[k], c[k]);
}

}  // namespace sincos_detail

#ifdef __FAST_MATH__
// -ffast-math lets the compiler reassociate the exact steps above (two_sum, the rounding shift)
// into nonsense; the C library's sin and cos, compiled apart, keep their accuracy. Bit equality
// with a runtime built without fast-math is lost either way.
inline void sincos(double x, double& s, double& c) noexcept {
  s = std::sin(x);
  c = std::cos(x);
}
inline void sincos(float x, float& s, float& c) noexcept {
  s = std::sin(x);
  c = std::cos(x);
}
inline void sincos(const double* x, double* s, double* c, int n) noexcept {
  for (int k = 0; k < n; ++k) sincos(x[k], s[k], c[k]);
}
inline void sincos(const float* x, float* s, float* c, int n) noexcept {
  for (int k = 0; k < n; ++k) sincos(x[k], s[k], c[k]);
}
#else
/// s = sin(x), c = cos(x), within 1 ulp for every double x (see the top of this file).
inline void sincos(double x, double& s, double& c) noexcept {
  if (!(std::fabs(x) < sincos_detail::kFastBound))
    sincos_detail::sincos_huge(x, s, c);
  else
    sincos_detail::sincos_fast(x, s, c);
}

/// s = sin(x), c = cos(x) for a float, within 0.5 + 2^-11 ulp (see sincos_detail::kP2f).
inline void sincos(float x, float& s, float& c) noexcept {
  if (!(std::fabs(x) < static_cast<float>(sincos_detail::kFastBound)))
    sincos_detail::sincos_huge(x, s, c);
  else
    sincos_detail::sincos_fast(x, s, c);
}

/// s[k] = sin(x[k]), c[k] = cos(x[k]) for k < n: the same bits as n calls of the above, in
/// about half their time where the compiler vectorises the loop.
inline void sincos(const double* x, double* s, double* c, int n) noexcept {
  sincos_detail::sincos_array(x, s, c, n);
}
inline void sincos(const float* x, float* s, float* c, int n) noexcept {
  sincos_detail::sincos_array(x, s, c, n);
}
#endif

}  // namespace dyngen

#endif  // DYNGEN_SINCOS_HPP
