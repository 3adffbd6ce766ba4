// Contact dynamics and impulses (constrained.hpp) on the shared robots, with contacts made by the
// generator's loader, and loop closures on random chains. Checked against references that do not
// use constrained.hpp: J and Jdot v of frames.hpp's frame_jacobians and frame_bias_accelerations
// at the constraints' frames (a loop's position error from frame_placements), RNEA, CRBA and ABA.
// The defining equations (dynamics and constraint rows, Baumgarte's kd and kp); the dense KKT
// system solved in MPFR on the runtime instantiated with mpreal; Gauss's principle of least
// constraint; the impulse law and its loss of kinetic energy; four feet in 6d (more rows than
// degrees of freedom) against the minimum-norm multipliers in long double; and
// contact_dynamics_derivatives against central differences in MPFR.
#include "dyngen/constrained.hpp"

#include <gtest/gtest.h>
#include <mpreal.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <span>
#include <string>
#include <unsupported/Eigen/MPRealSupport>
#include <vector>

#include "dyngen/dyngen.hpp"
#include "dyngen/numerics/reference.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

template <class S>
using VectorX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
template <class S>
using MatrixX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
using Vector = VectorX<double>;
using Matrix = MatrixX<double>;
using Exact = numerics::Exact;

constexpr int states_per_case = 4;
constexpr double eps = std::numeric_limits<double>::epsilon();

template <class S>
std::span<const S> span(const VectorX<S>& x) {
  return {x.data(), static_cast<std::size_t>(x.size())};
}
template <class S>
std::span<S> span(VectorX<S>& x) {
  return {x.data(), static_cast<std::size_t>(x.size())};
}

/// A robot file and the contacts the loader makes on it.
struct ContactCase {
  std::string name;
  std::string file;
  bool floating_base;
  std::vector<std::string> contacts;
};

std::ostream& operator<<(std::ostream& os, const ContactCase& c) { return os << c.name; }

Model<double> load(const ContactCase& c, const ConstraintSettings<double>& settings = {}) {
  gen::LoadOptions o;
  o.floating_base = c.floating_base;
  o.contacts = c.contacts;
  o.constraint_settings = settings;
  return gen::load_robot(test::model_path(c.file), o).model;
}

/// A random state: q uniform then its quaternions normalised, v in [-1, 1], tau in [-10, 10].
struct Sample {
  Vector q, v, tau;
};

std::vector<Sample> random_samples(const Model<double>& model, std::uint64_t seed,
                                   int n = states_per_case) {
  test::Random rng(seed);
  std::vector<Sample> samples;
  for (int k = 0; k < n; ++k) {
    Sample s{Vector(model.nq), Vector(model.nv), Vector(model.nv)};
    for (double& x : s.q) x = rng.uniform(-3, 3);
    normalize_configuration<double>(model, span(s.q));
    for (double& x : s.v) x = rng.uniform(-1, 1);
    for (double& x : s.tau) x = rng.uniform(-10, 10);
    samples.push_back(s);
  }
  return samples;
}

/// The terms of the constrained equations at (q, v), from frames.hpp, CRBA and RNEA rather than
/// constrained.hpp: M, h, and per constraint J_A - J_B and its Jdot v (frame B of a contact is
/// the world: zero rows), keeping the first 3 or 6 rows of each frame's 6; and a loop's position
/// error e, p_A - p_B then 1/2 vee(R_A R_B^T - R_B R_A^T) (a contact has none).
template <class S>
struct Terms {
  MatrixX<S> M, J;
  VectorX<S> h, gamma, e;
};

template <class S>
Terms<S> constraint_terms(const Model<S>& model, const VectorX<S>& q, const VectorX<S>& v) {
  Model<S> fm = model;
  fm.frames.clear();
  for (const Constraint<S>& c : model.constraints) {
    fm.frames.push_back({c.name + "/A", c.body_a, c.placement_a});
    fm.frames.push_back({c.name + "/B", c.body_b, c.placement_b});
  }
  Workspace<S> ws(fm);
  const int nv = model.nv, nf = static_cast<int>(fm.frames.size());
  std::vector<S> Jf(6 * static_cast<std::size_t>(nf) * nv), bias(6 * nf),
      M(static_cast<std::size_t>(nv) * nv), R(9 * nf), p(3 * nf);
  VectorX<S> h(nv);
  frame_jacobians<S>(fm, ws, span(q), JacobianAxes::World, Jf);
  frame_bias_accelerations<S>(fm, ws, span(q), span(v), JacobianAxes::World, bias);
  crba<S>(fm, ws, span(q), M);
  nle<S>(fm, ws, span(q), span(v), span(h));
  frame_placements<S>(fm, ws, span(q), R, p);
  Terms<S> t{test::to_eigen(M, nv), MatrixX<S>::Zero(model.nc, nv), h, VectorX<S>::Zero(model.nc),
             VectorX<S>::Zero(model.nc)};
  int row = 0;
  for (std::size_t k = 0; k < model.constraints.size(); ++k) {
    const std::size_t a = 2 * k, b = 2 * k + 1;
    using Rotation = Eigen::Matrix<S, 3, 3, Eigen::RowMajor>;
    const Rotation RA = Eigen::Map<const Rotation>(&R[9 * a]),
                   RB = Eigen::Map<const Rotation>(&R[9 * b]);
    const Rotation W = RA * RB.transpose() - RB * RA.transpose();
    const S e[6] = {p[3 * a] - p[3 * b],
                    p[3 * a + 1] - p[3 * b + 1],
                    p[3 * a + 2] - p[3 * b + 2],
                    W(2, 1) / S(2),
                    W(0, 2) / S(2),
                    W(1, 0) / S(2)};
    const bool loop = model.constraints[k].loop;
    for (int r = 0; r < constraint_rows(model.constraints[k]); ++r, ++row) {
      for (int c = 0; c < nv; ++c)
        t.J(row, c) = Jf[(6 * a + r) * nv + c] - Jf[(6 * b + r) * nv + c];
      t.gamma(row) = bias[6 * a + r] - bias[6 * b + r];
      if (loop) t.e(row) = e[r];
    }
  }
  return t;
}

