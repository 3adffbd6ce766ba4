/* dyngen_sincos: sine and cosine of one angle together, for double (about 60 additions and
 * multiplications of doubles) and for float (about 30 of floats, no double anywhere), with the
 * same bits wherever the format is IEEE-754 evaluated as such (FLT_EVAL_METHOD 0: SSE2 or a
 * Cortex-M FPU, not x87), rounding to nearest, and a*b+c not contracted into an FMA
 * (-ffp-contract=off).
 *
 * The runtime calls it for its joint angles (through dyngen/sincos.hpp) and the generated code
 * calls the same file (dyngen copies it verbatim into every package as dyngen_sincos.h), which
 * is why it is C99 that is also C++, includes nothing, calls no library function (it compiles
 * with -ffreestanding -nostdlib), has a classic include guard rather than #pragma once (both
 * copies may meet in one translation unit), and computes only with + - * and integer bit
 * operations.
 *
 * Accuracy against MPFR (tests/runtime/sincos_test.cpp prints the measured maxima): double at
 * most 0.77 ulp measured over the whole range (every binade, the hardest reductions, 10^7 random
 * arguments in [-pi, pi]); float within 1 ulp (the test gives the measured maximum). sin(+-0) =
 * +-0, cos(0) = 1, sin(x) = x for tiny and subnormal x, and both are NaN for +-inf and NaN.
 *
 * Algorithm: x = n pi/2 + r with |r| <= pi/4 (a little more where x 2/pi rounds across a
 * half-integer), r carried as a pair rh + rl; sin r and cos r by polynomials; the quadrant n mod
 * 4 swaps them and sets the signs, by bit masks rather than a branch, so that the common path has
 * a single, rarely taken branch: to the reduction of large arguments (Payne-Hanek, in integers).
 */
#ifndef DYNGEN_SINCOS_H
#define DYNGEN_SINCOS_H

typedef unsigned int dyngen_sc_u32;
typedef unsigned long long dyngen_sc_u64;
typedef char dyngen_sc_u32_has_32_bits[sizeof(dyngen_sc_u32) == 4 ? 1 : -1];
typedef char dyngen_sc_u64_has_64_bits[sizeof(dyngen_sc_u64) == 8 ? 1 : -1];
typedef char dyngen_sc_float_is_binary32[sizeof(float) == 4 ? 1 : -1];
typedef char dyngen_sc_double_is_binary64[sizeof(double) == 8 ? 1 : -1];

/* DYNGEN_DISPATCH, before a function's definition: the load-time choice of instruction set that
 * the generated functions and dyngen's loops take. On x86-64 GNU/Linux (the loader's ifunc) with
 * a compiler that has target_clones (GCC, clang), each such function is compiled for AVX2 and
 * for the baseline, and the loader binds the one the processor runs. The bits are the same in
 * both: AVX2 has no FMA to contract a*b+c into, and nothing is reassociated. It is empty where
 * code is built for one instruction set anyway (-mavx2, a Cortex-M) or under
 * -DDYNGEN_NO_DISPATCH (one baseline copy, half the compile time). DYNGEN_DISPATCHES says which
 * (1 or 0). */
#if defined(__x86_64__) && defined(__gnu_linux__) && !defined(__AVX2__)
#if !defined(DYNGEN_NO_DISPATCH) && defined(__has_attribute)
#if __has_attribute(target_clones)
#define DYNGEN_DISPATCHES 1
#define DYNGEN_DISPATCH __attribute__((target_clones("avx2", "default")))
#endif
#endif
#endif
#ifndef DYNGEN_DISPATCH
#define DYNGEN_DISPATCHES 0
#define DYNGEN_DISPATCH
#endif

#if defined(__GNUC__)
/* Large arguments are rare: kept out of line so that every call site stays small. */
#define DYNGEN_SC_COLD __attribute__((noinline, cold))
#else
#define DYNGEN_SC_COLD
#endif

/* ---- bits. Unions: defined in C, and GCC, clang and MSVC give C++ the same meaning. */

static inline dyngen_sc_u64 dyngen_sc_bits(double x) {
  union { double f; dyngen_sc_u64 u; } v;
  v.f = x;
  return v.u;
}

static inline double dyngen_sc_from_bits(dyngen_sc_u64 u) {
  union { double f; dyngen_sc_u64 u; } v;
  v.u = u;
  return v.f;
}

static inline dyngen_sc_u32 dyngen_sc_bitsf(float x) {
  union { float f; dyngen_sc_u32 u; } v;
  v.f = x;
  return v.u;
}

