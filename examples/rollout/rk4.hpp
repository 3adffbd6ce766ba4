// Integrating generated forward dynamics with the classical fourth-order Runge-Kutta method.
// The generated aba() gives the accelerations; the runtime's configuration_rate() turns
// velocities into the rate of q (a free joint's quaternion has four entries and three rates)
// and normalize_configuration() puts the quaternions back on the unit sphere after each step.
#pragma once

#include <cmath>
#include <span>
#include <vector>

#include <dyngen/kinematics.hpp>

namespace rollout {

/// A generated ABA: qdd = aba(q, v, tau), with the robot's model for the q kinematics.
struct System {
  dyngen::Model<double> model;  // the generated package's runtime_model()
  void (*aba)(const double* q, const double* v, const double* tau, double* qdd) noexcept;
};

struct State {
  std::vector<double> q, v;
};

/// One RK4 step of length h under constant joint forces tau.
inline State rk4_step(const System& system, const State& x, const std::vector<double>& tau,
                      double h) {
  const dyngen::Model<double>& model = system.model;
  // the derivative (dq/dt, dv/dt) at a state
  auto derivative = [&](const State& s) {
    State d{std::vector<double>(model.nq), std::vector<double>(model.nv)};
    dyngen::configuration_rate<double>(model, s.q, s.v, d.q);
    system.aba(s.q.data(), s.v.data(), tau.data(), d.v.data());
    return d;
  };
  // x + c d
  auto advance = [](const State& s, double c, const State& d) {
    State out = s;
    for (std::size_t k = 0; k < out.q.size(); ++k) out.q[k] += c * d.q[k];
    for (std::size_t k = 0; k < out.v.size(); ++k) out.v[k] += c * d.v[k];
    return out;
  };
  const State k1 = derivative(x);
  const State k2 = derivative(advance(x, h / 2, k1));
  const State k3 = derivative(advance(x, h / 2, k2));
  const State k4 = derivative(advance(x, h, k3));
  State next = x;
  for (std::size_t k = 0; k < next.q.size(); ++k)
    next.q[k] += h / 6 * (k1.q[k] + 2 * k2.q[k] + 2 * k3.q[k] + k4.q[k]);
  for (std::size_t k = 0; k < next.v.size(); ++k)
    next.v[k] += h / 6 * (k1.v[k] + 2 * k2.v[k] + 2 * k3.v[k] + k4.v[k]);
  dyngen::normalize_configuration<double>(model, next.q);
  return next;
}

/// What a torque-free rollout should conserve: the total energy, and (without gravity) the
/// spatial momentum in base coordinates.
struct Invariants {
  double energy;
  dyngen::Force<double> momentum;
};

inline Invariants invariants(const System& system, dyngen::Workspace<double>& ws, const State& x) {
  dyngen::forward_kinematics<double>(system.model, ws, x.q, x.v);
  return {dyngen::kinetic_energy<double>(system.model, ws, x.v) +
              dyngen::potential_energy(system.model, ws),
          dyngen::momentum(system.model, ws)};
}

/// The largest drift of the invariants from their initial values over `steps` steps of
/// length h with tau = 0: |E - E0| and |h - h0| (Euclidean norm of the 6-vector).
struct Drift {
  double energy = 0, momentum = 0;
};

inline Drift rollout(const System& system, State x, double h, int steps) {
  dyngen::Workspace<double> ws(system.model);
  const std::vector<double> tau(system.model.nv, 0.0);
  const Invariants start = invariants(system, ws, x);
  Drift drift;
  for (int step = 0; step < steps; ++step) {
    x = rk4_step(system, x, tau, h);
    const Invariants now = invariants(system, ws, x);
    const dyngen::Force<double> dh{now.momentum.ang - start.momentum.ang,
                                   now.momentum.lin - start.momentum.lin};
    drift.energy = std::max(drift.energy, std::abs(now.energy - start.energy));
    drift.momentum = std::max(drift.momentum,
                              std::sqrt(dot(dh.ang, dh.ang) + dot(dh.lin, dh.lin)));
  }
  return drift;
}

/// A deterministic, unremarkable initial state: joint angles and speeds of order one, a base
/// turned about a skew axis and moving in every direction.
inline State initial_state(const dyngen::Model<double>& model) {
  State x{std::vector<double>(model.nq), std::vector<double>(model.nv)};
  for (int k = 0; k < model.nq; ++k) x.q[k] = std::sin(1.3 * k + 0.4);
  for (int k = 0; k < model.nv; ++k) x.v[k] = std::cos(0.7 * k + 0.2);
  for (int i = 0; i < model.nbodies; ++i)
    if (const int o = dyngen::quaternion_offset(model.joint_type[i]); o >= 0) {
      double* w = &x.q[model.q_index[i] + o];
      const double c = std::cos(0.6), s = std::sin(0.6) / std::sqrt(3.0);
      w[0] = c, w[1] = s, w[2] = -s, w[3] = s;
    }
  return x;
}

}  // namespace rollout
