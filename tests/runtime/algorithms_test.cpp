// Cross-checks of RNEA, CRBA and ABA (the rigid-body algorithms chapter's experiments 1 and 2)
// on seeded random chains, the documented five-link case and the shared robots; closed-form
// oracles; and a long double instantiation as the higher-precision reference.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <string_view>

#include "dyngen/dyngen.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

template <class S>
using VectorX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
template <class S>
using MatrixX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
using Vector = VectorX<double>;
using Matrix = MatrixX<double>;

constexpr double eps = std::numeric_limits<double>::epsilon();
constexpr int states_per_model = 20;

/// The runtime's algorithms with Eigen vectors at the boundary.
template <class S>
class Dynamics {
 public:
  explicit Dynamics(Model<S> model) : model_(std::move(model)), ws_(model_) {}

  int nv() const { return model_.nv; }
  const Model<S>& model() const { return model_; }

  VectorX<S> rnea(const VectorX<S>& q, const VectorX<S>& qd, const VectorX<S>& qdd) {
    VectorX<S> tau(nv());
    dyngen::rnea<S>(model_, ws_, span(q), span(qd), span(qdd), {tau.data(), std::size_t(nv())});
    return tau;
  }

  /// M(q) from the runtime's row-major array.
  MatrixX<S> crba(const VectorX<S>& q) {
    std::vector<S> M(nv() * nv());
    dyngen::crba<S>(model_, ws_, span(q), M);
    return test::to_eigen(M, nv());
  }

  VectorX<S> nle(const VectorX<S>& q, const VectorX<S>& qd) {
    VectorX<S> h(nv());
    dyngen::nle<S>(model_, ws_, span(q), span(qd), {h.data(), std::size_t(nv())});
    return h;
  }

  MatrixX<S> minv(const VectorX<S>& q) {
    std::vector<S> Minv(nv() * nv());
    dyngen::minv<S>(model_, ws_, span(q), Minv);
    return test::to_eigen(Minv, nv());
  }

  VectorX<S> aba(const VectorX<S>& q, const VectorX<S>& qd, const VectorX<S>& tau) {
    VectorX<S> qdd(nv());
    dyngen::aba<S>(model_, ws_, span(q), span(qd), span(tau), {qdd.data(), std::size_t(nv())});
    return qdd;
  }

 private:
  static std::span<const S> span(const VectorX<S>& x) { return {x.data(), std::size_t(x.size())}; }

  Model<S> model_;
  Workspace<S> ws_;
};

Model<double> without_gravity(Model<double> model) {
  model.gravity = {0, 0, 0};
  return model;
}

/// The largest absolute entry; infinity if any entry is not finite, so that bounds fail.
double max_abs(const Matrix& x) {
  if (!x.allFinite()) return std::numeric_limits<double>::infinity();
  return x.size() ? x.cwiseAbs().maxCoeff() : 0.0;
}

/// The larger error so far; a NaN sticks, so that it fails the bound it is checked against.
double worse(double worst, double error) {
  if (std::isnan(worst) || std::isnan(error)) return std::numeric_limits<double>::quiet_NaN();
  return std::max(worst, error);
}

/// One state and the scales that bound the rounding errors of the algorithms at it.
struct Sample {
  Vector q, qd, qdd, tau;
  Matrix M;
  Vector bias;  // C(q, qd) qd + g(q) = RNEA(q, qd, 0)
  double lambda_min, lambda_max;

  /// Forward error bound of qdd from tau, in units of n eps. Rounding in RNEA or in ABA's
  /// recursions is a backward error dtau of about n eps (|M| |qdd| + |bias|) on the torques
  /// (each is a sum of n terms of those sizes), and M^-1 turns it into an error in qdd of at most
  /// |dtau| / lambda_min: n eps (cond(M) |qdd| + (|tau| + |bias|) / lambda_min).
  double qdd_scale() const {
    return lambda_max / lambda_min * qdd.cwiseAbs().maxCoeff() +
           (tau.cwiseAbs().maxCoeff() + bias.cwiseAbs().maxCoeff()) / lambda_min;
  }
};