static inline float dyngen_sc_from_bitsf(dyngen_sc_u32 u) {
  union { float f; dyngen_sc_u32 u; } v;
  v.u = u;
  return v.f;
}

static inline double dyngen_sc_fabs(double x) {
  return dyngen_sc_from_bits(dyngen_sc_bits(x) & ~(1ULL << 63));
}

static inline float dyngen_sc_fabsf(float x) {
  return dyngen_sc_from_bitsf(dyngen_sc_bitsf(x) & 0x7FFFFFFFu);
}

/* 2/pi = sum_j dyngen_sc_two_over_pi[j] 2^(-32(j+1)): its first 1280 bits, written by a
 * throwaway MPFR program at 2000 bits (w = floor(f * 2^32), f -= w, repeated). Doubles use words
 * up to index 36 (x = m 2^e with e <= 971), floats up to index 6. */
static const dyngen_sc_u32 dyngen_sc_two_over_pi[40] = {
    0xA2F9836Eu, 0x4E441529u, 0xFC2757D1u, 0xF534DDC0u, 0xDB629599u, 0x3C439041u, 0xFE5163ABu,
    0xDEBBC561u, 0xB7246E3Au, 0x424DD2E0u, 0x06492EEAu, 0x09D1921Cu, 0xFE1DEB1Cu, 0xB129A73Eu,
    0xE88235F5u, 0x2EBB4484u, 0xE99C7026u, 0xB45F7E41u, 0x3991D639u, 0x835339F4u, 0x9C845F8Bu,
    0xBDF9283Bu, 0x1FF897FFu, 0xDE05980Fu, 0xEF2F118Bu, 0x5A0A6D1Fu, 0x6D367ECFu, 0x27CB09B7u,
    0x4F463F66u, 0x9E5FEA2Du, 0x7527BAC7u, 0xEBE5F17Bu, 0x3D0739F7u, 0x8A5292EAu, 0x6BFB5FB1u,
    0x1F8D5D08u, 0x56033046u, 0xFC7B6BABu, 0xF0CFBC20u, 0x9AF4361Du,
};

/* Bits [pos, pos + 32) of the little-endian 32-bit limbs p (p[pos / 32 + 1] must exist). */
static inline dyngen_sc_u32 dyngen_sc_bits_at(const dyngen_sc_u32* p, int pos) {
  const int limb = pos / 32, shift = pos % 32;
  if (shift == 0) return p[limb];
  return (p[limb] >> shift) | (p[limb + 1] << (32 - shift));
}

/* ==== double ================================================================================ */

/* ---- exact double-double steps. No FMA, so a product's error comes from Veltkamp's split. */

/* s + e = a + b exactly (Knuth's TwoSum, no ordering needed). */
static inline void dyngen_sc_two_sum(double a, double b, double* s, double* e) {
  const double sum = a + b;
  const double bb = sum - a;
  *e = (a - (sum - bb)) + (b - bb);
  *s = sum;
}

/* hi + lo = a with hi holding the top 26 bits (Veltkamp; |a| < 2^995 so nothing overflows). */
static inline void dyngen_sc_split(double a, double* hi, double* lo) {
  const double t = 134217729.0 * a; /* 2^27 + 1 */
  *hi = t - (t - a);
  *lo = a - *hi;
}

/* p + e = a * b exactly (Dekker's TwoProduct). */
static inline void dyngen_sc_two_prod(double a, double b, double* p, double* e) {
  double ah, al, bh, bl;
  dyngen_sc_split(a, &ah, &al);
  dyngen_sc_split(b, &bh, &bl);
  *p = a * b;
  *e = ((ah * bh - *p) + ah * bl + al * bh) + al * bl;
}

/* ---- fast reduction, |x| < 2^21
 *
 * pi/2 = P1 + P2 + P3 + P4 + O(2^-159), P1..P3 with at most 32 significant bits, P4 a double
 * (MPFR, 2000 bits: each part is the remainder rounded to nearest). For |x| < 2^21, n < 2^21, so
 * n*P1, n*P2, n*P3 are exact and x - n*P1 is exact (Sterbenz); the two subtractions after it
 * keep their rounding errors, so rh + rl is r within 2^-134 + 2^-104 |r| (n*P4's rounding, the
 * omitted tail, the sum of the small terms). The smallest |r| of any double with n != 0 is
 * 2^-60.9 (Muller, "Elementary Functions": 6381956970095103 * 2^797; the test finds it again),
 * so r keeps 2^-73 relative accuracy; n = 0 gives r = x. Why 2^21: the products stay exact up
 * to there, and joint angles are far below it. */
