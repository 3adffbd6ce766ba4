// The kernels' versions for double and float written with vector types compute the bits of the
// generic loops: the generic template runs on Plain<T>, a scalar with T's arithmetic that no
// vector version matches.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "dyngen/kernels.hpp"

namespace {

template <class T>
struct Plain {
  T x{};
  Plain() = default;
  explicit Plain(int v) : x(static_cast<T>(v)) {}
  explicit Plain(T v) : x(v) {}
};
template <class T> Plain<T> operator+(Plain<T> a, Plain<T> b) { return Plain<T>(a.x + b.x); }
template <class T> Plain<T> operator*(Plain<T> a, Plain<T> b) { return Plain<T>(a.x * b.x); }
template <class T> Plain<T> operator-(Plain<T> a) { return Plain<T>(-a.x); }

template <class T>
bool same_bits(T a, T b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

/// Random entries over twelve orders of magnitude, so that sums round.
template <class T>
std::vector<T> random_entries(std::size_t count, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-6, 6);
  std::vector<T> x(count);
  for (T& e : x) e = static_cast<T>(std::ldexp(mantissa(rng), 2 * exponent(rng)));
  return x;
}

template <class T>
void expect_products_agree() {
  std::mt19937_64 rng(7);
  // every block width (1 to 24, in vectors and scalars), more than one block, and columns
  // with few and many non-zero rows
  std::vector<int> sizes;
  for (int n = 1; n <= 26; ++n) sizes.push_back(n);
  for (const int n : {31, 36, 48, 49, 50}) sizes.push_back(n);
  for (const int n : sizes) {
    std::vector<int> rows_begin{0}, rows;
    for (int c = 0; c < n; ++c) {
      for (int k = 0; k < n; ++k)
        if (rng() % 3 != 0) rows.push_back(k);
      rows_begin.push_back(static_cast<int>(rows.size()));
    }
    const std::vector<T> A = random_entries<T>(static_cast<std::size_t>(n * n), rng);
    const std::vector<T> B = random_entries<T>(static_cast<std::size_t>(n * n), rng);
    std::vector<T> C(A.size());
    dyngen::kernels::neg_product(n, rows_begin.data(), rows.data(), A.data(), B.data(), C.data());
    std::vector<Plain<T>> a, b, c(A.size());
    for (std::size_t e = 0; e < A.size(); ++e) a.emplace_back(A[e]), b.emplace_back(B[e]);
    dyngen::kernels::neg_product(n, rows_begin.data(), rows.data(), a.data(), b.data(), c.data());
    for (std::size_t e = 0; e < C.size(); ++e)
      ASSERT_TRUE(same_bits(C[e], c[e].x)) << "n " << n << ", entry " << e << ": " << C[e]
                                            << " against " << c[e].x;
  }
}

TEST(Kernels, VectorProductIsTheGenericProductDouble) { expect_products_agree<double>(); }
TEST(Kernels, VectorProductIsTheGenericProductFloat) { expect_products_agree<float>(); }

TEST(Kernels, VectorInnerProductIsTheGenericOne) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 100000; ++trial) {
    const std::vector<double> f = random_entries<double>(6, rng), m = random_entries<double>(6, rng);
    Plain<double> pf[6], pm[6];
    for (int k = 0; k < 6; ++k) pf[k] = Plain<double>(f[k]), pm[k] = Plain<double>(m[k]);
    const double x = dyngen::kernels::inner6(f.data(), m.data());
    const double y = dyngen::kernels::inner6(pf, pm).x;
    ASSERT_TRUE(same_bits(x, y)) << x << " against " << y;
  }
}

}  // namespace
