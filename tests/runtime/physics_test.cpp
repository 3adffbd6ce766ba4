// Physics identities (after RigidBodyDynamics.jl's tests): the kinetic energy 1/2 qd^T M qd
// equals the bodies' kinetic energies summed, and along a trajectory the rate of change of
// kinetic plus potential energy equals the power tau . qd of the joint forces. Body poses and
// velocities are computed here from the joint transforms, with 3-vector kinematics in world
// coordinates, independently of the algorithms' recursions and workspaces.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>

#include "dyngen/dyngen.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

using Vector = Eigen::VectorXd;
using Vector3 = Eigen::Vector3d;
using Matrix3 = Eigen::Matrix3d;
using test::dense;
using test::view;

constexpr double eps = std::numeric_limits<double>::epsilon();

/// Energies from world-frame kinematics: body i's rotation R_i (body to world) and origin p_i
/// compose its joint transform's E and r with its parent's (R_i = R_p E^T, p_i = p_p + R_p r);
/// angular velocities add the joint's S qd in world coordinates, origin velocities add
/// w_p x (p_i - p_p) as well.
class Energy {
 public:
  explicit Energy(const Model<double>& model)
      : model_(model), R_(model.nbodies), p_(model.nbodies), w_(model.nbodies), v_(model.nbodies) {}

  /// Sum over bodies of 1/2 v_i^T I_i v_i, written with (m, h, I) in body coordinates:
  /// 1/2 (w . I w + 2 v . (w x h) + m v . v), and over degrees of freedom of 1/2 armature qd^2.
  double kinetic(const Vector& q, const Vector& qd) {
    kinematics(q, qd);
    double T = 0;
    for (int i = 0; i < model_.nbodies; ++i) {
      const RigidInertia<double>& I = model_.I[i];
      const Vector3 w = R_[i].transpose() * w_[i], v = R_[i].transpose() * v_[i];
      T += 0.5 * (w.dot(dense(I.I) * w) + 2 * v.dot(w.cross(dense(I.h))) + I.m * v.dot(v));
    }
    // the rotors', spinning at their joint's rate
    for (std::size_t k = 0; k < model_.armature.size(); ++k) {
      const double rate = qd[static_cast<Eigen::Index>(k)];
      T += 0.5 * model_.armature[k] * rate * rate;
    }
    return T;
  }

  /// -sum over bodies of m_i gravity . c_i, with m c = m p + R h in world coordinates.
  double potential(const Vector& q) {
    kinematics(q, Vector::Zero(model_.nv));
    double V = 0;
    for (int i = 0; i < model_.nbodies; ++i)
      V -= dense(model_.gravity).dot(model_.I[i].m * p_[i] + R_[i] * dense(model_.I[i].h));
    return V;
  }

 private:
  void kinematics(const Vector& q, const Vector& qd) {
    for (int i = 0; i < model_.nbodies; ++i) {
      const int parent = model_.parent[i];
      const Matrix3 R_p = parent < 0 ? Matrix3::Identity() : R_[parent];
      const Vector3 p_p = parent < 0 ? Vector3::Zero() : p_[parent];
      const Vector3 w_p = parent < 0 ? Vector3::Zero() : w_[parent];
      const Vector3 v_p = parent < 0 ? Vector3::Zero() : v_[parent];
      const Xform<double> X = joint_transform(model_, i, &q[model_.q_index[i]]);
      R_[i] = R_p * dense(X.E).transpose();
      p_[i] = p_p + R_p * dense(X.r);
      const Motion<double> S_qd = joint_motion(model_, i, &qd[model_.v_index[i]]);
      w_[i] = w_p + R_[i] * dense(S_qd.ang);
      v_[i] = v_p + w_p.cross(p_[i] - p_p) + R_[i] * dense(S_qd.lin);
    }
  }

  const Model<double>& model_;
  std::vector<Matrix3> R_;
  std::vector<Vector3> p_, w_, v_;
};

struct Case {
  std::string name;
  std::function<Model<double>()> make;
};

/// Every shared robot (with romeo's massless joints locked, which ABA needs), fixed and
/// floating, the documented five-link case and random chains.
std::vector<Case> cases() {
  std::vector<Case> all;
  for (const test::RobotFile& robot : test::robot_files()) {
    all.push_back({robot.name, [=] { return test::load_for_aba(robot); }});
    all.push_back({robot.name + "_floating", [=] { return test::load_for_aba(robot, true); }});
  }
  all.push_back(
      {"planar5", [] { return gen::load_robot(test::model_path("planar5.yaml")).model; }});
  all.push_back({"all_joints", [] {
                   return gen::load_robot(test::model_path("coverage/all_joints.urdf")).model;
                 }});
  all.push_back({"ball_chain", [] { return test::load_model("coverage/ball_chain.yaml"); }});
  all.push_back({"planar_chain_12", [] { return test::make_random_chain(12, 31, true); }});
  all.push_back({"spatial_chain_12", [] { return test::make_random_chain(12, 32, false); }});
  return all;
}