/// contact_dynamics' qdd and lam.
struct Solution {
  Vector qdd, lam;
};

Solution contact_solution(const Model<double>& model, const Sample& s) {
  Workspace<double> ws(model);
  Solution x{Vector(model.nv), Vector(model.nc)};
  contact_dynamics<double>(model, ws, span(s.q), span(s.v), span(s.tau), span(x.qdd), span(x.lam));
  return x;
}

Vector rnea_of(const Model<double>& model, const Vector& q, const Vector& v, const Vector& qdd) {
  Workspace<double> ws(model);
  Vector tau(model.nv);
  rnea<double>(model, ws, span(q), span(v), span(qdd), span(tau));
  return tau;
}

/// ||RNEA(q, v, qdd) - tau - J^T lam||, relative to the terms' norms.
double dynamics_residual(const Model<double>& model, const Sample& s, const Terms<double>& t,
                         const Solution& x) {
  const Vector id = rnea_of(model, s.q, s.v, x.qdd), force = t.J.transpose() * x.lam;
  return (id - s.tau - force).norm() / (s.tau.norm() + force.norm() + id.norm());
}

/// ||J qdd + Jdot v + kd J v + kp e||, relative to the terms' norms.
double constraint_residual(const Terms<double>& t, const Vector& v, const Vector& qdd,
                           double kd = 0, double kp = 0) {
  const Vector Jv = t.J * v;
  return (t.J * qdd + t.gamma + kd * Jv + kp * t.e).norm() /
         (t.J.norm() * qdd.norm() + t.gamma.norm() + kd * Jv.norm() + kp * t.e.norm());
}

const std::vector<ContactCase>& contact_cases() {
  static const std::vector<ContactCase> cases = {
      {"solo12_point_feet", "solo12.urdf", true, {"FL_FOOT", "FR_FOOT:3d", "HL_FOOT", "HR_FOOT"}},
      {"solo12_two_feet_6d", "solo12.urdf", true, {"FL_FOOT:6d", "HR_FOOT:6d"}},
      {"ur5_tool_3d", "ur5.urdf", false, {"tool0:3d"}},
      {"atlas_feet_6d", "atlas.urdf", true, {"l_foot:6d", "r_foot:6d"}},
      // 6 rows on 7 joints: one degree of freedom left, the elbow's self-motion
      {"iiwa14_flange_6d", "iiwa14.urdf", false, {"iiwa_link_ee:6d"}},
      // panda_finger_joint2 mimics joint1: the right finger's row of J is in a shared column
      {"panda_fingers_mimic", "panda.urdf", false, {"panda_leftfinger:3d", "panda_rightfinger:3d"}},
  };
  return cases;
}

class ContactTest : public testing::TestWithParam<ContactCase> {};

INSTANTIATE_TEST_SUITE_P(Robots, ContactTest, testing::ValuesIn(contact_cases()),
                         [](const testing::TestParamInfo<ContactCase>& info) {
                           return info.param.name;
                         });

TEST_P(ContactTest, LoadsTheContacts) {
  const Model<double> model = load(GetParam());
  ASSERT_EQ(model.constraints.size(), GetParam().contacts.size());
  int rows = 0;
  for (const Constraint<double>& c : model.constraints) {
    EXPECT_GE(c.body_a, 0) << c.name;
    EXPECT_EQ(c.body_b, -1) << c.name;  // a contact holds its frame to the world
    EXPECT_FALSE(c.loop) << c.name;     // where it touched: no position error
    rows += constraint_rows(c);
  }
  EXPECT_EQ(model.nc, rows);
  if (GetParam().file == "panda.urdf") {
    EXPECT_FALSE(model.mimic.empty());
  }
}

