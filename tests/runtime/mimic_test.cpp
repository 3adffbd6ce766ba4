// Mimic joints (Model::mimic) against the same robot with every joint independent, driven by the
// mimic law: with q_joints = G q + offset and G the map from the coordinates to the joints,
// tau = G^T tau_joints(q_joints, G v, G a), M = G^T M_joints G, the frames' Jacobians J_joints G,
// and forward dynamics and M^-1 (by the factorised M) invert them. On the shared robots whose
// grippers and hands have URDF <mimic> joints, and on coverage/mimic_gripper.urdf, whose mimic
// joints have multipliers other than 1 and offsets, one below its primary.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>

#include "dyngen/dyngen.hpp"
#include "readers.hpp"
#include "robot.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

using Matrix = Eigen::MatrixXd;
using Vector = Eigen::VectorXd;
constexpr double eps = std::numeric_limits<double>::epsilon();

struct Pair {
  Model<double> coupled, joints;  // with mimic joints, and each joint independent
};

Pair load(const std::string& file, bool floating_base) {
  const std::string path = test::model_path(file);
  const std::string text = gen::read_file(path);
  gen::RobotDescription description = gen::reader_for(path, text).parse(path, text);
  const Vec3<double> g{0, 0, -9.81};
  Pair pair;
  pair.joints = description.builder.build(g, floating_base);
  for (const gen::RobotDescription::Mimic& m : description.mimics)
    description.builder.set_mimic(m.joint, m.mimicked, m.multiplier, m.offset);
  pair.coupled = description.builder.build(g, floating_base);
  return pair;
}

/// G: d q_joints / d q, and the offsets, from the coupled model's mimic law
Matrix coupling(const Pair& p) {
  Matrix G = Matrix::Zero(p.joints.nv, p.coupled.nv);
  for (int i = 0; i < p.coupled.nbodies; ++i)
    for (int d = 0; d < joint_nv(p.coupled.joint_type[i]); ++d)
      G(p.joints.v_index[i] + d, p.coupled.v_index[i] + d) =
          is_mimic(p.coupled, i) ? p.coupled.mimic_multiplier[i] : 1.0;
  return G;
}

/// q_joints from q (1-DoF and free joints alike: a mimic joint's entry by its law)
std::vector<double> joint_positions(const Pair& p, const std::vector<double>& q) {
  std::vector<double> x(p.joints.nq);
  for (int i = 0; i < p.coupled.nbodies; ++i)
    for (int e = 0; e < joint_nq(p.coupled.joint_type[i]); ++e) {
      const double qi = q[p.coupled.q_index[i] + e];
      x[p.joints.q_index[i] + e] = is_mimic(p.coupled, i)
                                       ? p.coupled.mimic_multiplier[i] * qi + p.coupled.mimic_offset[i]
                                       : qi;
    }
  return x;
}

std::vector<double> std_vector(const Vector& x) { return {x.data(), x.data() + x.size()}; }

double relative(const Matrix& a, const Matrix& b) { return (a - b).norm() / b.norm(); }

class Mimic : public ::testing::TestWithParam<std::pair<const char*, bool>> {};