Sample sample(Dynamics<double>& dyn, test::Random& rng) {
  const test::State s = test::random_state(dyn.model(), rng);
  Sample x;
  x.q = test::to_eigen(s.q);
  x.qd = test::to_eigen(s.qd);
  x.qdd = test::to_eigen(s.qdd);
  x.tau = test::to_eigen(s.tau);
  x.M = dyn.crba(x.q);
  x.bias = dyn.rnea(x.q, x.qd, Vector::Zero(dyn.nv()));
  const Eigen::SelfAdjointEigenSolver<Matrix> eig(x.M, Eigen::EigenvaluesOnly);
  x.lambda_min = eig.eigenvalues().minCoeff();
  x.lambda_max = eig.eigenvalues().maxCoeff();
  return x;
}

// ---- the models -----------------------------------------------------------------------------

struct Case {
  std::string name;
  std::function<Model<double>()> make;
  std::uint64_t seed;
};

std::vector<Case> cases() {
  std::vector<Case> all;
  for (const bool planar : {true, false})
    for (const int n : {1, 2, 5, 12}) {
      const std::uint64_t seed = 1000 + n + (planar ? 0 : 100);
      all.push_back({std::string(planar ? "planar" : "spatial") + "_chain_" + std::to_string(n),
                     [=] { return test::make_random_chain(n, seed, planar); }, seed});
    }
  all.push_back(
      {"planar5", [] { return gen::load_robot(test::model_path("planar5.yaml")).model; }, 5});
  all.push_back({"all_joints", [] {
                   return gen::load_robot(test::model_path("coverage/all_joints.urdf")).model;
                 }, 6});
  all.push_back({"armature_chain", [] {
                   return gen::load_robot(test::model_path("coverage/armature_chain.yaml")).model;
                 }, 9});
  for (const bool floating : {false, true})
    all.push_back({floating ? "ball_chain_floating" : "ball_chain",
                   [=] { return test::load_model("coverage/ball_chain.yaml", floating); },
                   floating ? 12u : 11u});
  all.push_back({"ur5_armature_floating", [] {
                   gen::LoadOptions options;
                   options.floating_base = true;
                   options.armature = {{"all", 0.05}, {"elbow_joint", 0.3}};
                   return gen::load_robot(test::model_path("ur5.urdf"), options).model;
                 }, 10});
  for (const test::RobotFile& robot : test::robot_files()) {
    all.push_back({robot.name, [=] { return test::load_for_aba(robot); }, 7});
    all.push_back({robot.name + "_floating", [=] { return test::load_for_aba(robot, true); }, 8});
  }
  return all;
}

class Algorithms : public ::testing::TestWithParam<Case> {
 protected:
  bool is_planar5() const { return GetParam().name == "planar5"; }
  void report(const char* what, double value) const {
    std::cout << "[ measured ] " << GetParam().name << ": " << what << " " << value << "\n";
  }
};

// The chapter's thresholds for the documented five-link case hold for any correct
// implementation, with an order of magnitude to spare (its M has entries of about 1 and a
// condition number of a few hundred); the other models are held to the scaled bounds below.
constexpr double chapter_replay_bound = 6e-13;
constexpr double chapter_crba_bound = 2e-13;

// Multiples of n eps times Sample::qdd_scale() or max|M|. Correct algorithms stay below 1
// (measured: at most 0.85 for qdd, 1.6 for M, on the 2-link spatial chain whose M has entries
// much smaller than the terms that make them); a wrong term gives errors of order
// 1 / (n eps cond(M)), above 1e4 for every model here.
constexpr double qdd_bound_neps = 4;
constexpr double mass_matrix_bound_neps = 8;

TEST_P(Algorithms, RneaThenAbaReplaysAcceleration) {
  Dynamics<double> dyn(GetParam().make());
  test::Random rng(GetParam().seed);
  const int n = dyn.nv();
  double worst = 0, worst_scaled = 0;
  for (int k = 0; k < states_per_model; ++k) {
    const Sample x = sample(dyn, rng);
    const Vector tau = dyn.rnea(x.q, x.qd, x.qdd);
    const double err = max_abs(dyn.aba(x.q, x.qd, tau) - x.qdd);
    worst = worse(worst, err);
    Sample replay = x;
    replay.tau = tau;
    worst_scaled = worse(worst_scaled, err / (n * eps * replay.qdd_scale()));
  }
  report("replay max abs error", worst);
  report("replay error / (n eps scale)", worst_scaled);
  EXPECT_LE(worst_scaled, qdd_bound_neps);
  if (is_planar5()) {
    EXPECT_LT(worst, chapter_replay_bound);
  }
}