static const double dyngen_sc_fast_bound = 0x1p21;
static const double dyngen_sc_two_over_pi_d = 0x1.45f306dc9c883p-1;
static const double dyngen_sc_P1 = 0x1.921fb544p+0;
static const double dyngen_sc_P2 = 0x1.0b4611a6p-34;
static const double dyngen_sc_P3 = 0x1.3198a2ep-69;
static const double dyngen_sc_P4 = 0x1.b839a252049c1p-104;
/* Adding 1.5 * 2^52 rounds a value below 2^51 to an integer, which lands in the low mantissa
 * bits. */
static const double dyngen_sc_round_shift = 0x1.8p52;

/* r = ax - n pi/2 as rh + rl, for 0 <= ax < 2^21; returns n (mod 2^51).
 *
 * The subtractions after t1 are Fast2Sums (s = a + b, e = (a - s) + b), exact here although
 * |a| >= |b| may fail: t1 is a multiple of 2^-52 (or n <= 1, where |t1| > |p2|), so when
 * |t1| < |p2| <= 2^-13, t1 - p2 is a multiple of 2^-65 below 2^-12, representable, and its
 * error is 0; likewise t2 - p3 (|p3| <= 2^-48, multiples of 2^-96). rh + rl is left
 * unnormalised (the kernel only needs |rl| small beside |rh|): |rl| <= 1.5 ulp(rh) when e2 or
 * e3 is nonzero, else |rl| = |n P4| <= 2^-82, below 2^-21 |rh|. */
static inline dyngen_sc_u64 dyngen_sc_reduce_fast(double ax, double* rh, double* rl) {
  const double shifted = ax * dyngen_sc_two_over_pi_d + dyngen_sc_round_shift;
  const double fn = shifted - dyngen_sc_round_shift;
  const double t1 = ax - fn * dyngen_sc_P1;
  const double p2 = fn * dyngen_sc_P2, p3 = fn * dyngen_sc_P3;
  const double t2 = t1 - p2;
  const double e2 = (t1 - t2) - p2;
  *rh = t2 - p3;
  *rl = (e2 - fn * dyngen_sc_P4) + ((t2 - *rh) - p3);
  return dyngen_sc_bits(shifted);
}

/* ---- huge arguments: Payne-Hanek */
static const double dyngen_sc_pio2_hi = 0x1.921fb54442d18p+0; /* pi/2 = hi + lo + O(2^-108) */
static const double dyngen_sc_pio2_lo = 0x1.1a62633145c07p-54;
static const double dyngen_sc_double_max = 0x1.fffffffffffffp+1023;

/* r = ax - n pi/2 as rh + rl for ax >= 2^20 (or inf, NaN); returns n mod 4.
 *
 * ax = m 2^e with m < 2^53. Words j of 2/pi with e - 32(j+1) >= 2 only add multiples of 4 to
 * ax 2/pi, so the product starts at word j0 and takes 7 words: P = m * (224 bits) = ax 2/pi
 * * 2^F, F = 32(j0 + 7) - e in [191, 255], less the words left out, which weigh
 * < 2^(53-F) <= 2^-138. Bits F+1, F of P are n mod 4 and the 160 bits below F the fraction. */