/// Whether W^T = L^-T J^T, after contact_dynamics at a random state, is +-0 off the columns
/// that kernels::constrained_columns' tables (Workspace::constraint_paths) give each row, and
/// whether the tables of rows per column are their transpose.
void expect_w_within_its_tables(const Model<double>& model) {
  Workspace<double> ws(model);
  const Sample s = random_samples(model, 97, 1)[0];
  Vector qdd(model.nv), lam(model.nc);
  contact_dynamics<double>(model, ws, span(s.q), span(s.v), span(s.tau), span(qdd), span(lam));
  const int n = model.nv;
  int nonzero = 0, listed = 0;
  for (int r = 0; r < model.nc; ++r)
    for (int k = 0; k < n; ++k) {
      const int* begin = &ws.w_columns[ws.w_begin[r]];
      const int* end = &ws.w_columns[0] + ws.w_begin[r + 1];
      const bool in_table = std::find(begin, end, k) != end;
      const int* rows_begin = &ws.w_rows[0] + ws.w_rows_begin[k];
      const int* rows_end = &ws.w_rows[0] + ws.w_rows_begin[k + 1];
      EXPECT_EQ(in_table, std::find(rows_begin, rows_end, r) != rows_end) << r << ", " << k;
      if (!in_table) {
        EXPECT_EQ(ws.Wt[row_major(n, r, k)], 0.0) << "row " << r << ", column " << k;
      }
      nonzero += ws.Wt[row_major(n, r, k)] != 0.0;
      listed += in_table;
    }
  EXPECT_GT(nonzero, 0);
  std::cout << "W: " << nonzero << " non-zero entries, " << listed << " in the tables, of "
            << model.nc * n << "\n";
}

TEST_P(ContactTest, WIsZeroOffItsTables) { expect_w_within_its_tables(load(GetParam())); }

// A loop between two legs: W's row is non-zero along both paths, which share the base.
TEST(LoopClosure, WIsZeroOffItsTablesAcrossLegs) {
  Model<double> model = load(contact_cases()[0]);
  const int fl = model.constraints[0].body_a, hr = model.constraints[3].body_a;
  const Xform<double> at{rotation_from_rpy(0.3, -0.2, 0.5), {0.1, -0.05, 0.2}};
  set_constraints<double>(model, {{"loop", fl, at, hr, at, true, true}}, {});
  expect_w_within_its_tables(model);
}

// M qdd + h = tau + J^T lam and J qdd + Jdot v = 0, with RNEA for the first.
TEST_P(ContactTest, SatisfiesTheDefiningEquations) {
  const Model<double> model = load(GetParam());
  double worst_dynamics = 0, worst_constraint = 0;
  for (const Sample& s : random_samples(model, 11)) {
    const Solution x = contact_solution(model, s);
    ASSERT_TRUE(x.qdd.allFinite() && x.lam.allFinite());
    const Terms<double> t = constraint_terms(model, s.q, s.v);
    worst_dynamics = std::max(worst_dynamics, dynamics_residual(model, s, t, x));
    worst_constraint = std::max(worst_constraint, constraint_residual(t, s.v, x.qdd));
  }
  std::cout << GetParam().name << ": dynamics residual " << worst_dynamics
            << ", constraint residual " << worst_constraint << "\n";
  EXPECT_LE(worst_dynamics, 1e-12);
  EXPECT_LE(worst_constraint, 1e-12);
}

/// The 2-norm condition number of a matrix, from its singular values.
double condition_number(const Matrix& A) {
  const Eigen::JacobiSVD<Matrix> svd(A);
  return svd.singularValues()(0) / svd.singularValues()(svd.singularValues().size() - 1);
}

/// The larger condition number of M and of A = J M^-1 J^T: the constrained solve's loss of
/// digits.
double solve_condition(const Terms<double>& t) {
  const Matrix A = t.J * t.M.inverse() * t.J.transpose();
  return std::max(condition_number(t.M), condition_number(A));
}

// contact_dynamics' double qdd and lam against the exact KKT solution (256-bit MPFR; the terms
// from the runtime on mpreal at the same double inputs), within 1000 eps times the condition
// number of M or of A = J M^-1 J^T, whichever is larger: the solve's loss of digits.
TEST_P(ContactTest, MatchesTheKktSolutionInMpfr) {
  const Model<double> model = load(GetParam());
  mpfr::mpreal::set_default_prec(numerics::exact_bits);
  const Model<Exact> exact = model.cast<Exact>();
  const int n = model.nv, m = model.nc;
  double worst_qdd = 0, worst_lam = 0, worst_ratio = 0;
  for (const Sample& s : random_samples(model, 23)) {
    const Solution x = contact_solution(model, s);
    const VectorX<Exact> q = s.q.cast<Exact>(), v = s.v.cast<Exact>(), tau = s.tau.cast<Exact>();
    const Terms<Exact> t = constraint_terms(exact, q, v);
    MatrixX<Exact> K = MatrixX<Exact>::Zero(n + m, n + m);
    K.topLeftCorner(n, n) = t.M;
    K.topRightCorner(n, m) = t.J.transpose();
    K.bottomLeftCorner(m, n) = t.J;
    VectorX<Exact> rhs(n + m);
    rhs << tau - t.h, -t.gamma;
    const VectorX<Exact> y = K.partialPivLu().solve(rhs);
    const VectorX<Exact> qdd = y.head(n), lam = -y.tail(m);
    const double e_qdd = numerics::relative_error(span(x.qdd), span(qdd));
    const double e_lam = numerics::relative_error(span(x.lam), span(lam));
    const double kappa = solve_condition(constraint_terms(model, s.q, s.v));
    EXPECT_LE(e_qdd, 1000 * eps * kappa);
    EXPECT_LE(e_lam, 1000 * eps * kappa);
    worst_qdd = std::max(worst_qdd, e_qdd);
    worst_lam = std::max(worst_lam, e_lam);
    worst_ratio = std::max(worst_ratio, std::max(e_qdd, e_lam) / (eps * kappa));
  }
  std::cout << GetParam().name << ": qdd error " << worst_qdd << ", lam error " << worst_lam
            << ", over eps cond " << worst_ratio << "\n";
}