TEST_P(Algorithms, CrbaMatchesRneaColumns) {
  // M e_j = RNEA(q, 0, e_j) - RNEA(q, 0, 0) with gravity removed
  Dynamics<double> dyn(GetParam().make());
  Dynamics<double> no_gravity(without_gravity(GetParam().make()));
  test::Random rng(GetParam().seed);
  const int n = dyn.nv();
  const Vector zero = Vector::Zero(n);
  double worst = 0, worst_scaled = 0;
  for (int k = 0; k < states_per_model; ++k) {
    const Sample x = sample(dyn, rng);
    Matrix M_rnea(n, n);
    const Vector bias = no_gravity.rnea(x.q, zero, zero);
    for (int j = 0; j < n; ++j)
      M_rnea.col(j) = no_gravity.rnea(x.q, zero, Vector::Unit(n, j)) - bias;
    const double err = max_abs(x.M - M_rnea);
    worst = worse(worst, err);
    worst_scaled = worse(worst_scaled, err / (n * eps * max_abs(x.M)));
  }
  report("CRBA vs RNEA columns max abs error", worst);
  report("CRBA vs RNEA columns error / (n eps max|M|)", worst_scaled);
  EXPECT_LE(worst_scaled, mass_matrix_bound_neps);
  if (is_planar5()) {
    EXPECT_LT(worst, chapter_crba_bound);
  }
}

TEST_P(Algorithms, MassMatrixAndNonlinearEffectsMakeRnea) {
  // RNEA(q, qd, qdd) = M(q) qdd + h(q, qd): CRBA's M and nle's h against RNEA
  Dynamics<double> dyn(GetParam().make());
  test::Random rng(GetParam().seed);
  const int n = dyn.nv();
  double worst_scaled = 0;
  for (int k = 0; k < states_per_model; ++k) {
    const Sample x = sample(dyn, rng);
    const Vector h = dyn.nle(x.q, x.qd);
    const Vector tau = dyn.rnea(x.q, x.qd, x.qdd);
    const double scale = max_abs(x.M) * x.qdd.cwiseAbs().maxCoeff() + h.cwiseAbs().maxCoeff();
    worst_scaled = worse(worst_scaled, max_abs(x.M * x.qdd + h - tau) / (n * eps * scale));
  }
  report("M qdd + h vs RNEA error / (n eps (|M| |qdd| + |h|))", worst_scaled);
  EXPECT_LE(worst_scaled, mass_matrix_bound_neps);
}

TEST_P(Algorithms, MinvInvertsCrbaAndMatchesAba) {
  // minv's M^-1 against CRBA's M (M^-1 M = 1) and against ABA's columns at zero velocity
  // and gravity (qdd = M^-1 e_c): errors in units of n eps cond(M)
  Dynamics<double> dyn(GetParam().make());
  Dynamics<double> no_gravity(without_gravity(GetParam().make()));
  test::Random rng(GetParam().seed);
  const int n = dyn.nv();
  const Vector zero = Vector::Zero(n);
  double worst_identity = 0, worst_aba = 0;
  for (int k = 0; k < states_per_model; ++k) {
    const Sample x = sample(dyn, rng);
    const Matrix Minv = dyn.minv(x.q);
    EXPECT_EQ(max_abs(Minv - Minv.transpose()), 0.0);
    const double cond = x.lambda_max / x.lambda_min;
    worst_identity = worse(worst_identity,
                           max_abs(Minv * x.M - Matrix::Identity(n, n)) / (n * eps * cond));
    Matrix columns(n, n);
    for (int c = 0; c < n; ++c) columns.col(c) = no_gravity.aba(x.q, zero, Vector::Unit(n, c));
    worst_aba = worse(worst_aba, max_abs(Minv - columns) / (n * eps * cond * max_abs(Minv)));
  }
  report("minv M - 1 / (n eps cond(M))", worst_identity);
  report("minv vs ABA columns / (n eps cond(M) max|Minv|)", worst_aba);
  EXPECT_LE(worst_identity, qdd_bound_neps);
  EXPECT_LE(worst_aba, qdd_bound_neps);
}