class Physics : public ::testing::TestWithParam<Case> {
 protected:
  void report(const char* what, double value) const {
    std::cout << "[ measured ] " << GetParam().name << ": " << what << " " << value << "\n";
  }
};

TEST_P(Physics, KineticEnergyIsHalfQdTransposeMQd) {
  const Model<double> model = GetParam().make();
  const int n = model.nv;
  Workspace<double> ws(model);
  Energy energy(model);
  test::Random rng(41);
  std::vector<double> M(n * n);
  double worst = 0;
  for (int k = 0; k < 20; ++k) {
    const test::State s = test::random_state(model, rng);
    crba<double>(model, ws, s.q, M);
    const Eigen::MatrixXd Md = test::to_eigen(M, n);
    const Vector qd = test::to_eigen(s.qd);
    const double T = 0.5 * qd.dot(Md * qd);
    // each side sums n^2 terms bounded by |qd|^T |M| |qd|
    const double scale = qd.cwiseAbs().dot(Md.cwiseAbs() * qd.cwiseAbs());
    const double T_bodies = energy.kinetic(test::to_eigen(s.q), qd);
    ASSERT_TRUE(std::isfinite(T) && std::isfinite(T_bodies));
    worst = std::max(worst, std::abs(T_bodies - T) / (n * eps * scale));
  }
  report("kinetic energy error / (n eps |qd|^T |M| |qd|)", worst);
  EXPECT_LE(worst, 4.0);
}

TEST_P(Physics, RuntimeEnergiesMatchWorldKinematics) {
  const Model<double> model = GetParam().make();
  Workspace<double> ws(model);
  Energy energy(model);
  test::Random rng(44);
  double worst = 0;
  for (int k = 0; k < 20; ++k) {
    const test::State s = test::random_state(model, rng);
    forward_kinematics<double>(model, ws, s.q, s.qd);
    const double T = kinetic_energy<double>(model, ws, s.qd), V = potential_energy(model, ws);
    const double T_ref = energy.kinetic(test::to_eigen(s.q), test::to_eigen(s.qd));
    const double V_ref = energy.potential(test::to_eigen(s.q));
    worst = std::max(worst, (std::abs(T - T_ref) + std::abs(V - V_ref)) /
                                (model.nbodies * 4 * eps * (std::abs(T_ref) + std::abs(V_ref))));
  }
  report("runtime energies vs world kinematics / (4 n eps (|T| + |V|))", worst);
  EXPECT_LE(worst, 1.0);
}

// Finite differences below (Pinocchio's choice, STYLE.md B4): central differences with
// h = 1e-8 and a tolerance of sqrt(h) = 1e-4 relative to the energies' scale. The truncation
// error is h^2 |d3E/dt3| ~ 1e-16; the rounding of E (about eps |E|), of the stepped state and
// of the ABA calls, divided by 2h, is about 1e-8 of the scale; so sqrt(h) leaves four orders of
// magnitude to spare, while a missing or mis-signed term is off by a large fraction of it.
constexpr double fd_h = 1e-8;
constexpr double fd_tol = 1e-4;

/// q moved by dt along velocity v: q + dt qdot(q, v), back on unit quaternions. A smooth curve
/// through q with tangent v, which is all that central differences and RK4 need.
Vector step(const Model<double>& model, const Vector& q, const Vector& v, double dt) {
  Vector qdot(model.nq);
  configuration_rate<double>(model, view(q), view(v), view(qdot));
  Vector out = q + dt * qdot;
  normalize_configuration<double>(model, view(out));
  return out;
}