/// contact_dynamics_derivatives in double against central differences of contact_dynamics in
/// 256-bit MPFR at q (+) +-h e_c (integrate, tangent columns), v +- h e_c and tau +- h e_c, h =
/// 1e-20 (truncation h^2, rounding 2^-256 / h: both far below double's eps). Returns the largest
/// error over max|entry| of each of the six, over eps times solve_condition.
double derivative_error(const Model<double>& model, const Sample& s,
                        const Vector& anchors = Vector()) {
  const int n = model.nv, m = model.nc;
  std::vector<double> d[6] = {std::vector<double>(n * n), std::vector<double>(n * n),
                              std::vector<double>(n * n), std::vector<double>(m * n),
                              std::vector<double>(m * n), std::vector<double>(m * n)};
  Workspace<double> ws(model);
  contact_dynamics_derivatives<double>(model, ws, span(s.q), span(s.v), span(s.tau), d[0], d[1],
                                       d[2], d[3], d[4], d[5], span(anchors));
  mpfr::mpreal::set_default_prec(numerics::exact_bits);
  const Model<Exact> exact = model.cast<Exact>();
  Workspace<Exact> xws(exact);
  const Exact h("1e-20");
  const VectorX<Exact> q = s.q.cast<Exact>(), v = s.v.cast<Exact>(), tau = s.tau.cast<Exact>(),
                       a = anchors.cast<Exact>();
  double worst = 0;
  for (int x = 0; x < 3; ++x) {
    Matrix fd_qdd(n, n), fd_lam(m, n);
    for (int c = 0; c < n; ++c) {
      VectorX<Exact> out[2][2] = {{VectorX<Exact>(n), VectorX<Exact>(m)},
                                  {VectorX<Exact>(n), VectorX<Exact>(m)}};
      for (int side = 0; side < 2; ++side) {
        VectorX<Exact> qx = q, vx = v, taux = tau, step = VectorX<Exact>::Zero(n);
        step(c) = side == 0 ? h : Exact(-h);
        if (x == 0) integrate<Exact>(exact, span(q), span(step), span(qx));
        if (x == 1) vx += step;
        if (x == 2) taux += step;
        contact_dynamics<Exact>(exact, xws, span(qx), span(vx), span(taux), span(out[side][0]),
                                span(out[side][1]), span(a));
      }
      for (int r = 0; r < n; ++r)
        fd_qdd(r, c) = ((out[0][0](r) - out[1][0](r)) / (2 * h)).toDouble();
      for (int r = 0; r < m; ++r)
        fd_lam(r, c) = ((out[0][1](r) - out[1][1](r)) / (2 * h)).toDouble();
    }
    const Matrix got_qdd = test::to_eigen(d[x], n),
                 got_lam = Eigen::Map<
                     const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
                     d[3 + x].data(), m, n);
    worst =
        std::max({worst, (got_qdd - fd_qdd).cwiseAbs().maxCoeff() / fd_qdd.cwiseAbs().maxCoeff(),
                  (got_lam - fd_lam).cwiseAbs().maxCoeff() / fd_lam.cwiseAbs().maxCoeff()});
  }
  return worst / (eps * solve_condition(constraint_terms(model, s.q, s.v)));
}

// The six derivatives against MPFR central differences, within 1000 eps cond relative to their
// largest entry, as the KKT solve above (measured at most 3.2, solo12_two_feet_6d; a term left out
// gives 7e9 or more).
TEST_P(ContactTest, DerivativesMatchCentralDifferencesInMpfr) {
  const Model<double> model = load(GetParam());
  double worst = 0;
  for (const Sample& s : random_samples(model, 29, 1))
    worst = std::max(worst, derivative_error(model, s));
  std::cout << GetParam().name << ": derivatives' error over eps cond " << worst << "\n";
  EXPECT_LE(worst, 1000);
}