TEST_P(Algorithms, LtdlFactorsCrbaWithAbasPivots) {
  // factor_ltdl's D against ABA's D = S^T IA S of each one-column joint (the same Schur
  // complements, computed from M here and from articulated inertias there): errors in units of
  // n eps cond(M). ltdl_inverse is minv's, which MinvInvertsCrbaAndMatchesAba checks.
  const Model<double> model = GetParam().make();
  Dynamics<double> dyn(model);
  Workspace<double> ws(model);
  test::Random rng(GetParam().seed);
  const int n = model.nv;
  const std::size_t nn = static_cast<std::size_t>(n) * n;
  std::vector<double> H(nn), Dinv(n), qdd(n);
  double worst_pivot = 0;
  for (int k = 0; k < states_per_model; ++k) {
    const Sample x = sample(dyn, rng);
    const std::span<const double> q(x.q.data(), std::size_t(x.q.size()));
    crba<double>(model, ws, q, H);
    factor_ltdl<double>(n, ws.column_parent.data(), H, Dinv);
    const double cond = x.lambda_max / x.lambda_min;
    aba<double>(model, ws, q, {x.qd.data(), std::size_t(n)}, {x.tau.data(), std::size_t(n)},
                qdd);
    for (int i = 0; i < model.nbodies; ++i) {
      if (joint_nv(model.joint_type[i]) != 1) continue;
      const double D = 1 / Dinv[model.v_index[i]];
      worst_pivot = worse(worst_pivot, std::abs(D - ws.D[i]) / (n * eps * cond * std::abs(D)));
    }
  }
  report("LTDL pivots vs ABA's D / (n eps cond(M) |D|)", worst_pivot);
  EXPECT_LE(worst_pivot, qdd_bound_neps);
}

TEST_P(Algorithms, MassMatrixIsSymmetricPositiveDefinite) {
  Dynamics<double> dyn(GetParam().make());
  test::Random rng(GetParam().seed);
  double lambda_min = std::numeric_limits<double>::infinity(), cond = 0;
  for (int k = 0; k < states_per_model; ++k) {
    const Sample x = sample(dyn, rng);
    EXPECT_EQ(max_abs(x.M - x.M.transpose()), 0.0);
    EXPECT_GT(x.lambda_min, 0.0);
    lambda_min = std::min(lambda_min, x.lambda_min);
    cond = std::max(cond, x.lambda_max / x.lambda_min);
  }
  report("smallest eigenvalue of M", lambda_min);
  report("largest condition number of M", cond);
}

TEST_P(Algorithms, AbaMatchesDenseSolve) {
  // qdd = M^-1 (tau - C qd - g) through CRBA and a Cholesky factorisation
  Dynamics<double> dyn(GetParam().make());
  test::Random rng(GetParam().seed);
  const int n = dyn.nv();
  double worst = 0, worst_scaled = 0;
  for (int k = 0; k < states_per_model; ++k) {
    Sample x = sample(dyn, rng);
    const Eigen::LLT<Matrix> llt(x.M);
    ASSERT_EQ(llt.info(), Eigen::Success);
    x.qdd = llt.solve(x.tau - x.bias);
    const double err = max_abs(dyn.aba(x.q, x.qd, x.tau) - x.qdd);
    worst = worse(worst, err);
    worst_scaled = worse(worst_scaled, err / (n * eps * x.qdd_scale()));
  }
  report("ABA vs dense solve max abs error", worst);
  report("ABA vs dense solve error / (n eps scale)", worst_scaled);
  EXPECT_LE(worst_scaled, qdd_bound_neps);
}

INSTANTIATE_TEST_SUITE_P(Models, Algorithms, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return info.param.name;
                         });

// ---- the runtime in long double as the reference --------------------------------------------

