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

constexpr double eps = std::numeric_limits<double>::epsilon();

/// Energies from world-frame kinematics: body i's rotation R_i (body to world) and origin p_i
/// compose its joint transform's E and r with its parent's (R_i = R_p E^T, p_i = p_p + R_p r);
/// angular velocities add the joint's S qd in world coordinates, origin velocities add
/// w_p x (p_i - p_p) as well.
class Energy {
 public:
  explicit Energy(const Model<double>& model)
      : model_(model), R_(model.nbodies), p_(model.nbodies), w_(model.nbodies),
        v_(model.nbodies) {}

  /// Sum over bodies of 1/2 v_i^T I_i v_i, written with (m, h, I) in body coordinates:
  /// 1/2 (w . I w + 2 v . (w x h) + m v . v).
  double kinetic(const Vector& q, const Vector& qd) {
    kinematics(q, qd);
    double T = 0;
    for (int i = 0; i < model_.nbodies; ++i) {
      const RigidInertia<double>& I = model_.I[i];
      const Vector3 w = R_[i].transpose() * w_[i], v = R_[i].transpose() * v_[i];
      T += 0.5 * (w.dot(dense(I.I) * w) + 2 * v.dot(w.cross(dense(I.h))) + I.m * v.dot(v));
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
      const int k = model_.q_index[i], parent = model_.parent[i];
      const Matrix3 R_p = parent < 0 ? Matrix3::Identity() : R_[parent];
      const Vector3 p_p = parent < 0 ? Vector3::Zero() : p_[parent];
      const Vector3 w_p = parent < 0 ? Vector3::Zero() : w_[parent];
      const Vector3 v_p = parent < 0 ? Vector3::Zero() : v_[parent];
      const Xform<double> X = joint_transform(model_, i, q[k]);
      R_[i] = R_p * dense(X.E).transpose();
      p_[i] = p_p + R_p * dense(X.r);
      const Motion<double> S_qd = joint_motion(model_, i, qd[k]);
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

/// Every shared robot (with romeo's massless joints locked, which ABA needs), the documented
/// five-link case and random chains.
std::vector<Case> cases() {
  std::vector<Case> all;
  for (const test::RobotFile& robot : test::robot_files())
    all.push_back({robot.name, [=] { return test::load_for_aba(robot); }});
  all.push_back({"planar5", [] { return gen::load_robot(test::model_path("planar5.yaml")).model; }});
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
    worst = std::max(worst, std::abs(energy.kinetic(test::to_eigen(s.q), qd) - T) / (n * eps * scale));
  }
  report("kinetic energy error / (n eps |qd|^T |M| |qd|)", worst);
  EXPECT_LE(worst, 4.0);
}

INSTANTIATE_TEST_SUITE_P(Models, Physics, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& info) { return info.param.name; });

}  // namespace
}  // namespace dyngen