static inline dyngen_sc_u64 dyngen_sc_reduce_huge(double ax, double* rh, double* rl) {
  if (!(ax <= dyngen_sc_double_max)) { /* inf or NaN: both results NaN */
    *rh = ax - ax;
    *rl = 0.0;
    return 0;
  }
  const dyngen_sc_u64 u = dyngen_sc_bits(ax);
  const int e = (int)(u >> 52) - 1075; /* ax >= 2^21 is normal */
  const dyngen_sc_u64 m = (u & ((1ULL << 52) - 1)) | (1ULL << 52);
  const int j0 = e > 2 ? (e - 2) / 32 : 0;

  /* P, little-endian limbs: the low limb of m times the words, then the high limb added in
   * (written out rather than zero-initialised, which some compilers turn into a memset call) */
  dyngen_sc_u32 p[9];
  dyngen_sc_u64 carry = 0;
  for (int k = 0; k < 7; ++k) {
    const dyngen_sc_u64 t = (m & 0xFFFFFFFFu) * dyngen_sc_two_over_pi[j0 + 6 - k] + carry;
    p[k] = (dyngen_sc_u32)t;
    carry = t >> 32;
  }
  p[7] = (dyngen_sc_u32)carry;
  carry = 0;
  for (int k = 0; k < 7; ++k) {
    const dyngen_sc_u64 t = (m >> 32) * dyngen_sc_two_over_pi[j0 + 6 - k] + p[1 + k] + carry;
    p[1 + k] = (dyngen_sc_u32)t;
    carry = t >> 32;
  }
  p[8] = (dyngen_sc_u32)carry;

  const int F = 32 * (j0 + 7) - e;
  dyngen_sc_u64 n = dyngen_sc_bits_at(p, F) & 3;
  dyngen_sc_u32 f[5]; /* the fraction, most significant limb first */
  for (int k = 0; k < 5; ++k) f[k] = dyngen_sc_bits_at(p, F - 32 * (k + 1));
  /* Round to the nearest n: a fraction >= 1/2 becomes fraction - 1, negated to its magnitude. */
  const int negative = (f[0] >> 31) != 0;
  if (negative) {
    n += 1;
    dyngen_sc_u64 borrow = 1; /* two's complement: ~f + 1, from the least significant limb */
    for (int k = 4; k >= 0; --k) {
      const dyngen_sc_u64 t = (dyngen_sc_u64)(~f[k]) + borrow;
      f[k] = (dyngen_sc_u32)t;
      borrow = t >> 32;
    }
  }
  /* fraction = fh + fl (each limb is exact in a double; TwoSum from the smallest up) */
  double fh = 0.0, fl = 0.0, scale = 0x1p-160;
  for (int k = 4; k >= 0; --k, scale *= 0x1p32) {
    double err;
    dyngen_sc_two_sum(fh, (double)f[k] * scale, &fh, &err);
    fl += err;
  }
  dyngen_sc_two_sum(fh, fl, &fh, &fl);
  /* r = fraction * pi/2 */
  double ph, pl;
  dyngen_sc_two_prod(fh, dyngen_sc_pio2_hi, &ph, &pl);
  pl += fh * dyngen_sc_pio2_lo + fl * dyngen_sc_pio2_hi;
  dyngen_sc_two_sum(ph, pl, rh, rl);
  if (negative) {
    *rh = -*rh;
    *rl = -*rl;
  }
  return n & 3;
}

/* ---- polynomials on |r| <= pi/4 + 2^-20, z = r^2
 *
 * sin r = r + r^3 S(z), cos r = 1 - z/2 + z^2 C(z). Coefficients: minimax (Remez exchange, a
 * throwaway MPFR program at 300 bits) of the error relative to sin r, resp. cos r, with the
 * leading coefficient fixed to the double nearest -1/6, resp. 1/24, and the others rounded to
 * double afterwards. Measured in MPFR with these doubles, the polynomials' own relative error is
 * below 2^-61 (sin) and 2^-62.7 (cos), under 0.003 ulp. */
static const double dyngen_sc_S0 = -0x1.5555555555555p-3;
static const double dyngen_sc_S1 = 0x1.1111111111068p-7;
static const double dyngen_sc_S2 = -0x1.a01a019ffe281p-13;
static const double dyngen_sc_S3 = 0x1.71de3a33598bdp-19;
static const double dyngen_sc_S4 = -0x1.ae642bd69331ep-26;
static const double dyngen_sc_S5 = 0x1.6109616b4fb8p-33;
static const double dyngen_sc_S6 = -0x1.9fc9cea5975cbp-41;
static const double dyngen_sc_C0 = 0x1.5555555555555p-5;
static const double dyngen_sc_C1 = -0x1.6c16c16c16289p-10;
static const double dyngen_sc_C2 = 0x1.a01a019e23bdap-16;
static const double dyngen_sc_C3 = -0x1.27e4f8f7626b2p-22;
static const double dyngen_sc_C4 = 0x1.1eea7dad5e23cp-29;
static const double dyngen_sc_C5 = -0x1.8ff3a5d184c24p-37;

static const double dyngen_sc_split_shift = 0x1.8p26; /* x + it - it: x to a multiple of 2^-26 */