// A rotor inertia (armature) a_k is M's diagonal entry plus a_k, and RNEA's torque plus a_k
// qdd_k: the model without armature, and the definition, against the model with it.
TEST(Armature, AddsToMassMatrixDiagonalAndTorques) {
  for (const bool floating_base : {false, true}) {
    gen::LoadOptions options;
    options.floating_base = floating_base;
    Dynamics<double> bare(gen::load_robot(test::model_path("ur5.urdf"), options).model);
    options.armature = {{"all", 0.05}, {"elbow_joint", 0.3}};
    Dynamics<double> geared(gen::load_robot(test::model_path("ur5.urdf"), options).model);
    const std::vector<double>& armature = geared.model().armature;
    ASSERT_EQ(armature.size(), static_cast<std::size_t>(geared.nv()));
    const int first = floating_base ? 6 : 0;  // the free joint has none
    for (int k = 0; k < geared.nv(); ++k)
      EXPECT_EQ(armature[k], k < first ? 0 : k == first + 2 ? 0.3 : 0.05) << k;
    const Vector a = test::to_eigen(armature);
    test::Random rng(20261128);
    for (int n = 0; n < 10; ++n) {
      const test::State s = test::random_state(geared.model(), rng);
      const Vector q = test::to_eigen(s.q), qd = test::to_eigen(s.qd), qdd = test::to_eigen(s.qdd);
      const Matrix M = bare.crba(q);
      const Matrix M_geared = geared.crba(q);
      EXPECT_LE(max_abs(M_geared - M - Matrix(a.asDiagonal())), 4 * eps * max_abs(M_geared));
      const Vector tau = geared.rnea(q, qd, qdd);
      EXPECT_LE(max_abs(tau - bare.rnea(q, qd, qdd) - a.cwiseProduct(qdd)),
                64 * eps * (max_abs(tau) + max_abs(M_geared) * max_abs(qdd)));
      // ABA's pivots with armature give the same accelerations as M with it
      const Vector qdd_dense = M_geared.ldlt().solve(tau - geared.nle(q, qd));
      EXPECT_LE(max_abs(geared.aba(q, qd, tau) - qdd_dense), 1e-9 * max_abs(qdd_dense));
    }
  }
}

TEST(LongDouble, DoubleAgreesWithinRoundingBounds) {
  static_assert(std::numeric_limits<long double>::digits > std::numeric_limits<double>::digits);
  const std::pair<std::string, Model<double>> models[] = {
      {"ur5", gen::load_robot(test::model_path("ur5.urdf")).model},
      {"planar5", gen::load_robot(test::model_path("planar5.yaml")).model},
      {"spatial_chain_12", test::make_random_chain(12, 77, false)}};
  for (const auto& [name, model] : models) {
    Dynamics<double> dyn(model);
    Dynamics<long double> ref(model.cast<long double>());
    test::Random rng(11);
    const int n = dyn.nv();
    double rnea_err = 0, crba_err = 0, aba_err = 0;
    for (int k = 0; k < states_per_model; ++k) {
      const Sample x = sample(dyn, rng);
      const VectorX<long double> q = x.q.cast<long double>(), qd = x.qd.cast<long double>();
      // each error in units of n eps times the scale that bounds it (see Sample::qdd_scale)
      const double tau_scale = x.lambda_max * x.qdd.cwiseAbs().maxCoeff() + max_abs(x.bias);
      const Vector tau_ref = ref.rnea(q, qd, x.qdd.cast<long double>()).cast<double>();
      rnea_err = worse(rnea_err, max_abs(dyn.rnea(x.q, x.qd, x.qdd) - tau_ref) / tau_scale);
      const Matrix M_ref = ref.crba(q).cast<double>();
      crba_err = worse(crba_err, max_abs(x.M - M_ref) / max_abs(M_ref));
      const Vector qdd_ref = ref.aba(q, qd, x.tau.cast<long double>()).cast<double>();
      Sample forward = x;
      forward.qdd = qdd_ref;
      aba_err = worse(aba_err, max_abs(dyn.aba(x.q, x.qd, x.tau) - qdd_ref) / forward.qdd_scale());
    }
    std::cout << "[ measured ] " << name << " (n = " << n << "): error / (n eps scale): rnea "
              << rnea_err / (n * eps) << ", crba " << crba_err / (n * eps) << ", aba "
              << aba_err / (n * eps) << "\n";
    // measured: at most 0.4 for rnea and crba, 0.002 for aba
    EXPECT_LE(rnea_err, 2 * n * eps) << name;
    EXPECT_LE(crba_err, 2 * n * eps) << name;
    EXPECT_LE(aba_err, 2 * n * eps) << name;
  }
}

// ---- closed-form oracles --------------------------------------------------------------------

/// Within 64 eps times the scale of the quantity: the oracles and the algorithms are a few
/// dozen operations on numbers of that size.
void expect_close(const Matrix& actual, const Matrix& expected, double scale,
                  const std::string& what) {
  EXPECT_LE(max_abs(actual - expected), 64 * eps * scale) << what << "\nactual\n"
                                                          << actual << "\nexpected\n"
                                                          << expected;
}

