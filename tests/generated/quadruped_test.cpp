// The solo12 quadruped of examples/quadruped (quadruped.hpp): a 5 cm drop on the generated aba,
// the touchdown's impact on the generated impulse_dynamics, and 10 s of standing on the
// generated contact_dynamics under a joint PD with gravity compensation, at 1 ms. Checked
// against what does not come from the function under test: semi-implicit Euler's closed-form
// fall, the impact law and Carnot's energy loss with the generated crba and frame Jacobians, the
// statics of the stance, and the requirement that the feet drift less than 1 mm.
#include "quadruped.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "test_support.hpp"

namespace {

using quadruped::nc;
using quadruped::nfeet;
using quadruped::nj;
using quadruped::nv;
using quadruped::Second;
using quadruped::State;
using quadruped::VectorC;
using quadruped::VectorV;

constexpr int seconds = 10;
constexpr double allowed_drift = 1e-3;  // m, the requirement over the 10 s

const double g = -quadruped::gravity_acceleration.z();
const double weight = quadruped::total_mass * g;

/// The three phases, run once for all the tests.
struct Phases {
  quadruped::Drop drop = quadruped::drop(quadruped::initial_state());
  quadruped::Impact impact = quadruped::touchdown(drop.touchdown);
  quadruped::Controller controller = quadruped::standing_controller(drop.touchdown.q);
  std::array<Second, seconds> windows = quadruped::stand<seconds>(
      {drop.touchdown.q, impact.v_plus}, drop.anchors, controller, [](const auto&) {});
};

const Phases& run() {
  static const Phases r;
  return r;
}

Eigen::Matrix<double, nv, nv> mass_matrix(const quadruped::VectorQ& q) {
  Eigen::Matrix<double, nv, nv, Eigen::RowMajor> M;
  solo12_quadruped::crba(q.data(), M.data());
  return M;
}

TEST(Quadruped, PackageIsTheExamples) {
  // the feet's frames in the contacts' order, and only the velocity gain (a position gain would
  // need the touchdown's anchors, contact_dynamics_anchored's): --baumgarte 0,30
  EXPECT_EQ(solo12_quadruped::model_constraint_settings.kp, 0.0);
  EXPECT_EQ(solo12_quadruped::model_constraint_settings.kd, 30.0);
  for (int i = 0; i < nfeet; ++i) {
    const char* frame = solo12_quadruped::frame_names[i];
    EXPECT_EQ(std::strncmp(frame, solo12_quadruped::constraint_names[i], std::strlen(frame)), 0);
  }
}

TEST(Quadruped, DropIsAFreeFallOfThePosture) {
  const quadruped::Drop& drop = run().drop;
  // no torque: every body falls with g, so the posture holds and the base falls straight down;
  // semi-implicit Euler puts the feet g dt^2 n (n + 1) / 2 lower after n steps
  const double dt = quadruped::step;
  int n = 1;
  while (g * dt * dt * n * (n + 1) / 2 < quadruped::drop_height) ++n;
  EXPECT_EQ(drop.steps, n);
  EXPECT_EQ(drop.feet_down, nfeet);  // symmetric posture, vertical fall: all at once
  EXPECT_NEAR(drop.touchdown.v[2], -g * dt * n, 1e-12);
  EXPECT_NEAR(drop.penetration, g * dt * dt * n * (n + 1) / 2 - quadruped::drop_height, 1e-12);
  EXPECT_LE(drop.penetration, -drop.touchdown.v[2] * dt);
  const State& x = drop.touchdown;
  EXPECT_LE((x.q.tail<nj>() - quadruped::joint_reference()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE(x.v.tail<nj>().cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE(x.v.segment<3>(3).norm(), 1e-12);  // no rotation
  EXPECT_LE(x.q.segment<3>(4).norm(), 1e-12);  // the base stays level
  EXPECT_LE(x.v.head<2>().norm(), 1e-12);      // nor does it slide
}

TEST(Quadruped, TouchdownStopsTheFeetAndLosesEnergy) {
  const State& minus = run().drop.touchdown;
  const quadruped::Impact& impact = run().impact;
  EXPECT_GT(impact.foot_speed_before, 0.5);
  EXPECT_LE(impact.foot_speed_after, 1e-12 * impact.foot_speed_before);
  // the impact law with the generated crba and frame Jacobians: M (v+ - v-) = J^T impulse
  const Eigen::Matrix<double, nv, nv> M = mass_matrix(minus.q);
  VectorC impulse;
  for (int i = 0; i < nfeet; ++i) impulse.segment<3>(3 * i) = impact.impulse[i];
  const VectorV dv = impact.v_plus - minus.v;
  const VectorV residual = M * dv - quadruped::feet(minus.q).J.transpose() * impulse;
  EXPECT_LE(residual.norm(), 1e-12 * (M * minus.v).norm());
  // a plastic impact loses energy, by Carnot's theorem the kinetic energy of the jump
  EXPECT_LE(impact.energy_after, impact.energy_before);
  EXPECT_NEAR(impact.energy_before - impact.energy_after, 0.5 * dv.dot(M * dv),
              1e-12 * impact.energy_before);
  for (const quadruped::Vector3& p : impact.impulse) EXPECT_GT(p.z(), 0.0);  // the ground pushes
}

TEST(Quadruped, FeedForwardHoldsTheStance) {
  // at the posture and at rest, the feed-forward alone leaves the robot still, each foot
  // carrying a quarter of the weight: the stance is symmetric, so the equal split balances the
  // base's force and moment too
  const Phases& r = run();
  EXPECT_LE(r.controller.base_residual.norm(), 1e-12 * weight);
  const State x{r.drop.touchdown.q, VectorV::Zero()};
  VectorV qdd;
  VectorC lambda;
  solo12_quadruped::contact_dynamics(x.q.data(), x.v.data(), r.controller.torque(x).data(),
                                     qdd.data(), lambda.data());
  EXPECT_LE(qdd.norm(), 1e-9 * g);
  for (int i = 0; i < nfeet; ++i)
    EXPECT_LE((lambda.segment<3>(3 * i) - quadruped::Vector3(0, 0, weight / nfeet)).norm(),
              1e-9 * weight);
}

TEST(Quadruped, FeetDriftLessThanAMillimetre) {
  const std::array<Second, seconds>& w = run().windows;
  for (int s = 0; s < seconds; ++s) EXPECT_LT(w[s].drift, allowed_drift) << "second " << s + 1;
  std::printf("[ measured ] drift %.3e m, |J v| %.3e m/s in the first second\n", w[0].drift,
              w[0].foot_speed);
  // after a second the impact's velocity error has decayed by exp(-KD 1 s) = exp(-30) and the
  // motion by exp(-zeta omega 1 s), about exp(-15): the feet stand still but for rounding, so
  // the drift no longer grows (without KD the error stays and the drift grows by mm a second)
  for (int s = 1; s < seconds; ++s) {
    EXPECT_LE(w[s].foot_speed, 1e-9) << "second " << s + 1;
    EXPECT_LE(w[s].drift - w[0].drift, 1e-8) << "second " << s + 1;
  }
}

TEST(Quadruped, FeetPushThroughout) {
  const std::array<Second, seconds>& w = run().windows;
  for (int s = 0; s < seconds; ++s) EXPECT_GT(w[s].push, 0.0) << "second " << s + 1;
  // standing still, each foot carries a quarter of the weight (the stance is symmetric; the
  // feet's drift shifts the posture, by far less than the 1% allowed here)
  EXPECT_NEAR(w.back().push, weight / nfeet, 0.01 * weight / nfeet);
}

/// The vertical stiffness of the stance: with the feet held, the base moving up by dz turns
/// the joints by dq = (dq/dz) dz (J_joints dq = -J_base e_z leg by leg), and the PD's springs
/// store 1/2 kp |dq/dz|^2 dz^2.
double vertical_stiffness(const quadruped::VectorQ& q, double kp) {
  const auto J = quadruped::feet(q).J;
  VectorV up = VectorV::Zero();
  up[2] = 1;  // base linear z: the base is level, so its axes are the world's
  const Eigen::Matrix<double, nc, nj> J_joints = J.rightCols<nj>();
  const quadruped::VectorJ dq_dz = J_joints.partialPivLu().solve(-J * up);
  return kp * dq_dz.squaredNorm();
}

TEST(Quadruped, BaseHeightStaysInItsEnergyBand) {
  const Phases& r = run();
  const double z0 = r.drop.touchdown.q[2];
  // gravity and the feed-forward balance at the posture, the damper and the contacts' Baumgarte
  // term only take energy away: to first order the base moves at most as far as the springs
  // can store the kinetic energy left after the impact
  const double stiffness = vertical_stiffness(r.drop.touchdown.q, r.controller.gains.kp);
  const double band = std::sqrt(2 * r.impact.energy_after / stiffness);
  double low = z0, high = z0;
  for (const Second& s : r.windows)
    low = std::min(low, s.base_low), high = std::max(high, s.base_high);
  std::printf("[ measured ] base %.4f .. %.4f m, touchdown at %.4f m, energy band +-%.4f m\n", low,
              high, z0, band);
  EXPECT_GE(low, z0 - band);
  EXPECT_LE(high, z0 + band);
  // at rest the joints are back at the posture, so the base is where it touched down, but for
  // the feet's drift
  EXPECT_LE(std::abs(r.windows.back().base_low - z0), allowed_drift);
  EXPECT_LE(std::abs(r.windows.back().base_high - z0), allowed_drift);
}

TEST(Quadruped, PhasesAllocateNothing) {
  const Phases& r = run();
  const dyngen::test::AllocationCounter counter;
  const quadruped::Drop drop = quadruped::drop(quadruped::initial_state());
  const quadruped::Impact impact = quadruped::touchdown(drop.touchdown);
  const auto w = quadruped::stand<1>({drop.touchdown.q, impact.v_plus}, drop.anchors,
                                     r.controller, [](const auto&) {});
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(w[0].drift, 0.0);
}

}  // namespace
