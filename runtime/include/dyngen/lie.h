/* dyngen_lie: the scalar coefficients of the exponential and logarithm of rotations that
 * integrate, difference and their Jacobians need, for double and for float (computed in float).
 * Each is an even function of the angle t, so it takes t^2 (a sum of squares the caller has) and
 * has no branch in its callers: where the closed form loses digits to cancellation or is 0/0 it
 * switches to its Taylor series in t^2, whose terms below the cut-off are smaller than an ulp.
 *
 * The runtime calls these through dyngen/lie.hpp and the generated code calls the same file
 * (dyngen copies it verbatim into a package that needs it as dyngen_lie.h), so both give the same
 * bits. Include dyngen_sincos.h (dyngen/sincos.h) first: sin and cos are dyngen_sincos's. The
 * square root and atan2 are the C library's: sqrt is correctly rounded wherever IEEE-754 holds,
 * atan2 (only in the logarithm's coefficient) is as exact as the library makes it.
 *
 * Series coefficients: exact rationals (Bernoulli numbers for the logarithm's) rounded to
 * double by Python's fractions module. tests/runtime/lie_test.cpp measures each function against
 * 256-bit MPFR.
 */
#ifndef DYNGEN_LIE_H
#define DYNGEN_LIE_H

#if defined(__GNUC__)
#define DYNGEN_LIE_SQRT __builtin_sqrt
#define DYNGEN_LIE_SQRTF __builtin_sqrtf
#define DYNGEN_LIE_ATAN2 __builtin_atan2
#define DYNGEN_LIE_ATAN2F __builtin_atan2f
#else
#include <math.h>
#define DYNGEN_LIE_SQRT sqrt
#define DYNGEN_LIE_SQRTF sqrtf
#define DYNGEN_LIE_ATAN2 atan2
#define DYNGEN_LIE_ATAN2F atan2f
#endif

/* sum_k c[k] x^k, k < n, by Horner's rule */
static inline double dyngen_lie_series(const double* c, int n, double x) {
  double y = c[n - 1];
  int k;
  for (k = n - 2; k >= 0; --k) y = c[k] + x * y;
  return y;
}

static inline float dyngen_lie_seriesf(const float* c, int n, float x) {
  float y = c[n - 1];
  int k;
  for (k = n - 2; k >= 0; --k) y = c[k] + x * y;
  return y;
}

/* sin(t/2)/t = sum (-1)^k t^2k / ((2k+1)! 2^(2k+1)) */
static const double dyngen_lie_half_sinc_series[12] = {
    0.5, -0.020833333333333332, 0.00026041666666666666, -1.5500992063492063e-06,
    5.382288910934745e-09, -1.2232474797578965e-11, 1.9603324996120133e-14,
    -2.333729166204778e-17, 2.1449716601146855e-20, -1.5679617398499164e-23,
    9.333105594344741e-27, -4.6112181790240814e-30};
static const float dyngen_lie_half_sinc_seriesf[12] = {
    0.5f, -0.020833333333333332f, 0.00026041666666666666f, -1.5500992063492063e-06f,
    5.382288910934745e-09f, -1.2232474797578965e-11f, 1.9603324996120133e-14f,
    -2.333729166204778e-17f, 2.1449716601146855e-20f, -1.5679617398499164e-23f,
    9.333105594344741e-27f, -4.6112181790240814e-30f};
/* (t - sin t)/t^3 = sum (-1)^k t^2k / (2k+3)! */
static const double dyngen_lie_exp_c_series[12] = {
    0.16666666666666666, -0.008333333333333333, 0.0001984126984126984,
    -2.7557319223985893e-06, 2.505210838544172e-08, -1.6059043836821613e-10,
    7.647163731819816e-13, -2.8114572543455206e-15, 8.22063524662433e-18,
    -1.9572941063391263e-20, 3.868170170630684e-23, -6.446950284384474e-26};
static const float dyngen_lie_exp_c_seriesf[12] = {
    0.16666666666666666f, -0.008333333333333333f, 0.0001984126984126984f,
    -2.7557319223985893e-06f, 2.505210838544172e-08f, -1.6059043836821613e-10f,
    7.647163731819816e-13f, -2.8114572543455206e-15f, 8.22063524662433e-18f,
    -1.9572941063391263e-20f, 3.868170170630684e-23f, -6.446950284384474e-26f};
/* (t^2 + 2 cos t - 2)/(2 t^4) = sum (-1)^k t^2k / (2k+4)! */
static const double dyngen_lie_exp_d_series[12] = {
    0.041666666666666664, -0.001388888888888889, 2.48015873015873e-05,
    -2.755731922398589e-07, 2.08767569878681e-09, -1.1470745597729725e-11,
    4.779477332387385e-14, -1.5619206968586225e-16, 4.110317623312165e-19,
    -8.896791392450574e-22, 1.6117375710961184e-24, -2.4795962632247976e-27};