/// An orthonormal basis of J's null space: the right singular vectors past its rank.
Matrix null_space(const Matrix& J) {
  Eigen::JacobiSVD<Matrix> svd(J, Eigen::ComputeFullV);
  const Eigen::Index rank = svd.rank();
  return svd.matrixV().rightCols(J.cols() - rank);
}

// Gauss's principle of least constraint: qdd minimises G(x) = 1/2 (x - qdd_free)^T M
// (x - qdd_free) over J x = -Jdot v, qdd_free = ABA's. Along a feasible direction d = N z
// (N a basis of null(J)), G(qdd + d) - G(qdd) = g^T d + 1/2 d^T M d with g = M (qdd -
// qdd_free) = J^T lam, whose first term is zero: so the rise must be 1/2 d^T M d, > 0.
TEST_P(ContactTest, MinimisesGaussConstraint) {
  const Model<double> model = load(GetParam());
  Workspace<double> ws(model);
  test::Random rng(37);
  double worst_stationarity = 0, worst_rise = 0, worst_feasibility = 0;
  for (const Sample& s : random_samples(model, 31)) {
    const Solution x = contact_solution(model, s);
    Vector free(model.nv);
    aba<double>(model, ws, span(s.q), span(s.v), span(s.tau), span(free));
    const Terms<double> t = constraint_terms(model, s.q, s.v);
    const Matrix N = null_space(t.J);
    ASSERT_GT(N.cols(), 0);
    const Vector g = t.M * (x.qdd - free);
    worst_stationarity = std::max(worst_stationarity, (N.transpose() * g).norm() / g.norm());
    using L = long double;
    const auto G = [&](const Vector& y) {
      const VectorX<L> d = (y - free).cast<L>();
      return L(0.5) * d.dot(t.M.cast<L>() * d);
    };
    for (const double scale : {1e-2, 1.0}) {
      Vector z(N.cols());
      for (double& zi : z) zi = rng.uniform(-1, 1);
      const Vector d = N * z * (scale * (x.qdd.norm() + 1) / z.norm());
      const double rise = static_cast<double>(G(x.qdd + d) - G(x.qdd));
      const double quadratic = 0.5 * d.dot(t.M * d);
      EXPECT_GT(rise, 0);
      worst_rise = std::max(worst_rise, std::abs(rise / quadratic - 1));
      worst_feasibility = std::max(worst_feasibility, constraint_residual(t, s.v, x.qdd + d));
    }
  }
  std::cout << GetParam().name << ": projected gradient " << worst_stationarity
            << ", rise off 1/2 d^T M d by " << worst_rise << ", feasibility " << worst_feasibility
            << "\n";
  EXPECT_LE(worst_stationarity, 1e-12);
  // g^T d vanishes only to the rounding of qdd + d against g: measured up to 3e-10 of the rise
  // (iiwa14, panda), so 1e-8
  EXPECT_LE(worst_rise, 1e-8);
  EXPECT_LE(worst_feasibility, 1e-12);
}

/// Kinetic energy by kinematics.hpp: the sum over bodies of 1/2 v_i . I_i v_i.
double kinetic(const Model<double>& model, const Vector& q, const Vector& v) {
  Workspace<double> ws(model);
  forward_kinematics<double>(model, ws, span(q), span(v));
  return kinetic_energy<double>(model, ws, span(v));
}

// The impulse at touchdown for restitution 0 and 0.5: J v+ = -e J v-, M (v+ - v-) = J^T p, and
// the kinetic energy lost, (1 - e^2) / 2 w^T A^-1 w for w = J v- and A = J M^-1 J^T (Newton's
// law on all contacts at once), which is >= 0: it never rises.
TEST_P(ContactTest, ImpulseObeysTheImpactLaw) {
  for (const double e : {0.0, 0.5}) {
    ConstraintSettings<double> settings;
    settings.restitution = e;
    const Model<double> model = load(GetParam(), settings);
    ASSERT_EQ(model.constraint_settings.restitution, e);
    Workspace<double> ws(model);
    double worst_velocity = 0, worst_momentum = 0, worst_loss = 0;
    for (const Sample& s : random_samples(model, 41)) {
      Vector v_plus(model.nv), p(model.nc);
      impulse_dynamics<double>(model, ws, span(s.q), span(s.v), span(v_plus), span(p));
      ASSERT_TRUE(v_plus.allFinite() && p.allFinite());
      const Terms<double> t = constraint_terms(model, s.q, s.v);
      const Vector w = t.J * s.v, Jp = t.J.transpose() * p, jump = t.M * (v_plus - s.v);
      worst_velocity = std::max(worst_velocity, (t.J * v_plus + e * w).norm() /
                                                    (t.J.norm() * v_plus.norm() + e * w.norm()));
      worst_momentum = std::max(worst_momentum, (jump - Jp).norm() / (jump.norm() + Jp.norm()));
      const double before = kinetic(model, s.q, s.v), after = kinetic(model, s.q, v_plus);
      EXPECT_LE(after, before * (1 + 1e-12));
      using L = long double;
      const MatrixX<L> JL = t.J.cast<L>(), A = JL * t.M.cast<L>().ldlt().solve(JL.transpose());
      const VectorX<L> wL = w.cast<L>();
      const double loss = static_cast<double>((1 - e * e) / 2 * wL.dot(A.ldlt().solve(wL)));
      worst_loss = std::max(worst_loss, std::abs(before - after - loss) / before);
    }
    std::cout << GetParam().name << " e=" << e << ": J v+ residual " << worst_velocity
              << ", momentum residual " << worst_momentum << ", energy loss off by " << worst_loss
              << " of T\n";
    EXPECT_LE(worst_velocity, 1e-12);
    EXPECT_LE(worst_momentum, 1e-12);
    // measured up to 7e-13 of T (solo12's two 6d feet, whose A has condition number ~1e6)
    EXPECT_LE(worst_loss, 1e-11);
  }
}