TEST_P(Mimic, AlgorithmsAreTheIndependentJointsUnderTheMimicLaw) {
  const Pair p = load(GetParam().first, GetParam().second);
  ASSERT_FALSE(p.coupled.mimic.empty());
  ASSERT_LT(p.coupled.nv, p.joints.nv);
  const int n = p.coupled.nv, nf = p.joints.nv;
  const Matrix G = coupling(p);
  Workspace<double> ws(p.coupled), wsf(p.joints);
  test::Random rng(42);
  double worst_tau = 0, worst_M = 0, worst_g = 0, worst_qdd = 0, worst_minv = 0, worst_J = 0;
  std::vector<double> tau(n), M(n * n), g(n), qdd(n), Minv(n * n), Mf(nf * nf), tauf(nf), gf(nf);
  const std::size_t frames = p.coupled.frames.size();
  std::vector<double> J(6 * n * frames), Jf(6 * nf * frames);
  for (int sample = 0; sample < 10; ++sample) {
    const test::State s = test::random_state(p.coupled, rng);
    const std::vector<double> qf = joint_positions(p, s.q);
    const std::vector<double> vf = std_vector(G * test::to_eigen(s.qd)),
                              af = std_vector(G * test::to_eigen(s.qdd));
    rnea<double>(p.coupled, ws, s.q, s.qd, s.qdd, tau);
    rnea<double>(p.joints, wsf, qf, vf, af, tauf);
    const Vector tau_ref = G.transpose() * test::to_eigen(tauf);
    worst_tau = std::max(worst_tau, relative(test::to_eigen(tau), tau_ref));
    crba<double>(p.coupled, ws, s.q, M);
    crba<double>(p.joints, wsf, qf, Mf);
    const Matrix M_ref = G.transpose() * test::to_eigen(Mf, nf) * G;
    worst_M = std::max(worst_M, relative(test::to_eigen(M, n), M_ref));
    gravity<double>(p.coupled, ws, s.q, g);
    gravity<double>(p.joints, wsf, qf, gf);
    worst_g = std::max(worst_g, relative(test::to_eigen(g), G.transpose() * test::to_eigen(gf)));
    // forward dynamics: the round trip through RNEA, and M^-1 against M
    aba<double>(p.coupled, ws, s.q, s.qd, s.tau, qdd);
    rnea<double>(p.coupled, ws, s.q, s.qd, qdd, tau);
    worst_qdd = std::max(worst_qdd, relative(test::to_eigen(tau), test::to_eigen(s.tau)));
    minv<double>(p.coupled, ws, s.q, Minv);
    worst_minv = std::max(worst_minv, (test::to_eigen(Minv, n) * M_ref - Matrix::Identity(n, n))
                                          .cwiseAbs().maxCoeff());
    frame_jacobians<double>(p.coupled, ws, s.q, JacobianAxes::World, J);
    frame_jacobians<double>(p.joints, wsf, qf, JacobianAxes::World, Jf);
    const Matrix Jc = Eigen::Map<const Matrix>(J.data(), n, 6 * frames);   // J^T, column-major
    const Matrix Jj = Eigen::Map<const Matrix>(Jf.data(), nf, 6 * frames);
    worst_J = std::max(worst_J, relative(Jc, G.transpose() * Jj));
    // the centre of mass's and the centroidal momentum's Jacobians, 3 and 6 rows
    std::vector<double> c(3), Jcom(3 * n), Jcomf(3 * nf), A(6 * n), Af(6 * nf), h(6), hf(6);
    com<double>(p.coupled, ws, s.q, c, Jcom);
    com<double>(p.joints, wsf, qf, c, Jcomf);
    worst_J = std::max(worst_J, relative(Eigen::Map<const Matrix>(Jcom.data(), n, 3),
                                         G.transpose() * Eigen::Map<const Matrix>(Jcomf.data(), nf, 3)));
    centroidal<double>(p.coupled, ws, s.q, s.qd, A, h);
    centroidal<double>(p.joints, wsf, qf, vf, Af, hf);
    worst_J = std::max(worst_J, relative(Eigen::Map<const Matrix>(A.data(), n, 6),
                                         G.transpose() * Eigen::Map<const Matrix>(Af.data(), nf, 6)));
    worst_J = std::max(worst_J, relative(test::to_eigen(h), test::to_eigen(hf)));
  }
  std::cout << "[ measured ] " << GetParam().first << (GetParam().second ? " floating" : "")
            << " (nv " << n << " of " << nf << "): tau " << worst_tau << ", M " << worst_M
            << ", g " << worst_g << ", J, Jc, Ag, hg " << worst_J << ", aba round trip " << worst_qdd
            << ", |Minv M - 1| " << worst_minv << "\n";
  // sums in another order: rounding of the largest terms, a few hundred eps at most
  EXPECT_LE(worst_tau, 1e3 * eps);
  EXPECT_LE(worst_M, 1e3 * eps);
  EXPECT_LE(worst_g, 1e3 * eps);
  EXPECT_LE(worst_J, 1e3 * eps);
  EXPECT_LE(worst_qdd, 1e-9);
  EXPECT_LE(worst_minv, 1e-9);
}