/* sin and cos of r = rh + rl, |rh| <= pi/4 + 2^-20, |rl| <= 1.5 ulp(rh) or 2^-21 |rh|.
 *
 * The error that matters is the last addition's: the terms added to rh (sin) and to 1 - r^2/2
 * (cos) are small beside them and carry a few of their own ulps. cos needs 1 - r^2/2 exactly,
 * r^2/2 being up to 0.31 of the result: rh = ah + al with ah a multiple of 2^-26, so ah^2/2 is
 * a multiple of 2^-53 and w = 1 - ah^2/2, in [0.69, 1], is exact; the rest of r^2/2,
 * (ah + al/2) al, is small. rl enters to first order: sin(rh + rl) = sin rh + rl cos rh, with
 * w for cos rh (within 2%, on a term of at most 1.5 ulp: 0.03 ulp), and cos(rh + rl) = cos rh
 * - rh rl. The polynomials end in c0 + z q(z), rounded once, but take q by Estrin's scheme, for
 * a shorter dependency chain than Horner's. */
static inline void dyngen_sc_kernel(double rh, double rl, double* s, double* c) {
  const double z = rh * rh, z2 = z * z, z4 = z2 * z2;
  const double ps =
      dyngen_sc_S0 + z * ((dyngen_sc_S1 + z * dyngen_sc_S2) +
                          z2 * ((dyngen_sc_S3 + z * dyngen_sc_S4) + z2 * (dyngen_sc_S5 + z * dyngen_sc_S6)));
  const double pc = dyngen_sc_C0 + z * ((dyngen_sc_C1 + z * dyngen_sc_C2) +
                                        z2 * (dyngen_sc_C3 + z * dyngen_sc_C4) + z4 * dyngen_sc_C5);
  const double ah = (rh + dyngen_sc_split_shift) - dyngen_sc_split_shift;
  const double al = rh - ah;
  const double w = 1.0 - 0.5 * (ah * ah);
  *s = rh + ((rh * z) * ps + rl * w);
  *c = w + ((z2 * pc - rh * rl) - (ah + 0.5 * al) * al);
}

/* sin x and cos x from sr = sin r, cr = cos r and n, x = n pi/2 + r: sin x is sr, cr, -sr, -cr
 * and cos x is cr, -sr, -cr, sr for n mod 4 = 0..3, and sin is odd. With masks, not branches. */
static inline void dyngen_sc_to_quadrant(double x, dyngen_sc_u64 n, double sr, double cr,
                                         double* s, double* c) {
  const dyngen_sc_u64 sign = 1ULL << 63;
  const dyngen_sc_u64 sb = dyngen_sc_bits(sr), cb = dyngen_sc_bits(cr);
  const dyngen_sc_u64 swap = (sb ^ cb) & (0 - (n & 1)); /* sb ^ swap = cb where n is odd */
  const dyngen_sc_u64 sin_sign = ((n << 62) ^ dyngen_sc_bits(x)) & sign;
  const dyngen_sc_u64 cos_sign = ((n + 1) << 62) & sign;
  *s = dyngen_sc_from_bits(sb ^ swap ^ sin_sign);
  *c = dyngen_sc_from_bits(cb ^ swap ^ cos_sign);
}

/* sincos for |x| >= 2^21, inf and NaN. */
DYNGEN_SC_COLD static void dyngen_sc_sincos_huge(double x, double* s, double* c) {
  double rh, rl, sr, cr;
  const dyngen_sc_u64 n = dyngen_sc_reduce_huge(dyngen_sc_fabs(x), &rh, &rl);
  dyngen_sc_kernel(rh, rl, &sr, &cr);
  dyngen_sc_to_quadrant(x, n, sr, cr, s, c);
}

/* The fast path, right for |x| < 2^21; any other x gives some value, safely. */
static inline void dyngen_sc_sincos_fast(double x, double* s, double* c) {
  double rh, rl, sr, cr;
  const dyngen_sc_u64 n = dyngen_sc_reduce_fast(dyngen_sc_fabs(x), &rh, &rl);
  dyngen_sc_kernel(rh, rl, &sr, &cr);
  dyngen_sc_to_quadrant(x, n, sr, cr, s, c);
}

/* ==== float: the same steps in float arithmetic ============================================= */

/* ---- exact float-float steps */

static inline void dyngen_sc_two_sumf(float a, float b, float* s, float* e) {
  const float sum = a + b;
  const float bb = sum - a;
  *e = (a - (sum - bb)) + (b - bb);
  *s = sum;
}

/* p + e = a * b exactly, for |a|, |b| < 2^115 (Veltkamp's split at 12 bits, Dekker). */
static inline void dyngen_sc_two_prodf(float a, float b, float* p, float* e) {
  const float ta = 4097.0f * a, tb = 4097.0f * b; /* 2^12 + 1 */
  const float ah = ta - (ta - a), bh = tb - (tb - b);
  const float al = a - ah, bl = b - bh;
  *p = a * b;
  *e = ((ah * bh - *p) + ah * bl + al * bh) + al * bl;
}