// Baumgarte's velocity gain on contacts: J qdd + Jdot v = -kd J v, kd = 10. Without anchors kp
// acts on a loop's position error only, and a contact has none: kp = 100 changes nothing.
TEST_P(ContactTest, HoldsBaumgarteVelocityGain) {
  ConstraintSettings<double> settings;
  settings.kd = 10;
  const Model<double> model = load(GetParam(), settings);
  Model<double> stiff = model;
  stiff.constraint_settings.kp = 100;
  double worst_dynamics = 0, worst_constraint = 0;
  for (const Sample& s : random_samples(model, 53)) {
    const Solution x = contact_solution(model, s);
    const Terms<double> t = constraint_terms(model, s.q, s.v);
    worst_dynamics = std::max(worst_dynamics, dynamics_residual(model, s, t, x));
    worst_constraint = std::max(worst_constraint, constraint_residual(t, s.v, x.qdd, 10));
    const Solution y = contact_solution(stiff, s);
    EXPECT_EQ(x.qdd, y.qdd);
    EXPECT_EQ(x.lam, y.lam);
  }
  std::cout << GetParam().name << " kd=10: dynamics residual " << worst_dynamics
            << ", constraint residual " << worst_constraint << "\n";
  EXPECT_LE(worst_dynamics, 1e-12);
  EXPECT_LE(worst_constraint, 1e-12);
}

/// Frame A's placement of each constraint at q: rotation R (row-major) and origin p, base
/// coordinates (frames.hpp's frame_placements).
struct Placements {
  std::vector<double> R, p;
};

Placements contact_placements(const Model<double>& model, const Vector& q) {
  Model<double> fm = model;
  fm.frames.clear();
  for (const Constraint<double>& c : model.constraints)
    fm.frames.push_back({c.name, c.body_a, c.placement_a});
  Workspace<double> ws(fm);
  const std::size_t nf = fm.frames.size();
  Placements x{std::vector<double>(9 * nf), std::vector<double>(3 * nf)};
  frame_placements<double>(fm, ws, span(q), x.R, x.p);
  return x;
}

using Rotation = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

/// q moved by up to 0.05 in each tangent coordinate.
Vector nearby(const Model<double>& model, const Vector& q, test::Random& rng) {
  Vector d(model.nv), out(model.nq);
  for (double& x : d) x = rng.uniform(-0.05, 0.05);
  integrate<double>(model, span(q), span(d), span(out));
  return out;
}

/// contact_dynamics_anchored's anchors for the contact frames at placements x: each origin,
/// then for 6 rows the rotation as Eigen's angle-axis vector.
Vector anchors_of(const Model<double>& model, const Placements& x) {
  Vector anchors(model.nc);
  int row = 0;
  for (std::size_t k = 0; k < model.constraints.size(); ++k) {
    const Eigen::AngleAxisd turn{Rotation(Eigen::Map<const Rotation>(&x.R[9 * k]))};
    const Eigen::Vector3d w = turn.angle() * turn.axis();
    const double a[6] = {x.p[3 * k], x.p[3 * k + 1], x.p[3 * k + 2], w.x(), w.y(), w.z()};
    for (int r = 0; r < constraint_rows(model.constraints[k]); ++r, ++row) anchors(row) = a[r];
  }
  return anchors;
}

