// The solo12 quadruped (tests/models/solo12.urdf on a floating base) dropped onto flat ground,
// caught by its feet and held standing, from one generated package, solo12_quadruped (point
// contacts at FL_FOOT, FR_FOOT, HL_FOOT and HR_FOOT, --baumgarte 0,30). Three phases:
//   drop:      the generated aba with the feet free, until the feet cross z = 0;
//   touchdown: the generated impulse_dynamics stops the feet (J v_plus = 0);
//   standing:  the generated contact_dynamics under a joint PD with gravity compensation.
// Semi-implicit Euler at 1 ms, q (+) dt v by the generated integrate. Everything in the loops is
// fixed-size: no heap.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>

#include "solo12_quadruped_dynamics.hpp"
#include "solo12_quadruped_model.hpp"

namespace quadruped {

namespace robot = solo12_quadruped;

constexpr int nq = robot::nq, nv = robot::nv, nc = robot::nc;
constexpr int nfeet = robot::nconstraints, nj = nv - 6;  // the legs' joints, after the base's 6
static_assert(robot::nframes == nfeet && nc == 3 * nfeet && nq == nv + 1);

using VectorQ = Eigen::Matrix<double, nq, 1>;
using VectorV = Eigen::Matrix<double, nv, 1>;
using VectorJ = Eigen::Matrix<double, nj, 1>;
using VectorC = Eigen::Matrix<double, nc, 1>;
using Vector3 = Eigen::Vector3d;
using Feet = std::array<Vector3, nfeet>;

struct State {
  VectorQ q;  // base position, base quaternion (w, x, y, z), 12 joint angles
  VectorV v;  // base linear and angular velocity (base axes), 12 joint rates
};

inline constexpr double step = 1e-3;         // s
inline constexpr double drop_height = 0.05;  // m, the feet above the ground at the start

/// The joint PD's gains, the same on every joint (README: the gains).
struct Gains {
  double kp = 5.0;  // N m/rad
  double kd = 0.2;  // N m s/rad
};

/// The standing posture: hips flexed 0.8 rad and knees -1.6 rad on the front legs, mirrored on
/// the hind ones (example-robot-data's "standing" pose), which puts each foot under its hip.
inline VectorJ joint_reference() {
  VectorJ q;
  q << 0, 0.8, -1.6, 0, 0.8, -1.6, 0, -0.8, 1.6, 0, -0.8, 1.6;
  return q;
}

/// The feet's origins (world axes: the floating base's parent is the world) and the linear rows
/// of their Jacobians, d p / d v, stacked in constraint order.
struct FeetKinematics {
  Feet p;
  Eigen::Matrix<double, nc, nv> J;
};

inline FeetKinematics feet(const VectorQ& q) {
  double R[nfeet * 9], p[nfeet * 3], J[nfeet * 6 * nv];
  robot::frame_placements(q.data(), R, p);
  robot::frame_jacobians(q.data(), J);
  FeetKinematics f;
  for (int i = 0; i < nfeet; ++i) {
    f.p[i] = Eigen::Map<const Vector3>(p + 3 * i);
    f.J.middleRows<3>(3 * i) =
        Eigen::Map<const Eigen::Matrix<double, 3, nv, Eigen::RowMajor>>(J + 6 * nv * i);
  }
  return f;
}

/// Total mass, from the package's model records.
inline const double total_mass = [] {
  double m = 0;
  for (const dyngen::BodyRecord& body : robot::model_bodies) m += body.mass;
  return m;
}();

inline const Vector3 gravity_acceleration = Eigen::Map<const Vector3>(robot::model_gravity);

/// Kinetic energy 1/2 v^T M v, M from the generated crba.
inline double kinetic_energy(const State& x) {
  Eigen::Matrix<double, nv, nv, Eigen::RowMajor> M;
  robot::crba(x.q.data(), M.data());
  return 0.5 * x.v.dot(M * x.v);
}

/// The start of the drop: the standing posture, base level and at rest, feet drop_height above
/// the ground (all four at one height: the posture is symmetric).
inline State initial_state() {
  State x{VectorQ::Zero(), VectorV::Zero()};
  x.q[3] = 1;  // identity quaternion
  x.q.tail<nj>() = joint_reference();
  x.q[2] = drop_height - feet(x.q).p[0].z();
  return x;
}

/// One semi-implicit Euler step: v += dt qdd, then q = q (+) dt v on the configuration space
/// (the free joint's quaternion turned by the rotation dt w, not added to).
inline void euler_step(State& x, const VectorV& qdd) {
  x.v += step * qdd;
  const VectorV d = step * x.v;
  const VectorQ q = x.q;  // integrate's input, kept apart from its output
  robot::integrate(q.data(), d.data(), x.q.data());
}

/// Phase 1, the drop. With no joint torque every body falls with the same acceleration g, so the
/// posture holds and the fall is straight down; it ends at the first step after which a foot is
/// at or below z = 0.
struct Drop {
  State touchdown;         // the state at the end of that step
  int steps = 0;           // steps of free fall
  int feet_down = 0;       // feet at or below the ground after it (4: they touch at once)
  double penetration = 0;  // m, how far below z = 0 the lowest foot is (at most |v_z| dt)
  Feet anchors;            // where the feet touched down, which the standing phase holds them to
};

inline Drop drop(State x) {
  const VectorV tau = VectorV::Zero();
  VectorV qdd;
  constexpr int max_steps = 1000;  // 1 s: far more than the 0.1 s a 5 cm fall takes
  for (int k = 1; k <= max_steps; ++k) {
    robot::aba(x.q.data(), x.v.data(), tau.data(), qdd.data());
    euler_step(x, qdd);
    const Feet p = feet(x.q).p;
    const auto down =
        std::count_if(p.begin(), p.end(), [](const Vector3& f) { return f.z() <= 0; });
    if (down == 0) continue;
    double lowest = 0;
    for (const Vector3& f : p) lowest = std::min(lowest, f.z());
    return {x, k, static_cast<int>(down), -lowest, p};
  }
  return {x, max_steps, 0, 0, feet(x.q).p};
}

/// Phase 2, the touchdown: a perfectly inelastic impact (restitution 0), the feet's velocity
/// brought to zero in one instant by impulses at the feet.
struct Impact {
  VectorV v_plus;
  Feet impulse;                                        // N s on each foot, world axes
  double energy_before = 0, energy_after = 0;          // J, kinetic
  double foot_speed_before = 0, foot_speed_after = 0;  // largest |J v| of a foot, m/s
};

inline Impact touchdown(const State& x) {
  Impact impact;
  VectorC impulse;
  robot::impulse_dynamics(x.q.data(), x.v.data(), impact.v_plus.data(), impulse.data());
  const FeetKinematics f = feet(x.q);
  const VectorC before = f.J * x.v, after = f.J * impact.v_plus;
  for (int i = 0; i < nfeet; ++i) {
    impact.impulse[i] = impulse.segment<3>(3 * i);
    impact.foot_speed_before = std::max(impact.foot_speed_before, before.segment<3>(3 * i).norm());
    impact.foot_speed_after = std::max(impact.foot_speed_after, after.segment<3>(3 * i).norm());
  }
  impact.energy_before = kinetic_energy(x);
  impact.energy_after = kinetic_energy({x.q, impact.v_plus});
  return impact;
}

/// Phase 3's controller: tau = 0 on the base (it has no actuator), and on the joints
///   kp (q_ref - q) - kd v + tau_ff,
/// with tau_ff the joint torques that hold the robot still in the posture: the joint rows of
/// g(q_ref) - J(q_ref)^T lambda_0, lambda_0 the weight shared equally by the four feet.
struct Controller {
  Gains gains;
  VectorJ q_ref, tau_ff;
  Eigen::Matrix<double, 6, 1> base_residual;  // the base rows: ~0 when lambda_0 balances them