// d tau / d(q, v) = G^T d tau_joints / d(q, v)_joints G by the chain rule; rnea_derivatives
// computes it so, and the independent check is aba_derivatives (built on it) against central
// differences of aba along integrate and v. With h = 1e-6 their truncation (h^2) and rounding
// (eps / h times cond(M)) stay below 1e-5: measured at most 2.3e-6 (mimic_gripper floating,
// whose base link is massless); a wrong term is off by O(1).
TEST_P(Mimic, DerivativesAreTheChainRuleOfTheJointsAndOfAba) {
  const Pair p = load(GetParam().first, GetParam().second);
  const int n = p.coupled.nv, nf = p.joints.nv;
  const Matrix G = coupling(p);
  Workspace<double> ws(p.coupled), wsf(p.joints);
  test::Random rng(7);
  const test::State s = test::random_state(p.coupled, rng);
  const std::vector<double> qf = joint_positions(p, s.q);
  const std::vector<double> vf = std_vector(G * test::to_eigen(s.qd)),
                            af = std_vector(G * test::to_eigen(s.qdd));
  std::vector<double> dq(n * n), dv(n * n), dqf(nf * nf), dvf(nf * nf);
  rnea_derivatives<double>(p.coupled, ws, s.q, s.qd, s.qdd, dq, dv);
  rnea_derivatives<double>(p.joints, wsf, qf, vf, af, dqf, dvf);
  const double rnea_error =
      std::max(relative(test::to_eigen(dq, n), G.transpose() * test::to_eigen(dqf, nf) * G),
               relative(test::to_eigen(dv, n), G.transpose() * test::to_eigen(dvf, nf) * G));
  // aba_derivatives against central differences of aba along integrate and v
  std::vector<double> Dq(n * n), Dv(n * n), Minv(n * n), plus(n), minus(n), qp(p.coupled.nq),
      qm(p.coupled.nq), d(n, 0.0);
  aba_derivatives<double>(p.coupled, ws, s.q, s.qd, s.tau, Dq, Dv, Minv);
  const double h = 1e-6;
  Matrix fq(n, n), fv(n, n);
  for (int c = 0; c < n; ++c) {
    d.assign(n, 0.0);
    d[c] = h;
    integrate<double>(p.coupled, s.q, d, qp);
    d[c] = -h;
    integrate<double>(p.coupled, s.q, d, qm);
    aba<double>(p.coupled, ws, qp, s.qd, s.tau, plus);
    aba<double>(p.coupled, ws, qm, s.qd, s.tau, minus);
    fq.col(c) = (test::to_eigen(plus) - test::to_eigen(minus)) / (2 * h);
    std::vector<double> vp = s.qd, vm = s.qd;
    vp[c] += h, vm[c] -= h;
    aba<double>(p.coupled, ws, s.q, vp, s.tau, plus);
    aba<double>(p.coupled, ws, s.q, vm, s.tau, minus);
    fv.col(c) = (test::to_eigen(plus) - test::to_eigen(minus)) / (2 * h);
  }
  const double aba_error =
      std::max(relative(test::to_eigen(Dq, n), fq), relative(test::to_eigen(Dv, n), fv));
  std::cout << "[ measured ] " << GetParam().first << (GetParam().second ? " floating" : "")
            << ": rnea_derivatives vs G^T d G " << rnea_error
            << ", aba_derivatives vs central differences " << aba_error << "\n";
  EXPECT_LE(rnea_error, 1e3 * eps);
  EXPECT_LE(aba_error, 1e-5);
}

INSTANTIATE_TEST_SUITE_P(Robots, Mimic,
                         ::testing::Values(std::pair{"coverage/mimic_gripper.urdf", false},
                                           std::pair{"coverage/mimic_gripper.urdf", true},
                                           std::pair{"coverage/mimic_mirror.urdf", false},
                                           std::pair{"coverage/parallel_gripper.urdf", false},
                                           std::pair{"coverage/parallel_gripper.urdf", true},
                                           std::pair{"panda.urdf", false},
                                           std::pair{"panda.urdf", true},
                                           std::pair{"pr2.urdf", false},
                                           std::pair{"baxter.urdf", false}),
                         [](const auto& info) {
                           return test::case_name(info.param.first, info.param.second);
                         });

}  // namespace
}  // namespace dyngen