// Baumgarte's kp on contacts from their anchors (contact_dynamics_anchored): the anchors are the
// contact frames' placements at a configuration 0.05 away, the rotation as Eigen's angle-axis
// vector; e (p_A - p_ref, then 1/2 vee(R_A R_ref^T - R_ref R_A^T)) from frame_placements, and
// J qdd + Jdot v = -kd J v - kp e with M qdd + h = tau + J^T lam.
TEST_P(ContactTest, AnchorsGiveBaumgartesPositionGain) {
  ConstraintSettings<double> settings;
  settings.kd = 20, settings.kp = 100;
  const Model<double> model = load(GetParam(), settings);
  test::Random rng(59);
  double worst_dynamics = 0, worst_constraint = 0, smallest_e = 1;
  for (const Sample& s : random_samples(model, 59)) {
    const Placements ref = contact_placements(model, nearby(model, s.q, rng)),
                     now = contact_placements(model, s.q);
    const Vector anchors = anchors_of(model, ref);
    Terms<double> t = constraint_terms(model, s.q, s.v);
    int row = 0;
    for (std::size_t k = 0; k < model.constraints.size(); ++k) {
      const Rotation RA = Eigen::Map<const Rotation>(&now.R[9 * k]),
                     RB = Eigen::Map<const Rotation>(&ref.R[9 * k]);
      const Rotation W = RA * RB.transpose() - RB * RA.transpose();
      const double e[6] = {now.p[3 * k] - ref.p[3 * k], now.p[3 * k + 1] - ref.p[3 * k + 1],
                           now.p[3 * k + 2] - ref.p[3 * k + 2], W(2, 1) / 2, W(0, 2) / 2,
                           W(1, 0) / 2};
      for (int r = 0; r < constraint_rows(model.constraints[k]); ++r, ++row) t.e(row) = e[r];
    }
    Workspace<double> ws(model);
    Solution x{Vector(model.nv), Vector(model.nc)};
    contact_dynamics<double>(model, ws, span(s.q), span(s.v), span(s.tau), span(x.qdd),
                             span(x.lam), span(anchors));
    worst_dynamics = std::max(worst_dynamics, dynamics_residual(model, s, t, x));
    worst_constraint = std::max(worst_constraint, constraint_residual(t, s.v, x.qdd, 20, 100));
    smallest_e = std::min(smallest_e, t.e.norm());
  }
  std::cout << GetParam().name << " kp=100, kd=20, anchors: dynamics residual " << worst_dynamics
            << ", constraint residual " << worst_constraint << ", |e| >= " << smallest_e << "\n";
  EXPECT_GT(smallest_e, 1e-4);  // the anchors are away from the frames: kp matters
  EXPECT_LE(worst_dynamics, 1e-12);
  EXPECT_LE(worst_constraint, 1e-12);
}

// contact_dynamics_anchored_derivatives (kp 100, kd 20, anchors as above) against MPFR central
// differences of contact_dynamics with the same anchors, as DerivativesMatchCentralDifferences.
TEST_P(ContactTest, AnchoredDerivativesMatchCentralDifferencesInMpfr) {
  ConstraintSettings<double> settings;
  settings.kd = 20, settings.kp = 100;
  const Model<double> model = load(GetParam(), settings);
  test::Random rng(61);
  double worst = 0;
  for (const Sample& s : random_samples(model, 61, 1)) {
    const Vector anchors = anchors_of(model, contact_placements(model, nearby(model, s.q, rng)));
    worst = std::max(worst, derivative_error(model, s, anchors));
  }
  std::cout << GetParam().name << " anchored: derivatives' error over eps cond " << worst << "\n";
  EXPECT_LE(worst, 1000);
}

// Four feet in 6d on solo12: 24 rows on 18 degrees of freedom, every one locked, consistent only
// at v = 0. There qdd = 0 and lam is fixed up to null(J^T) (6 dimensions); the proximal solve from
// lam = 0 tends to the minimum-norm lam, pinv(A) r with A = J M^-1 J^T and r = -J M^-1 (tau - h),
// computed here in long double by SVD, its rank cut at 1e-12 of the largest singular value
// (measured: sigma_18 / sigma_1 >= 9e-5, sigma_19 / sigma_18 <= 3e-16). Along null(A) each
// proximal step adds the rounding of r - A lam (eps relative) over mu = damping times A's mean
// diagonal: lam is off the minimum-norm one by about eps / damping (measured 0.38 eps / damping,
// 8e-7 at the default 1e-10 and 7e-9 at 1e-8), so the bound is 10 eps / damping.
TEST(RedundantContacts, FourFeet6dGiveTheMinimumNormForces) {
  using L = long double;
  const ContactCase feet{"solo12_four_feet_6d",
                         "solo12.urdf",
                         true,
                         {"FL_FOOT:6d", "FR_FOOT:6d", "HL_FOOT:6d", "HR_FOOT:6d"}};
  for (const double damping : {ConstraintSettings<double>::default_damping(), 1e-8}) {
    ConstraintSettings<double> settings;
    settings.damping = damping;
    const Model<double> model = load(feet, settings);
    ASSERT_EQ(model.nc, 24);
    ASSERT_EQ(model.nv, 18);
    const Model<L> ml = model.cast<L>();
    double worst_qdd = 0, worst_dynamics = 0, worst_lam = 0, gap = 0, smallest = 1;
    for (Sample s : random_samples(model, 61)) {
      s.v.setZero();
      const Solution x = contact_solution(model, s);
      ASSERT_TRUE(x.qdd.allFinite() && x.lam.allFinite());
      const Terms<L> t = constraint_terms<L>(ml, s.q.cast<L>(), s.v.cast<L>());
      const Eigen::LDLT<MatrixX<L>> M(t.M);
      const MatrixX<L> A = t.J * M.solve(t.J.transpose());
      const VectorX<L> free = M.solve(s.tau.cast<L>() - t.h), r = -t.J * free;
      Eigen::JacobiSVD<MatrixX<L>> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
      svd.setThreshold(1e-12L);
      ASSERT_EQ(svd.rank(), 18);
      const VectorX<L>& sigma = svd.singularValues();
      gap = std::max(gap, static_cast<double>(sigma(18) / sigma(17)));
      smallest = std::min(smallest, static_cast<double>(sigma(17) / sigma(0)));
      const Vector lam = svd.solve(r).cast<double>();
      worst_lam = std::max(worst_lam, (x.lam - lam).norm() / lam.norm());
      worst_qdd = std::max(worst_qdd, x.qdd.norm() / static_cast<double>(free.norm()));
      const Terms<double> td = constraint_terms(model, s.q, s.v);
      worst_dynamics = std::max(worst_dynamics, dynamics_residual(model, s, td, x));
    }
    std::cout << "four feet 6d, damping " << damping << ": |qdd| / |qdd_free| " << worst_qdd
              << ", dynamics residual " << worst_dynamics << ", lam off the minimum-norm one by "
              << worst_lam << " (sigma_18 / sigma_1 of A " << smallest << ", sigma_19 / sigma_18 "
              << gap << ")\n";
    EXPECT_LE(worst_qdd, 1e-12);       // measured 4e-16
    EXPECT_LE(worst_dynamics, 1e-12);  // measured 9e-16
    EXPECT_LE(worst_lam, 10 * eps / damping);
  }
}