/// Checks M, g, tau = M qdd + C qd + g and ABA's qdd against the oracle's. Rounding errors in
/// tau are relative to its terms' sizes; in qdd they are those divided by lambda_min(M).
void expect_dynamics(Dynamics<double>& dyn, const Vector& q, const Vector& qd, const Vector& qdd,
                     const Matrix& M, const Vector& coriolis, const Vector& gravity) {
  const Vector zero = Vector::Zero(dyn.nv());
  expect_close(dyn.crba(q), M, max_abs(M), "M");
  expect_close(dyn.rnea(q, zero, zero), gravity, max_abs(gravity), "g");
  const Vector tau = M * qdd + coriolis + gravity;
  const double tau_scale = max_abs(M) * max_abs(qdd) + max_abs(coriolis) + max_abs(gravity);
  expect_close(dyn.rnea(q, qd, qdd), tau, tau_scale, "tau");
  const double lambda_min = Eigen::SelfAdjointEigenSolver<Matrix>(M).eigenvalues().minCoeff();
  expect_close(dyn.aba(q, qd, tau), qdd, tau_scale / lambda_min, "qdd");
}

TEST(ClosedForm, TwoLinkPlanarArm) {
  // Spong, Hutchinson & Vidyasagar, "Robot Modeling and Control", sec. 7.4.1: links along x,
  // joints about z, centres of mass at lc1 and lc2 (not half the lengths), gravity along -y.
  const double l1 = 0.8, lc1 = 0.3, m1 = 1.5, I1 = 0.09;
  const double lc2 = 0.42, m2 = 0.8, I2 = 0.03;  // the length of link 2 plays no part
  const double g = 9.81;
  ModelBuilder builder;
  builder.add_link({.name = "base", .com = {}, .I_com = {}});
  builder.add_link({.name = "upper", .mass = m1, .com = {lc1, 0, 0}, .I_com = {0.001, I1, I1}});
  builder.add_link({.name = "fore", .mass = m2, .com = {lc2, 0, 0}, .I_com = {0.002, I2, I2}});
  builder.add_joint({.name = "shoulder",
                     .kind = JointKind::Revolute,
                     .parent = "base",
                     .child = "upper",
                     .xyz = {},
                     .axis = {0, 0, 1}});
  builder.add_joint({.name = "elbow",
                     .kind = JointKind::Revolute,
                     .parent = "upper",
                     .child = "fore",
                     .xyz = {l1, 0, 0},
                     .axis = {0, 0, 1}});
  Dynamics<double> dyn(builder.build({0, -g, 0}));

  test::Random rng(21);
  for (int k = 0; k < states_per_model; ++k) {
    const Vector q = test::to_eigen(rng.vector(2, -3.2, 3.2));
    const Vector qd = test::to_eigen(rng.vector(2, -2, 2));
    const Vector qdd = test::to_eigen(rng.vector(2, -2, 2));
    const double c2 = std::cos(q[1]);
    Matrix M(2, 2);
    M(0, 0) = m1 * lc1 * lc1 + m2 * (l1 * l1 + lc2 * lc2 + 2 * l1 * lc2 * c2) + I1 + I2;
    M(0, 1) = M(1, 0) = m2 * (lc2 * lc2 + l1 * lc2 * c2) + I2;
    M(1, 1) = m2 * lc2 * lc2 + I2;
    const double h = -m2 * l1 * lc2 * std::sin(q[1]);
    const Vector coriolis{{h * qd[1] * qd[1] + 2 * h * qd[0] * qd[1], -h * qd[0] * qd[0]}};
    const double g12 = m2 * lc2 * g * std::cos(q[0] + q[1]);
    const Vector gravity{{(m1 * lc1 + m2 * l1) * g * std::cos(q[0]) + g12, g12}};
    expect_dynamics(dyn, q, qd, qdd, M, coriolis, gravity);
  }
}

/// The position of R(angle) a in the plane of a rotation about x, (y, z) coordinates.
Eigen::Vector2d rotate(double angle, const Eigen::Vector2d& a) {
  return Eigen::Rotation2Dd(angle) * a;
}

/// d/d angle of R(angle) a.
Eigen::Vector2d rotate_d(double angle, const Eigen::Vector2d& a) {
  return Eigen::Rotation2Dd(angle + std::numbers::pi / 2) * a;
}