/* ---- fast reduction, |x| < 2^8
 *
 * pi/2 = PF1 + PF2 + PF3 + PF4 + O(2^-78), PF1..PF3 with at most 16 significant bits, PF4 a
 * float (MPFR, as for double). Below 2^8, n < 2^8: n*PF1..n*PF3 are exact and x - n*PF1 is
 * exact; rh + rl is r within about 2^-70. The smallest |r| of any float with n != 0 is 2^-27.8
 * (at 0x1.f9cbe2p+7, the test finds it again), so r keeps better than 2^-40 relative accuracy.
 * The test checks the reduction against the double one for every float below the bound. Why
 * 2^8: a larger n needs shorter parts, and more of them, for its products to stay exact; joint
 * angles stay far below. */
static const float dyngen_sc_fast_boundf = 0x1p8f;
static const float dyngen_sc_two_over_pif = 0x1.45f306p-1f;
static const float dyngen_sc_PF1 = 0x1.922p+0f;
static const float dyngen_sc_PF2 = -0x1.2aeep-18f;
static const float dyngen_sc_PF3 = -0x1.e974p-35f;
static const float dyngen_sc_PF4 = 0x1.1a6264p-54f;
static const float dyngen_sc_round_shiftf = 0x1.8p23f; /* as for double: n in the low bits */

static inline dyngen_sc_u32 dyngen_sc_reduce_fastf(float ax, float* rh, float* rl) {
  const float shifted = ax * dyngen_sc_two_over_pif + dyngen_sc_round_shiftf;
  const float fn = shifted - dyngen_sc_round_shiftf;
  const float t1 = ax - fn * dyngen_sc_PF1;
  const float p2 = fn * dyngen_sc_PF2, p3 = fn * dyngen_sc_PF3;
  const float t2 = t1 - p2;
  const float e2 = (t1 - t2) - p2;
  *rh = t2 - p3;
  *rl = (e2 - fn * dyngen_sc_PF4) + ((t2 - *rh) - p3);
  return dyngen_sc_bitsf(shifted);
}

/* ---- huge floats: Payne-Hanek, as for double, with a 64-bit fraction */
static const float dyngen_sc_pio2_hif = 0x1.921fb6p+0f; /* pi/2 = hi + lo + O(2^-49) */
static const float dyngen_sc_pio2_lof = -0x1.777a5cp-25f;
static const float dyngen_sc_float_max = 0x1.fffffep+127f;

/* 2^-k for 0 <= k < 127. */
static inline float dyngen_sc_exp2_negf(int k) {
  return dyngen_sc_from_bitsf((dyngen_sc_u32)(127 - k) << 23);
}

/* r = ax - n pi/2 as rh + rl for ax >= 2^8 (or inf, NaN); returns n mod 4.
 *
 * ax = m 2^e with m < 2^24 and e in [-15, 104]. As for double, the product starts at word j0
 * of 2/pi and takes 4 words: P = m * (128 bits), F = 32(j0 + 4) - e in [95, 143] fraction
 * bits, the words left out weighing < 2^(24-F) <= 2^-71. The 64 bits below F are the fraction,
 * within 2^-64; the smallest |r| of a float is 2^-29.2 (the test finds it), so normalised to
 * 48 bits, fh + fl, it keeps 2^-34 relative accuracy, and r = (fh + fl) pi/2 as a float-float. */