// A loop closure (none of the shared robot files has one): a random spatial chain with body a's
// frame held to body b's (or to a frame fixed in the world, b = -1), in 3d and 6d, at placements
// that leave a position error e. Baumgarte's gains kd = 10, kp = 100: J qdd + Jdot v = -kd J v -
// kp e with J = J_A - J_B, and the dynamics.
TEST(LoopClosure, HoldsBaumgarteGains) {
  struct Loop {
    int links, a, b;
    bool six_d;
  };
  for (const Loop& loop : {Loop{6, 1, 5, false}, Loop{9, 2, 8, true}, Loop{7, 6, -1, true}}) {
    Model<double> model = test::make_random_chain(loop.links, 71, false);
    const Xform<double> pa{rotation_from_rpy(0.3, -0.2, 0.5), {0.1, -0.05, 0.2}},
        pb{rotation_from_rpy(-0.4, 0.1, 0.7), {-0.1, 0.15, 0.05}};
    ConstraintSettings<double> settings;
    settings.kd = 10, settings.kp = 100;
    set_constraints<double>(model, {{"loop", loop.a, pa, loop.b, pb, loop.six_d, true}}, settings);
    double worst_dynamics = 0, worst_constraint = 0, error = 0;
    for (const Sample& s : random_samples(model, 73)) {
      const Solution x = contact_solution(model, s);
      const Terms<double> t = constraint_terms(model, s.q, s.v);
      worst_dynamics = std::max(worst_dynamics, dynamics_residual(model, s, t, x));
      worst_constraint = std::max(worst_constraint, constraint_residual(t, s.v, x.qdd, 10, 100));
      error = std::max(error, t.e.norm());
    }
    std::cout << "loop " << loop.a << "-" << loop.b << (loop.six_d ? " 6d" : " 3d")
              << ": dynamics residual " << worst_dynamics << ", constraint residual "
              << worst_constraint << " (|e| up to " << error << ")\n";
    EXPECT_GT(error, 0.1);  // kp's term is not empty
    EXPECT_LE(worst_dynamics, 1e-12);
    EXPECT_LE(worst_constraint, 1e-12);
  }
}

// The derivatives of loop closures with Baumgarte's gains (kd = 10, kp = 100), and of point
// feet with kd alone, against MPFR central differences as above.
TEST(LoopClosure, DerivativesMatchCentralDifferencesInMpfr) {
  ConstraintSettings<double> settings;
  settings.kd = 10, settings.kp = 100;
  double worst = 0;
  for (const bool six_d : {false, true}) {
    Model<double> model = test::make_random_chain(7, 79, false);
    const Xform<double> pa{rotation_from_rpy(0.3, -0.2, 0.5), {0.1, -0.05, 0.2}},
        pb{rotation_from_rpy(-0.4, 0.1, 0.7), {-0.1, 0.15, 0.05}};
    set_constraints<double>(model, {{"loop", 2, pa, 6, pb, six_d, true}}, settings);
    for (const Sample& s : random_samples(model, 83, 1))
      worst = std::max(worst, derivative_error(model, s));
  }
  settings.kp = 0;
  const Model<double> feet = load(contact_cases()[0], settings);
  for (const Sample& s : random_samples(feet, 89, 1))
    worst = std::max(worst, derivative_error(feet, s));
  std::cout << "loops and feet with gains: derivatives' error over eps cond " << worst << "\n";
  EXPECT_LE(worst, 1000);
}

}  // namespace
}  // namespace dyngen