TEST(ClosedForm, DoublePendulumUrdf) {
  // Both joints of double_pendulum.urdf turn about parallel x axes, so the dynamics are those
  // of a planar two-link arm in the y-z plane (offsets along x do not matter). With J_i the
  // moment of inertia about the joint axis, c_i the centres of mass and l the elbow's offset
  // in (y, z) coordinates, and A = l . R(q2) c2:
  //   M11 = J1 + J2 + m2 (|l|^2 + 2 A), M12 = J2 + m2 A, M22 = J2, h = m2 dA/dq2,
  //   tau1 += h (qd2^2 + 2 qd1 qd2), tau2 -= h qd1^2 (Christoffel symbols of M),
  //   g = dV/dq with V = 9.81 (m1 z1 + m2 z2). Inputs from the URDF's <inertial> and <origin>.
  const double m1 = 0.26703, Ixx1 = 0.00040827, m2 = 0.33238, Ixx2 = 0.0011753;
  const Eigen::Vector2d c1(2.1727E-06, 0.036012), c2(1.9371E-10, 0.10088), l(0, 0.1);
  const double J1 = Ixx1 + m1 * c1.squaredNorm(), J2 = Ixx2 + m2 * c2.squaredNorm();
  const double g = 9.81;
  Dynamics<double> dyn(gen::load_robot(test::model_path("double_pendulum.urdf")).model);
  ASSERT_EQ(dyn.nv(), 2);

  test::Random rng(22);
  for (int k = 0; k < states_per_model; ++k) {
    const Vector q = test::to_eigen(rng.vector(2, -3.2, 3.2));
    const Vector qd = test::to_eigen(rng.vector(2, -2, 2));
    const Vector qdd = test::to_eigen(rng.vector(2, -2, 2));
    const double A = l.dot(rotate(q[1], c2)), h = m2 * l.dot(rotate_d(q[1], c2));
    Matrix M(2, 2);
    M << J1 + J2 + m2 * (l.squaredNorm() + 2 * A), J2 + m2 * A, J2 + m2 * A, J2;
    const Vector coriolis{{h * (qd[1] * qd[1] + 2 * qd[0] * qd[1]), -h * qd[0] * qd[0]}};
    const double dz2 = m2 * rotate_d(q[0] + q[1], c2).y();
    const Vector gravity{
        {g * (m1 * rotate_d(q[0], c1).y() + m2 * rotate_d(q[0], l).y() + dz2), g * dz2}};
    expect_dynamics(dyn, q, qd, qdd, M, coriolis, gravity);
  }
}

TEST(ClosedForm, FreePrismaticJoint) {
  // One body sliding along a unit axis k (world direction R k): M = m, no velocity terms, and
  // g = -m gravity . R k, whatever q, qd and the body's rotational inertia.
  test::Random rng(23);
  for (int k = 0; k < 50; ++k) {
    const Eigen::Vector3d axis =
        Eigen::Vector3d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)).normalized();
    const Eigen::Matrix3d R = Eigen::Quaterniond(rng.uniform(-1, 1), rng.uniform(-1, 1),
                                                 rng.uniform(-1, 1), rng.uniform(-1, 1))
                                  .normalized()
                                  .toRotationMatrix();
    const double m = rng.uniform(0.1, 10);
    ModelBuilder builder;
    builder.add_link({.name = "base", .com = {}, .I_com = {}});
    builder.add_link({.name = "slider",
                      .mass = m,
                      .com = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)},
                      .I_com = {0.3, 0.2, 0.4, 0.01, -0.02, 0.03}});
    builder.add_joint(
        {.name = "slide",
         .kind = JointKind::Prismatic,
         .parent = "base",
         .child = "slider",
         .xyz = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)},
         .R = {R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)},
         .axis = {axis.x(), axis.y(), axis.z()}});
    const Eigen::Vector3d gravity(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10));
    Dynamics<double> dyn(builder.build({gravity.x(), gravity.y(), gravity.z()}));
    const Vector q{{rng.uniform(-3, 3)}}, qd{{rng.uniform(-3, 3)}}, qdd{{rng.uniform(-3, 3)}};
    const double g_axis = gravity.dot(R * axis);
    expect_dynamics(dyn, q, qd, qdd, Matrix::Constant(1, 1, m), Vector::Zero(1),
                    Vector::Constant(1, -m * g_axis));
  }
}

// ---- a robot without a defined ABA ----------------------------------------------------------