static const float dyngen_lie_exp_d_seriesf[12] = {
    0.041666666666666664f, -0.001388888888888889f, 2.48015873015873e-05f,
    -2.755731922398589e-07f, 2.08767569878681e-09f, -1.1470745597729725e-11f,
    4.779477332387385e-14f, -1.5619206968586225e-16f, 4.110317623312165e-19f,
    -8.896791392450574e-22f, 1.6117375710961184e-24f, -2.4795962632247976e-27f};
/* (2t - 3 sin t + t cos t)/(2 t^5) = sum (-1)^k (k+1) t^2k / (2k+5)! */
static const double dyngen_lie_exp_e_series[12] = {
    0.008333333333333333, -0.0003968253968253968, 8.267195767195768e-06,
    -1.0020843354176688e-07, 8.029521918410807e-10, -4.58829823909189e-12,
    1.9680200780418645e-14, -6.576508197299464e-17, 1.7615646957052136e-19,
    -3.868170170630684e-22, 7.091645312822921e-25, -1.1020427836554655e-27};
static const float dyngen_lie_exp_e_seriesf[12] = {
    0.008333333333333333f, -0.0003968253968253968f, 8.267195767195768e-06f,
    -1.0020843354176688e-07f, 8.029521918410807e-10f, -4.58829823909189e-12f,
    1.9680200780418645e-14f, -6.576508197299464e-17f, 1.7615646957052136e-19f,
    -3.868170170630684e-22f, 7.091645312822921e-25f, -1.1020427836554655e-27f};
/* (1 - (t/2) cot(t/2))/t^2 = sum (-1)^(n+1) B_2n t^(2n-2) / (2n)!, n >= 1 */
static const double dyngen_lie_log_alpha_series[20] = {
    0.08333333333333333, 0.001388888888888889, 3.306878306878307e-05,
    8.267195767195768e-07, 2.08767569878681e-08, 5.284190138687493e-10,
    1.3382536530684679e-11, 3.3896802963225827e-13, 8.586062056277845e-15,
    2.174868698558062e-16, 5.5090028283602295e-18, 1.3954464685812522e-19,
    3.534707039629467e-21, 8.953517427037546e-23, 2.267952452337683e-24,
    5.744790668872202e-26, 1.455172475614865e-27, 3.6859949406653103e-29,
    9.336734257095045e-31, 2.36502241570063e-32};
static const float dyngen_lie_log_alpha_seriesf[20] = {
    0.08333333333333333f, 0.001388888888888889f, 3.306878306878307e-05f,
    8.267195767195768e-07f, 2.08767569878681e-08f, 5.284190138687493e-10f,
    1.3382536530684679e-11f, 3.3896802963225827e-13f, 8.586062056277845e-15f,
    2.174868698558062e-16f, 5.5090028283602295e-18f, 1.3954464685812522e-19f,
    3.534707039629467e-21f, 8.953517427037546e-23f, 2.267952452337683e-24f,
    5.744790668872202e-26f, 1.455172475614865e-27f, 3.6859949406653103e-29f,
    9.336734257095045e-31f, 2.36502241570063e-32f};

/* cos(t/2) */
static inline double dyngen_half_cos(double t2) {
  double s, c;
  dyngen_sincos(0.5 * DYNGEN_LIE_SQRT(t2), &s, &c);
  return c;
}

static inline float dyngen_half_cosf(float t2) {
  float s, c;
  dyngen_sincosf(0.5f * DYNGEN_LIE_SQRTF(t2), &s, &c);
  return c;
}

/* sin(t/2)/t: the quaternion of exp(w) is (cos(t/2), sin(t/2)/t w) */
static inline double dyngen_half_sinc(double t2) {
  double t, s, c;
  if (t2 <= 1.0) return dyngen_lie_series(dyngen_lie_half_sinc_series, 12, t2);
  t = DYNGEN_LIE_SQRT(t2);
  dyngen_sincos(0.5 * t, &s, &c);
  return s / t;
}

static inline float dyngen_half_sincf(float t2) {
  float t, s, c;
  if (t2 <= 1.0f) return dyngen_lie_seriesf(dyngen_lie_half_sinc_seriesf, 12, t2);
  t = DYNGEN_LIE_SQRTF(t2);
  dyngen_sincosf(0.5f * t, &s, &c);
  return s / t;
}