  VectorV torque(const State& x) const {
    VectorV tau = VectorV::Zero();
    tau.tail<nj>() = gains.kp * (q_ref - x.q.tail<nj>()) - gains.kd * x.v.tail<nj>() + tau_ff;
    return tau;
  }
};

inline Controller standing_controller(const VectorQ& q_ref, Gains gains = {}) {
  VectorV g;
  robot::gravity(q_ref.data(), g.data());
  VectorC lambda0;
  for (int i = 0; i < nfeet; ++i)
    lambda0.segment<3>(3 * i) = -total_mass / nfeet * gravity_acceleration;
  const VectorV held = g - feet(q_ref).J.transpose() * lambda0;
  return {gains, q_ref.tail<nj>(), held.tail<nj>(), held.head<6>()};
}

/// The largest or smallest values over one second of standing.
struct Second {
  double drift = 0;                                             // m, largest |p_foot - anchor|
  double base_low = std::numeric_limits<double>::infinity();    // m, lowest base height
  double base_high = -std::numeric_limits<double>::infinity();  // m, highest
  double foot_speed = 0;                                        // m/s, largest |J v| of a foot
  double push = std::numeric_limits<double>::infinity();        // N, smallest vertical foot force
  double torque = 0;                                            // N m, largest |tau| of a joint
};

/// One step's numbers, for a log: time, each foot's drift and the base's height.
struct Sample {
  double time;
  std::array<double, nfeet> drift;
  double base_height;
};

/// Phase 3, standing: Seconds of contact_dynamics under the controller from x, the feet held
/// where they touched down (anchors). on_step(const Sample&) sees every step.
template <int Seconds, class OnStep>
std::array<Second, Seconds> stand(State x, const Feet& anchors, const Controller& controller,
                                  OnStep&& on_step) {
  const int steps = static_cast<int>(std::lround(1 / step));
  std::array<Second, Seconds> seconds{};
  VectorV qdd;
  VectorC lambda;
  for (int s = 0; s < Seconds; ++s)
    for (int k = 0; k < steps; ++k) {
      const VectorV tau = controller.torque(x);
      robot::contact_dynamics(x.q.data(), x.v.data(), tau.data(), qdd.data(), lambda.data());
      euler_step(x, qdd);
      const FeetKinematics f = feet(x.q);
      const VectorC foot_velocity = f.J * x.v;
      Second& w = seconds[s];
      Sample sample{(s * steps + k + 1) * step, {}, x.q[2]};
      for (int i = 0; i < nfeet; ++i) {
        sample.drift[i] = (f.p[i] - anchors[i]).norm();
        w.drift = std::max(w.drift, sample.drift[i]);
        w.foot_speed = std::max(w.foot_speed, foot_velocity.segment<3>(3 * i).norm());
        w.push = std::min(w.push, lambda[3 * i + 2]);
      }
      w.torque = std::max(w.torque, tau.cwiseAbs().maxCoeff());
      w.base_low = std::min(w.base_low, x.q[2]);
      w.base_high = std::max(w.base_high, x.q[2]);
      on_step(sample);
    }
  return seconds;
}

}  // namespace quadruped
