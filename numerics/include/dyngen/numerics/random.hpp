// Seeded random numbers and random states, the same on every standard library: doubles are
// built from the raw 64-bit output of std::mt19937_64 (whose sequence the standard fixes)
// instead of std::uniform_real_distribution (whose algorithm it does not).
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "dyngen/model.hpp"

namespace dyngen::numerics {

class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  /// Raw 64 random bits.
  std::uint64_t bits() { return engine_(); }

  /// Uniform in [0, 1): the top 53 bits scaled by 2^-53, so every value is exact.
  double uniform() { return static_cast<double>(bits() >> 11) * 0x1.0p-53; }

  /// Uniform between lo and hi (hi itself only through rounding).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  /// Uniform integer in [0, n), n > 0 (the modulo bias is below 2^-40 for small n).
  int index(int n) { return static_cast<int>(bits() % static_cast<std::uint64_t>(n)); }

  /// True with probability p.
  bool chance(double p) { return uniform() < p; }

  /// n values uniform between lo and hi.
  std::vector<double> vector(int n, double lo, double hi) {
    std::vector<double> x(n);
    for (double& xi : x) xi = uniform(lo, hi);
    return x;
  }

 private:
  std::mt19937_64 engine_;
};

/// A unit quaternion (w, x, y, z), uniformly distributed over rotations.
inline std::vector<double> random_unit_quaternion(Random& rng) {
  for (;;) {
    // uniform in the unit ball, away from 0, then normalised: uniform on the sphere
    const double w = rng.uniform(-1, 1), x = rng.uniform(-1, 1), y = rng.uniform(-1, 1),
                 z = rng.uniform(-1, 1);
    const double norm = std::sqrt(w * w + x * x + y * y + z * z);
    if (norm > 0.1 && norm <= 1) return {w / norm, x / norm, y / norm, z / norm};
  }
}

/// The inputs of one call of each algorithm: q has model.nq entries, the others model.nv.
struct State {
  std::vector<double> q, qd, qdd, tau;
};

/// q in [-pi, pi], qd and qdd in [-2, 2], tau in [-5, 5] (the same numbers in metres for
/// prismatic joints); a free joint's position in [-1, 1] m, and a random unit quaternion for
/// free and ball joints.
inline State random_state(const Model<double>& model, Random& rng) {
  State s;
  for (int i = 0; i < model.nbodies; ++i) {
    if (is_mimic(model, i)) continue;  // its primary's entry
    const int o = quaternion_offset(model.joint_type[i]);
    if (o < 0) {
      s.q.push_back(rng.uniform(-std::numbers::pi, std::numbers::pi));
      continue;
    }
    for (int k = 0; k < o; ++k) s.q.push_back(rng.uniform(-1, 1));
    const std::vector<double> w = random_unit_quaternion(rng);
    s.q.insert(s.q.end(), w.begin(), w.end());
  }
  s.qd = rng.vector(model.nv, -2, 2);
  s.qdd = rng.vector(model.nv, -2, 2);
  s.tau = rng.vector(model.nv, -5, 5);
  return s;
}

/// The state with every value rounded to float (and held as double again): the inputs that
/// float code sees.
inline State round_to_float(const State& s) {
  State r = s;
  for (std::vector<double>* x : {&r.q, &r.qd, &r.qdd, &r.tau})
    for (double& xi : *x) xi = static_cast<double>(static_cast<float>(xi));
  return r;
}

}  // namespace dyngen::numerics
