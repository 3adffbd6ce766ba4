// A four-bar linkage (four_bar.yaml: crank, coupler and rocker in a chain, and a loop closure
// that holds the rocker's tip on the ground pivot) simulated from the generated
// contact_dynamics, which solves the loop's constrained dynamics inside the generated code, and
// advanced by the classical Runge-Kutta method (RK4) at a fixed step. Two packages of the same
// file: four_bar, generated with Baumgarte stabilisation (--baumgarte 400,40), and
// four_bar_free, without. The loop's position error, the energy and the closed-form kinematics
// come from the generated frame placements, Jacobians, CRBA and centre of mass. Everything in
// the loop is fixed-size: no heap.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "four_bar_dynamics.hpp"
#include "four_bar_free_dynamics.hpp"
#include "four_bar_model.hpp"

namespace closed_loop {

constexpr int nv = four_bar::nv;
static_assert(four_bar::nq == nv && four_bar::nframes == 1 && four_bar::nc == 3);

using Vector = Eigen::Matrix<double, nv, 1>;
using Vector2 = Eigen::Vector2d;
using Vector3 = Eigen::Vector3d;

/// The link lengths of four_bar.yaml, for the closed-form kinematics: stated here, not read from
/// the generated code, so that the closed form checks it.
struct Lengths {
  double crank = 0.2, coupler = 0.5, rocker = 0.4, ground = 0.45;
};

struct State {
  Vector q, v;
};

/// A package's constrained dynamics: the generated contact_dynamics of four_bar (stabilised) or
/// four_bar_free.
using ContactDynamics = void (*)(const double*, const double*, const double*, double*,
                                 double*) noexcept;
inline constexpr ContactDynamics stabilised = four_bar::contact_dynamics;
inline constexpr ContactDynamics unstabilised = four_bar_free::contact_dynamics;

// The example's set-up: the step and the assembly mode (the branch of rocker_angle). The gains
// of four_bar's --baumgarte KP,KD = 400,40 make the loop's error obey
// e'' + 40 e' + 400 e = 0: critically damped, a time constant of 50 ms.
inline constexpr double step = 1e-3;  // s
inline constexpr int assembly = 1;

/// The loop at one state, from the generated functions: the tip's position error (x and y of
/// the tip relative to the ground pivot; z holds by itself in the plane), its Jacobian, the mass
/// matrix and the centre of mass.
struct Loop {
  Vector2 phi;                      // position error, m
  Eigen::Matrix<double, 2, nv> J;   // d phi / dq
  Eigen::Matrix<double, nv, nv> M;  // mass matrix
  Vector3 com;                      // centre of mass, m
};

/// The tip in the rocker's frame and the ground pivot in the base's (four_bar.yaml's loop).
inline const Vector3 tip_on_rocker{0.4, 0, 0}, ground_pivot{0.45, 0, 0};

inline Loop evaluate(const State& x) {
  double R[9], p[3], J[6 * nv], M[nv * nv], Jc[3 * nv];
  four_bar::frame_placements(x.q.data(), R, p);
  four_bar::frame_jacobians(x.q.data(), J);
  Loop loop;
  four_bar::crba(x.q.data(), M);
  loop.M = Eigen::Map<const Eigen::Matrix<double, nv, nv, Eigen::RowMajor>>(M);
  four_bar::com(x.q.data(), loop.com.data(), Jc);
  // the tip at r = R t from the rocker's origin: p_tip = p + r, J_tip = J_lin - [r]x J_ang
  const Vector3 r =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R) * tip_on_rocker;
  const Eigen::Map<const Eigen::Matrix<double, 6, nv, Eigen::RowMajor>> Jr(J);
  Eigen::Matrix3d skew;
  skew << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  const Eigen::Matrix<double, 3, nv> J_tip = Jr.topRows<3>() - skew * Jr.bottomRows<3>();
  loop.phi = (Eigen::Map<const Vector3>(p) + r - ground_pivot).head<2>();
  loop.J = J_tip.topRows<2>();
  return loop;
}

/// Total mass, from the generated model's records.
inline const double total_mass = [] {
  double m = 0;
  for (const dyngen::BodyRecord& body : four_bar::model_bodies) m += body.mass;
  return m;
}();

/// Total energy: kinetic 1/2 v^T M v, potential -m g . c from the centre of mass.
inline double energy(const Loop& loop, const State& x) {
  const Eigen::Map<const Vector3> g(four_bar::model_gravity);
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

/// The constrained accelerations and the loop's force on the rocker's tip (N, base axes; the
/// redundant z row's is zero).
struct Constrained {
  Vector qdd;
  Vector3 lambda;
};

inline Constrained constrained_acceleration(ContactDynamics f, const State& x, const Vector& tau) {
  Constrained c;
  f(x.q.data(), x.v.data(), tau.data(), c.qdd.data(), c.lambda.data());
  return c;
}

/// One step of the classical fourth-order Runge-Kutta method under joint forces tau.
inline State rk4_step(ContactDynamics f, const State& x, double h, const Vector& tau) {
  auto rate = [&](const State& y) -> State {
    return {y.v, constrained_acceleration(f, y, tau).qdd};
  };
  auto advance = [](const State& y, double c, const State& d) -> State {
    return {y.q + c * d.q, y.v + c * d.v};
  };
  const State k1 = rate(x);
  const State k2 = rate(advance(x, h / 2, k1));
  const State k3 = rate(advance(x, h / 2, k2));
  const State k4 = rate(advance(x, h, k3));
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
std::array<Window, Seconds> rollout(ContactDynamics f, State x, double h, int branch) {
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
      x = rk4_step(f, x, h, tau);
    }
  return windows;
}

}  // namespace closed_loop