/* (t - sin t)/t^3: of [w]^2 in the SE(3) exponential's V and in the right Jacobian of exp */
static inline double dyngen_exp_c(double t2) {
  double t, s, c;
  if (t2 <= 4.0) return dyngen_lie_series(dyngen_lie_exp_c_series, 12, t2);
  t = DYNGEN_LIE_SQRT(t2);
  dyngen_sincos(t, &s, &c);
  return (t - s) / (t2 * t);
}

static inline float dyngen_exp_cf(float t2) {
  float t, s, c;
  if (t2 <= 4.0f) return dyngen_lie_seriesf(dyngen_lie_exp_c_seriesf, 12, t2);
  t = DYNGEN_LIE_SQRTF(t2);
  dyngen_sincosf(t, &s, &c);
  return (t - s) / (t2 * t);
}

/* (t^2 + 2 cos t - 2)/(2 t^4): of the SE(3) Jacobian's coupling block */
static inline double dyngen_exp_d(double t2) {
  double t, s, c;
  if (t2 <= 4.0) return dyngen_lie_series(dyngen_lie_exp_d_series, 12, t2);
  t = DYNGEN_LIE_SQRT(t2);
  dyngen_sincos(t, &s, &c);
  return (t2 + 2.0 * c - 2.0) / (2.0 * t2 * t2);
}

static inline float dyngen_exp_df(float t2) {
  float t, s, c;
  if (t2 <= 4.0f) return dyngen_lie_seriesf(dyngen_lie_exp_d_seriesf, 12, t2);
  t = DYNGEN_LIE_SQRTF(t2);
  dyngen_sincosf(t, &s, &c);
  return (t2 + 2.0f * c - 2.0f) / (2.0f * t2 * t2);
}

/* (2t - 3 sin t + t cos t)/(2 t^5): of the SE(3) Jacobian's coupling block */
static inline double dyngen_exp_e(double t2) {
  double t, s, c;
  if (t2 <= 4.0) return dyngen_lie_series(dyngen_lie_exp_e_series, 12, t2);
  t = DYNGEN_LIE_SQRT(t2);
  dyngen_sincos(t, &s, &c);
  return (2.0 * t - 3.0 * s + t * c) / (2.0 * t2 * t2 * t);
}

static inline float dyngen_exp_ef(float t2) {
  float t, s, c;
  if (t2 <= 4.0f) return dyngen_lie_seriesf(dyngen_lie_exp_e_seriesf, 12, t2);
  t = DYNGEN_LIE_SQRTF(t2);
  dyngen_sincosf(t, &s, &c);
  return (2.0f * t - 3.0f * s + t * c) / (2.0f * t2 * t2 * t);
}

/* (1 - (t/2) cot(t/2))/t^2 = 1/t^2 - cos(t/2)/(2 t sin(t/2)): of [w]^2 in V^-1 and in the
 * right Jacobian of log; t < 2 pi */
static inline double dyngen_log_alpha(double t2) {
  double t, s, c;
  if (t2 <= 4.0) return dyngen_lie_series(dyngen_lie_log_alpha_series, 20, t2);
  t = DYNGEN_LIE_SQRT(t2);
  dyngen_sincos(0.5 * t, &s, &c);
  return 1.0 / t2 - c / (2.0 * t * s);
}

static inline float dyngen_log_alphaf(float t2) {
  float t, s, c;
  if (t2 <= 4.0f) return dyngen_lie_seriesf(dyngen_lie_log_alpha_seriesf, 20, t2);
  t = DYNGEN_LIE_SQRTF(t2);
  dyngen_sincosf(0.5f * t, &s, &c);
  return 1.0f / t2 - c / (2.0f * t * s);
}

/* The factor k with log(quaternion (c, u)) = k u, |u|^2 = s2, the shorter way round:
 * 2 atan2(|u|, |c|) / |u|, negated for c < 0 (2/|c| at u = 0) */
static inline double dyngen_log_factor(double s2, double c) {
  const double s = DYNGEN_LIE_SQRT(s2), a = c < 0.0 ? -c : c;
  const double k = s2 > 0.0 ? 2.0 * DYNGEN_LIE_ATAN2(s, a) / s : 2.0 / a;
  return c < 0.0 ? -k : k;
}

static inline float dyngen_log_factorf(float s2, float c) {
  const float s = DYNGEN_LIE_SQRTF(s2), a = c < 0.0f ? -c : c;
  const float k = s2 > 0.0f ? 2.0f * DYNGEN_LIE_ATAN2F(s, a) / s : 2.0f / a;
  return c < 0.0f ? -k : k;
}

#endif /* DYNGEN_LIE_H */