static inline dyngen_sc_u32 dyngen_sc_reduce_hugef(float ax, float* rh, float* rl) {
  if (!(ax <= dyngen_sc_float_max)) { /* inf or NaN: both results NaN */
    *rh = ax - ax;
    *rl = 0.0f;
    return 0;
  }
  const dyngen_sc_u32 u = dyngen_sc_bitsf(ax);
  const int e = (int)(u >> 23) - 150; /* ax >= 2^8 is normal */
  const dyngen_sc_u64 m = (u & 0x7FFFFFu) | 0x800000u;
  const int j0 = e > 2 ? (e - 2) / 32 : 0;

  dyngen_sc_u32 p[6]; /* P, little-endian limbs, and one of padding */
  dyngen_sc_u64 carry = 0;
  for (int k = 0; k < 4; ++k) {
    const dyngen_sc_u64 t = m * dyngen_sc_two_over_pi[j0 + 3 - k] + carry;
    p[k] = (dyngen_sc_u32)t;
    carry = t >> 32;
  }
  p[4] = (dyngen_sc_u32)carry;
  p[5] = 0;

  const int F = 32 * (j0 + 4) - e;
  dyngen_sc_u32 n = dyngen_sc_bits_at(p, F) & 3;
  dyngen_sc_u64 f = (dyngen_sc_u64)dyngen_sc_bits_at(p, F - 32) << 32 | dyngen_sc_bits_at(p, F - 64);
  /* Round to the nearest n, as for double. */
  const int negative = (f >> 63) != 0;
  if (negative) {
    n += 1;
    f = 0 - f;
  }
  /* Normalise: the leading one to bit 63 (f != 0: |r| >= 2^-29.2), then 24 bits to fh and the
   * next 24 to fl, each exact in a float. */
  int lz = 0;
  for (int step = 32; step > 0; step /= 2) {
    if (!(f >> (64 - step))) {
      f <<= step;
      lz += step;
    }
  }
  const float fh = (float)(dyngen_sc_u32)(f >> 40) * dyngen_sc_exp2_negf(24 + lz);
  const float fl = (float)(dyngen_sc_u32)((f >> 16) & 0xFFFFFFu) * dyngen_sc_exp2_negf(48 + lz);
  /* r = fraction * pi/2 */
  float ph, pl;
  dyngen_sc_two_prodf(fh, dyngen_sc_pio2_hif, &ph, &pl);
  pl += fh * dyngen_sc_pio2_lof + fl * dyngen_sc_pio2_hif;
  dyngen_sc_two_sumf(ph, pl, rh, rl);
  if (negative) {
    *rh = -*rh;
    *rl = -*rl;
  }
  return n & 3;
}

/* ---- polynomials on |r| <= pi/4 + 2^-13
 *
 * sin r = r + r^3 S(z), cos r = 1 - z/2 + z^2 C(z), three coefficients each: near-minimax
 * (Lawson's iteration of weighted least squares, a throwaway MPFR program at 200 bits) of the
 * error relative to sin r, resp. cos r, rounded to float. Measured in MPFR with these floats:
 * relative error below 2^-26.9 (sin) and 2^-32.4 (cos). */
static const float dyngen_sc_SF0 = -0x1.555546p-3f;
static const float dyngen_sc_SF1 = 0x1.11073cp-7f;
static const float dyngen_sc_SF2 = -0x1.9943f4p-13f;
static const float dyngen_sc_CF0 = 0x1.55554ap-5f;
static const float dyngen_sc_CF1 = -0x1.6c0c34p-10f;
static const float dyngen_sc_CF2 = 0x1.99ebb2p-16f;

/* As the double kernel, but cheaper where float allows: w = 1 - z/2 is rounded, and its rounding
 * error, (1 - w) - z/2 (exact: Fast2Sum, 1 >= z/2), goes back into cos; what remains is z's own
 * rounding, at most 2^-26 in z/2, a quarter of an ulp of cos near r = pi/4 and less below. */
static inline void dyngen_sc_kernelf(float rh, float rl, float* s, float* c) {
  const float z = rh * rh, z2 = z * z;
  const float ps = dyngen_sc_SF0 + z * (dyngen_sc_SF1 + z * dyngen_sc_SF2);
  const float pc = dyngen_sc_CF0 + z * (dyngen_sc_CF1 + z * dyngen_sc_CF2);
  const float hz = 0.5f * z;
  const float w = 1.0f - hz;
  *s = rh + ((rh * z) * ps + rl * w);
  *c = w + ((z2 * pc - rh * rl) + ((1.0f - w) - hz));
}

static inline void dyngen_sc_to_quadrantf(float x, dyngen_sc_u32 n, float sr, float cr, float* s,
                                          float* c) {
  const dyngen_sc_u32 sign = 0x80000000u;
  const dyngen_sc_u32 sb = dyngen_sc_bitsf(sr), cb = dyngen_sc_bitsf(cr);
  const dyngen_sc_u32 swap = (sb ^ cb) & (0u - (n & 1u));
  const dyngen_sc_u32 sin_sign = ((n << 30) ^ dyngen_sc_bitsf(x)) & sign;
  const dyngen_sc_u32 cos_sign = ((n + 1u) << 30) & sign;
  *s = dyngen_sc_from_bitsf(sb ^ swap ^ sin_sign);
  *c = dyngen_sc_from_bitsf(cb ^ swap ^ cos_sign);
}

