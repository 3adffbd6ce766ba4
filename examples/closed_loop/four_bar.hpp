// A four-bar linkage simulated as the generated open chain (four_bar.urdf: crank, coupler,
// rocker) plus a loop constraint that holds the rocker's tip on the ground pivot. Each step
// solves the KKT system of the constrained dynamics, with Baumgarte stabilisation, and advances
// by the classical Runge-Kutta method (RK4) at a fixed step. Everything in the loop is
// fixed-size: no heap.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "four_bar_dynamics.hpp"
#include "four_bar_model.hpp"

namespace closed_loop {

constexpr int nv = four_bar::nv;
constexpr int tip = 0, ground_pivot = 1;  // frame indices, in the order of dyngen's --frames
static_assert(four_bar::nq == nv && four_bar::nframes == 2);

using Vector = Eigen::Matrix<double, nv, 1>;
using Vector2 = Eigen::Vector2d;

/// The link lengths of four_bar.urdf, for the closed-form kinematics: stated here, not read from
/// the generated code, so that the closed form checks it.
struct Lengths {
  double crank = 0.2, coupler = 0.5, rocker = 0.4, ground = 0.45;
};

struct State {
  Vector q, v;
};

/// Baumgarte stabilisation: the constraint error phi is made to obey
/// phi'' + 2 alpha phi' + beta^2 phi = 0 instead of phi'' = 0. Zero gains: no stabilisation.
struct Stabilisation {
  double alpha = 0, beta = 0;  // 1/s
};

// The example's set-up: the step, the gains (critically damped, alpha = beta: an error decays
// with a time constant of 1 / beta) and the assembly mode (the branch of rocker_angle).
inline constexpr double step = 1e-3;  // s
inline constexpr Stabilisation baumgarte{20, 20};
inline constexpr int assembly = 1;

/// The loop at one state: the open chain's dynamics and the constraint's two rows, x and y of
/// the tip relative to the ground pivot. The other rows of a revolute loop joint (z, and the
/// rotations about x and y) hold by themselves in a planar linkage; their zero rows would make
/// the KKT matrix singular.
struct Loop {
  Eigen::Matrix<double, nv, nv> M;  // mass matrix
  Vector h;                         // C(q, v) v + g(q)
  Vector2 phi;                      // position error, m
  Eigen::Matrix<double, 2, nv> J;   // d phi / dq
  Vector2 Jdot_v;                   // phi'' at qdd = 0
  Eigen::Vector3d com;              // centre of mass, m
};

/// The loop at x, from the generated functions (one joint_trig shared by all of them).
inline Loop evaluate(const State& x) {
  using four_bar::nframes;
  four_bar::JointTrig trig;
  four_bar::joint_trig(x.q.data(), trig);
  double M[nv * nv], R[nframes * 9], p[nframes * 3], J[nframes * 6 * nv], Jdot_v[nframes * 6],
      Jc[3 * nv];
  Loop loop;
  four_bar::crba_trig(x.q.data(), trig, M);
  loop.M = Eigen::Map<const Eigen::Matrix<double, nv, nv, Eigen::RowMajor>>(M);
  four_bar::nle_trig(x.q.data(), trig, x.v.data(), loop.h.data());
  four_bar::frame_placements_trig(x.q.data(), trig, R, p);
  four_bar::frame_jacobians_trig(x.q.data(), trig, J);
  four_bar::frame_accelerations_trig(x.q.data(), trig, x.v.data(), Jdot_v);
  four_bar::com_trig(x.q.data(), trig, loop.com.data(), Jc);
  // the linear rows come first, in base axes: row i of frame f is (6 f + i)
  for (int i = 0; i < 2; ++i) {
    loop.phi[i] = p[3 * tip + i] - p[3 * ground_pivot + i];
    for (int j = 0; j < nv; ++j)
      loop.J(i, j) = J[(6 * tip + i) * nv + j] - J[(6 * ground_pivot + i) * nv + j];
    loop.Jdot_v[i] = Jdot_v[6 * tip + i] - Jdot_v[6 * ground_pivot + i];
  }
  return loop;
}

/// The constrained accelerations and the constraint force: the solution of
///   [M J^T] [ qdd   ]   [ tau - h                                ]
///   [J  0 ] [-lambda] = [ -Jdot_v - 2 alpha J v - beta^2 phi     ]
/// lambda is the force the ground pivot exerts on the tip (N, base axes).
struct Constrained {
  Vector qdd;
  Vector2 lambda;
};

inline Constrained constrained_acceleration(const Loop& loop, const Vector& v, const Vector& tau,
                                            Stabilisation s) {
  Eigen::Matrix<double, nv + 2, nv + 2> K;
  K << loop.M, loop.J.transpose(), loop.J, Eigen::Matrix2d::Zero();
  Eigen::Matrix<double, nv + 2, 1> rhs;
  rhs << tau - loop.h, -loop.Jdot_v - 2 * s.alpha * (loop.J * v) - s.beta * s.beta * loop.phi;
  // K is symmetric but indefinite (M's block positive, the zero block's pivots negative): LU
  const Eigen::Matrix<double, nv + 2, 1> x = K.partialPivLu().solve(rhs);
  return {x.head<nv>(), -x.tail<2>()};
}

/// Total mass, from the generated model's records.
inline const double total_mass = [] {
  double m = 0;
  for (const dyngen::BodyRecord& body : four_bar::model_bodies) m += body.mass;
  return m;
}();

/// Total energy: kinetic 1/2 v^T M v, potential -m g . c from the centre of mass.
inline double energy(const Loop& loop, const State& x) {
  const Eigen::Map<const Eigen::Vector3d> g(four_bar::model_gravity);
  return 0.5 * x.v.dot(loop.M * x.v) - total_mass * g.dot(loop.com);
}

/// The rocker's angle at the ground pivot (from the ground line, +x, to the rocker) for a crank
/// angle theta2, by Freudenstein's equation of the four-bar's loop closure:
///   K1 cos theta4 - K2 cos theta2 + K3 = cos(theta2 - theta4),
///   K1 = d / a, K2 = d / c, K3 = (a^2 - b^2 + c^2 + d^2) / (2 a c)
/// with a, b, c, d the crank, coupler, rocker and ground. As P cos theta4 + Q sin theta4 + S = 0
/// it has two solutions, the linkage's two assembly modes: branch +1 or -1 picks one.
inline double rocker_angle(double theta2, int branch, Lengths l = {}) {
  const double a = l.crank, b = l.coupler, c = l.rocker, d = l.ground;
  const double K1 = d / a, K2 = d / c, K3 = (a * a - b * b + c * c + d * d) / (2 * a * c);
  const double P = K1 - std::cos(theta2), Q = -std::sin(theta2), S = K3 - K2 * std::cos(theta2);
  return std::atan2(Q, P) + branch * std::acos(-S / std::hypot(P, Q));
}

/// The same angle in the simulated chain: the rocker's x axis points from its joint to the tip,
/// so the line from the ground pivot to the rocker's joint is at q1 + q2 + q3 - pi.
inline double simulated_rocker_angle(const State& x) { return x.q.sum() - std::numbers::pi; }

/// A state on the loop: the crank at theta2 turning at omega (rad, rad/s), the other joints
/// from the closed-form kinematics in the given assembly mode, their rates from J v = 0. By
/// default the crank starts fast enough to go over the top: it turns 8 times in 5 s.
inline State initial_state(double theta2 = 0, double omega = 8, int branch = assembly,
                           Lengths l = {}) {
  const double theta4 = rocker_angle(theta2, branch, l);
  // the coupler's joint B at the crank's end, the rocker's joint C on the rocker from the pivot
  const double Bx = l.crank * std::cos(theta2), By = l.crank * std::sin(theta2);
  const double Cx = l.ground + l.rocker * std::cos(theta4), Cy = l.rocker * std::sin(theta4);
  const double theta3 = std::atan2(Cy - By, Cx - Bx);
  State x{Vector(theta2, theta3 - theta2, theta4 + std::numbers::pi - theta3), Vector::Zero()};
  const Loop loop = evaluate(x);
  x.v[0] = omega;
  x.v.tail<2>() = -loop.J.rightCols<2>().partialPivLu().solve(loop.J.col(0) * omega);
  return x;
}

/// One step of the classical fourth-order Runge-Kutta method under joint forces tau, from x,
/// whose loop at_x is already evaluated.
inline State rk4_step(const State& x, const Loop& at_x, double h, const Vector& tau,
                      Stabilisation s) {
  // the time derivative (v, qdd) of a state
  auto rate = [&](const State& y, const Loop& loop) -> State {
    return {y.v, constrained_acceleration(loop, y.v, tau, s).qdd};
  };
  auto advance = [](const State& y, double c, const State& d) -> State {
    return {y.q + c * d.q, y.v + c * d.v};
  };
  const State k1 = rate(x, at_x);
  const State x2 = advance(x, h / 2, k1);
  const State k2 = rate(x2, evaluate(x2));
  const State x3 = advance(x, h / 2, k2);
  const State k3 = rate(x3, evaluate(x3));
  const State x4 = advance(x, h, k3);
  const State k4 = rate(x4, evaluate(x4));
  return {x.q + h / 6 * (k1.q + 2 * k2.q + 2 * k3.q + k4.q),
          x.v + h / 6 * (k1.v + 2 * k2.v + 2 * k3.v + k4.v)};
}

/// The largest values over one second of a rollout.
struct Window {
  double position = 0;  // |phi|, m
  double velocity = 0;  // |J v|, m/s
  double energy = 0;    // |E - E0|, J
  double rocker = 0;    // |rocker angle - Freudenstein's|, rad
};

/// Seconds of free motion (tau = 0) from x at step h: the constraint's drift, the energy's
/// and the distance to the closed-form kinematics (assembly mode branch), second by second.
template <int Seconds>
std::array<Window, Seconds> rollout(State x, double h, Stabilisation s, int branch) {
  const int steps = static_cast<int>(std::lround(1 / h));
  const Vector tau = Vector::Zero();
  std::array<Window, Seconds> windows{};
  const double E0 = energy(evaluate(x), x);
  for (Window& w : windows)
    for (int k = 0; k < steps; ++k) {
      const Loop loop = evaluate(x);
      w.position = std::max(w.position, loop.phi.norm());
      w.velocity = std::max(w.velocity, (loop.J * x.v).norm());
      w.energy = std::max(w.energy, std::abs(energy(loop, x) - E0));
      const double error = simulated_rocker_angle(x) - rocker_angle(x.q[0], branch);
      w.rocker = std::max(w.rocker, std::abs(std::remainder(error, 2 * std::numbers::pi)));
      x = rk4_step(x, loop, h, tau, s);
    }
  return windows;
}

}  // namespace closed_loop