TEST_P(Physics, GravityTorqueIsPotentialGradient) {
  // gravity(q) = dV/dq along each velocity direction
  const Model<double> model = GetParam().make();
  const int n = model.nv;
  Workspace<double> ws(model);
  Energy energy(model);
  test::Random rng(42);
  std::vector<double> g(n);
  double worst = 0;
  for (int k = 0; k < 5; ++k) {
    const Vector q = test::to_eigen(test::random_state(model, rng).q);
    gravity<double>(model, ws, view(q), g);
    ASSERT_TRUE(test::to_eigen(g).allFinite());
    // |V| bounds the rounding of V; |g| the size of the gradient
    const double scale = std::abs(energy.potential(q)) + test::to_eigen(g).cwiseAbs().maxCoeff();
    for (int j = 0; j < n; ++j) {
      const Vector e = Vector::Unit(n, j);
      const double dV = (energy.potential(step(model, q, e, fd_h)) -
                         energy.potential(step(model, q, e, -fd_h))) /
                        (2 * fd_h);
      ASSERT_TRUE(std::isfinite(dV)) << "joint " << j;
      worst = std::max(worst, std::abs(dV - g[j]) / scale);
    }
  }
  report("|dV/dq - g| / (|V| + |g|)", worst);
  EXPECT_LE(worst, fd_tol);
}

TEST_P(Physics, PowerIsRateOfChangeOfEnergy) {
  // Along a trajectory of ABA under a constant tau and gravity, integrated with RK4:
  // d/dt (T + V) = tau . qd, with the derivative by central differences from RK4 steps of +-h.
  const Model<double> model = GetParam().make();
  const int n = model.nv;
  Workspace<double> ws(model);
  Energy energy(model);
  test::Random rng(43);
  test::State start = test::random_state(model, rng);
  Vector q = test::to_eigen(start.q), qd = test::to_eigen(rng.vector(n, -1, 1));
  // tau_i = M_ii(q0) times up to 2 rad/s^2: light fingers as well as heavy legs then move by
  // comparable angles over the trajectory (a torque of a few Nm would spin pr2's fingers at
  // 1e5 rad/s^2 and RK4 with a 5 ms step would diverge)
  std::vector<double> M(n * n);
  crba<double>(model, ws, view(q), M);
  const Vector tau =
      test::to_eigen(M, n).diagonal().cwiseProduct(test::to_eigen(rng.vector(n, -2, 2)));

  auto acceleration = [&](const Vector& x, const Vector& xd) {
    Vector xdd(n);
    aba<double>(model, ws, view(x), view(xd), view(tau), view(xdd));
    return xdd;
  };
  auto rate = [&](const Vector& x, const Vector& xd) {
    Vector xdot(model.nq);
    configuration_rate<double>(model, view(x), view(xd), view(xdot));
    return xdot;
  };
  auto rk4 = [&](Vector& x, Vector& xd, double dt) {
    const Vector k1 = rate(x, xd), l1 = acceleration(x, xd);
    const Vector x2 = x + dt / 2 * k1, xd2 = xd + dt / 2 * l1;
    const Vector k2 = rate(x2, xd2), l2 = acceleration(x2, xd2);
    const Vector x3 = x + dt / 2 * k2, xd3 = xd + dt / 2 * l2;
    const Vector k3 = rate(x3, xd3), l3 = acceleration(x3, xd3);
    const Vector x4 = x + dt * k3, xd4 = xd + dt * l3;
    const Vector k4 = rate(x4, xd4), l4 = acceleration(x4, xd4);
    x += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    xd += dt / 6 * (l1 + 2 * l2 + 2 * l3 + l4);
    normalize_configuration<double>(model, view(x));
  };
  auto total_energy = [&](const Vector& x, const Vector& xd) {
    return energy.kinetic(x, xd) + energy.potential(x);
  };

  double worst = 0;
  for (int step = 0; step < 20; ++step) {
    Vector q_plus = q, qd_plus = qd, q_minus = q, qd_minus = qd;
    rk4(q_plus, qd_plus, fd_h);
    rk4(q_minus, qd_minus, -fd_h);
    const double dE =
        (total_energy(q_plus, qd_plus) - total_energy(q_minus, qd_minus)) / (2 * fd_h);
    const double power = tau.dot(qd);
    const double scale = std::abs(energy.kinetic(q, qd)) + std::abs(energy.potential(q)) +
                         tau.cwiseProduct(qd).cwiseAbs().sum();
    ASSERT_TRUE(std::isfinite(dE) && std::isfinite(power)) << "step " << step;
    worst = std::max(worst, std::abs(dE - power) / scale);
    rk4(q, qd, 5e-3);
  }
  report("|dE/dt - tau . qd| / (|T| + |V| + sum |tau_i qd_i|)", worst);
  EXPECT_LE(worst, fd_tol);
}

INSTANTIATE_TEST_SUITE_P(Models, Physics, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return info.param.name;
                         });

}  // namespace
}  // namespace dyngen