TEST(Romeo, UnlockedMassMatrixHasExactZeroColumns) {
  // romeo's hands have no mass: the column of each joint whose subtree is massless is exactly
  // zero, so M is singular; lock_massless removes exactly those joints (24, README.md).
  gen::LoadOptions options;
  options.mimic_independent = true;
  const Model<double> model = gen::load_robot(test::model_path("romeo.urdf"), options).model;
  std::vector<bool> massless(model.nbodies, true);
  for (int i = model.nbodies - 1; i >= 0; --i) {
    const RigidInertia<double>& I = model.I[i];
    const bool own_mass = I.m != 0 || I.h.x != 0 || I.h.y != 0 || I.h.z != 0 || I.I.xx != 0 ||
                          I.I.yy != 0 || I.I.zz != 0 || I.I.xy != 0 || I.I.xz != 0 || I.I.yz != 0;
    massless[i] = massless[i] && !own_mass;
    if (!massless[i] && model.parent[i] >= 0) massless[model.parent[i]] = false;
  }
  Dynamics<double> dyn(model);
  test::Random rng(24);
  const Matrix M = dyn.crba(test::to_eigen(rng.vector(model.nv, -3, 3)));
  int zero_columns = 0;
  for (int i = 0; i < model.nbodies; ++i) {
    const int k = model.v_index[i];
    if (massless[i]) {
      ++zero_columns;
      EXPECT_EQ(max_abs(M.col(k)), 0.0) << model.joint_name[i];
    } else {
      EXPECT_GT(M(k, k), 0.0) << model.joint_name[i];
    }
  }
  EXPECT_EQ(zero_columns, 24);
  options.lock_massless = true;
  EXPECT_EQ(gen::load_robot(test::model_path("romeo.urdf"), options).model.nv, model.nv - 24);
}

TEST(AlgorithmTable, NamesAndArraysAreConsistent) {
  // the generator puts trig after q and the check draws each array by its name: every entry
  // reads q first, names are unique, and an array's name fixes its extent
  std::map<std::string_view, Extent> extent;
  std::set<std::string_view> names;
  for (const AlgorithmSpec<double>& a : algorithm_table<double>()) {
    EXPECT_TRUE(names.insert(a.name).second) << a.name;
    ASSERT_FALSE(a.inputs.empty()) << a.name;
    EXPECT_EQ(a.inputs.front().name, "q") << a.name;
    EXPECT_FALSE(a.outputs.empty()) << a.name;
    std::vector<ArraySpec> arrays = a.inputs;
    arrays.insert(arrays.end(), a.outputs.begin(), a.outputs.end());
    std::set<std::string_view> in_signature;
    for (const ArraySpec& x : arrays) {
      EXPECT_TRUE(in_signature.insert(x.name).second) << a.name << " takes " << x.name << " twice";
      const auto [it, added] = extent.emplace(x.name, x.extent);
      EXPECT_EQ(it->second, x.extent) << a.name << ": " << x.name;
    }
  }
}

// the CRBA+LDLT variant of dyngen report and bench/'s peers call the entry of each of the three
// Computes with a fixed signature; the default set is the three of them
TEST(AlgorithmTable, EachComputesHasOneEntryWithItsSignature) {
  const auto names = [](const std::vector<ArraySpec>& arrays) {
    std::vector<std::string_view> out;
    for (const ArraySpec& x : arrays) out.push_back(x.name);
    return out;
  };
  using Names = std::vector<std::string_view>;
  const std::map<Computes, std::pair<Names, Names>> signature{
      {Computes::InverseDynamics, {{"q", "v", "a"}, {"tau"}}},
      {Computes::MassMatrix, {{"q"}, {"M"}}},
      {Computes::ForwardDynamics, {{"q", "v", "tau"}, {"qdd"}}}};
  std::map<Computes, int> count;
  Names in_default_set;
  for (const AlgorithmSpec<double>& a : algorithm_table<double>()) {
    if (a.in_default_set) in_default_set.push_back(a.name);
    if (a.computes == Computes::Other) continue;
    ++count[a.computes];
    EXPECT_EQ(find_algorithm<double>(a.computes), &a) << a.name;
    EXPECT_EQ(names(a.inputs), signature.at(a.computes).first) << a.name;
    EXPECT_EQ(names(a.outputs), signature.at(a.computes).second) << a.name;
    EXPECT_FALSE(a.title.empty()) << a.name;
  }
  EXPECT_EQ(count, (std::map<Computes, int>{{Computes::InverseDynamics, 1},
                                            {Computes::MassMatrix, 1},
                                            {Computes::ForwardDynamics, 1}}));
  EXPECT_EQ(in_default_set, (Names{"rnea", "crba", "aba"}));
  EXPECT_EQ(find_algorithm<double>(Computes::Other), nullptr);
}

}  // namespace
}  // namespace dyngen