DYNGEN_SC_COLD static void dyngen_sc_sincosf_huge(float x, float* s, float* c) {
  float rh, rl, sr, cr;
  const dyngen_sc_u32 n = dyngen_sc_reduce_hugef(dyngen_sc_fabsf(x), &rh, &rl);
  dyngen_sc_kernelf(rh, rl, &sr, &cr);
  dyngen_sc_to_quadrantf(x, n, sr, cr, s, c);
}

static inline void dyngen_sc_sincosf_fast(float x, float* s, float* c) {
  float rh, rl, sr, cr;
  const dyngen_sc_u32 n = dyngen_sc_reduce_fastf(dyngen_sc_fabsf(x), &rh, &rl);
  dyngen_sc_kernelf(rh, rl, &sr, &cr);
  dyngen_sc_to_quadrantf(x, n, sr, cr, s, c);
}

/* ==== the functions ========================================================================= */

#ifdef __FAST_MATH__
/* -ffast-math lets the compiler reassociate the exact steps above (two_sum, the rounding shift)
 * into nonsense; the C library's sin and cos, compiled apart, keep their accuracy (and need
 * libm). Bit equality with a runtime built without fast-math is lost either way. */
static inline void dyngen_sincos(double x, double* s, double* c) {
  *s = __builtin_sin(x);
  *c = __builtin_cos(x);
}
static inline void dyngen_sincosf(float x, float* s, float* c) {
  *s = __builtin_sinf(x);
  *c = __builtin_cosf(x);
}
static inline void dyngen_sincos_array(const double* x, double* s, double* c, int n) {
  for (int k = 0; k < n; ++k) dyngen_sincos(x[k], &s[k], &c[k]);
}
static inline void dyngen_sincosf_array(const float* x, float* s, float* c, int n) {
  for (int k = 0; k < n; ++k) dyngen_sincosf(x[k], &s[k], &c[k]);
}
#else
/* *s = sin(x), *c = cos(x), within 1 ulp for every double x (see the top of this file). */
static inline void dyngen_sincos(double x, double* s, double* c) {
  if (!(dyngen_sc_fabs(x) < dyngen_sc_fast_bound))
    dyngen_sc_sincos_huge(x, s, c);
  else
    dyngen_sc_sincos_fast(x, s, c);
}

/* *s = sin(x), *c = cos(x) for a float, in float arithmetic, within 1 ulp. */
static inline void dyngen_sincosf(float x, float* s, float* c) {
  if (!(dyngen_sc_fabsf(x) < dyngen_sc_fast_boundf))
    dyngen_sc_sincosf_huge(x, s, c);
  else
    dyngen_sc_sincosf_fast(x, s, c);
}

/* s[k] = sin(x[k]), c[k] = cos(x[k]) for k < n: the same bits as n calls of the above, in about
 * half their time where the compiler vectorises the first loop (GCC does at -O3), which also
 * notes whether any argument is large or not finite (its magnitude's bits at or above the
 * bound's: NaN's are above infinity's); only then does the second loop redo those. The note
 * compares the high 32 bits alone (the bound's low word is 0): SSE2 has no 64-bit integer
 * comparison, and GCC does not vectorise the loop with one. */
static inline void dyngen_sincos_array(const double* x, double* s, double* c, int n) {
  dyngen_sc_u32 large = 0;
  for (int k = 0; k < n; ++k) {
    dyngen_sc_sincos_fast(x[k], &s[k], &c[k]);
    large |= ((dyngen_sc_u32)(dyngen_sc_bits(x[k]) >> 32) & 0x7FFFFFFFu) >= 0x41400000u; /* 2^21 */
  }
  if (large)
    for (int k = 0; k < n; ++k)
      if (!(dyngen_sc_fabs(x[k]) < dyngen_sc_fast_bound))
        dyngen_sc_sincos_huge(x[k], &s[k], &c[k]);
}

static inline void dyngen_sincosf_array(const float* x, float* s, float* c, int n) {
  dyngen_sc_u32 large = 0;
  for (int k = 0; k < n; ++k) {
    dyngen_sc_sincosf_fast(x[k], &s[k], &c[k]);
    large |= (dyngen_sc_bitsf(x[k]) & 0x7FFFFFFFu) >= 0x43800000u; /* 2^8 */
  }
  if (large)
    for (int k = 0; k < n; ++k)
      if (!(dyngen_sc_fabsf(x[k]) < dyngen_sc_fast_boundf))
        dyngen_sc_sincosf_huge(x[k], &s[k], &c[k]);
}
#endif

#endif /* DYNGEN_SINCOS_H */
