// NAME_eigen.hpp (issue 46) on ur5 with every function: its matrices read as the functions mean
// them, checked against what does not come from the layout: central differences of rnea for
// d tau / dq and of the frame placements for the frame Jacobians, indexed through Eigen; its
// map() against the plain arrays' documented indexing; and a column-major matrix, fixed or
// dynamic, refused at compile time where an output is row-major.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <random>

#include "ur5_all_eigen.hpp"

namespace {

namespace pkg = ur5_all;
using VectorQ = pkg::eigen::Matrix<pkg::nq, 1>;
using MatrixVV = pkg::eigen::Matrix<pkg::nv, pkg::nv>;

template <class M>
constexpr bool crba_takes = requires(const VectorQ& q, M& m) { pkg::crba(q, m); };
static_assert(crba_takes<MatrixVV>);
static_assert(!crba_takes<Eigen::Matrix<double, pkg::nv, pkg::nv>>, "column-major, fixed size");
static_assert(!crba_takes<Eigen::MatrixXd>, "column-major, dynamic size");
static_assert(sizeof(pkg::eigen::PerFrame<6, pkg::nv, pkg::nframes>) ==
              sizeof(double) * 6 * pkg::nv * pkg::nframes);

VectorQ random_q(std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(-3, 3);
  VectorQ q;
  for (int i = 0; i < pkg::nq; ++i) q(i) = angle(rng);
  return q;
}

constexpr double h = 1e-6, tolerance = 1e-6;  // central differences: error O(h^2) + rounding / h

TEST(Eigen, DerivativeColumnsAreTheJointsDirections) {
  std::mt19937 rng(46);
  for (int k = 0; k < 10; ++k) {
    const VectorQ q = random_q(rng);
    const pkg::eigen::Matrix<pkg::nv, 1> v = random_q(rng), a = random_q(rng);
    MatrixVV dtau_dq, dtau_dv;
    pkg::rnea_derivatives(q, v, a, dtau_dq, dtau_dv);
    for (int j = 0; j < pkg::nv; ++j) {
      VectorQ plus = q, minus = q;
      plus(j) += h;
      minus(j) -= h;
      pkg::eigen::Matrix<pkg::nv, 1> tau_plus, tau_minus;
      pkg::rnea(plus, v, a, tau_plus);
      pkg::rnea(minus, v, a, tau_minus);
      const pkg::eigen::Matrix<pkg::nv, 1> column = (tau_plus - tau_minus) / (2 * h);
      for (int i = 0; i < pkg::nv; ++i)
        EXPECT_NEAR(dtau_dq(i, j), column(i), tolerance * (1 + std::abs(column(i))))
            << "d tau_" << i << " / dq_" << j;
    }
  }
}

TEST(Eigen, FrameJacobiansMoveTheFramesOrigins) {
  std::mt19937 rng(47);
  for (int k = 0; k < 10; ++k) {
    const VectorQ q = random_q(rng);
    pkg::eigen::PerFrame<6, pkg::nv, pkg::nframes> J;
    pkg::frame_jacobians(q, J);
    for (int j = 0; j < pkg::nv; ++j) {
      VectorQ plus = q, minus = q;
      plus(j) += h;
      minus(j) -= h;
      pkg::eigen::PerFrame<3, 3, pkg::nframes> R_plus, R_minus;
      pkg::eigen::PerFrame<3, 1, pkg::nframes> p_plus, p_minus;
      pkg::frame_placements(plus, R_plus, p_plus);
      pkg::frame_placements(minus, R_minus, p_minus);
      for (int f = 0; f < pkg::nframes; ++f)
        for (int i = 0; i < 3; ++i) {  // linear rows first: the origin's velocity
          const double dp = (p_plus[f](i) - p_minus[f](i)) / (2 * h);
          EXPECT_NEAR(J[f](i, j), dp, tolerance * (1 + std::abs(dp)))
              << pkg::frame_names[f] << " row " << i << ", joint " << j;
        }
    }
  }
}

TEST(Eigen, MapReadsThePlainArraysAsDocumented) {
  std::mt19937 rng(48);
  const VectorQ q = random_q(rng);
  double M[pkg::nv * pkg::nv];
  pkg::crba(q.data(), M);
  MatrixVV M_eigen;
  pkg::crba(q, M_eigen);
  const auto view = pkg::eigen::map<pkg::nv, pkg::nv>(M);
  const Eigen::MatrixXd copy = M_eigen;  // column-major, and the same matrix, not its transpose
  for (int i = 0; i < pkg::nv; ++i)
    for (int j = 0; j < pkg::nv; ++j) {
      EXPECT_EQ(view(i, j), M[i * pkg::nv + j]);
      EXPECT_EQ(M_eigen(i, j), M[i * pkg::nv + j]);
      EXPECT_EQ(copy(i, j), M[i * pkg::nv + j]);
    }
}

}  // namespace
