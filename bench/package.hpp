// One package of generated code that dyngen_bench times, and how its robot was loaded.
#pragma once

#include <vector>

#include "dyngen/numerics/random.hpp"
#include "robot.hpp"
#include "algorithm.hpp"
#include "trace.hpp"

namespace dyngen::bench {

/// The three functions of one generated package.
struct Functions {
  void (*rnea)(const double* q, const double* v, const double* a, double* tau) noexcept;
  void (*crba)(const double* q, double* M) noexcept;
  void (*aba)(const double* q, const double* v, const double* tau, double* qdd) noexcept;
};

struct Package {
  const char* name;    // robot, robot_floating or KIND_chainN: the C++ namespace
  const char* robot;   // the robot, or planar_chain / spatial_chain
  const char* base;    // fixed or floating
  int links;           // chains: number of links; robots: 0
  const char* input;   // what dyngen read
  const char* urdf;    // what MuJoCo and KDL read: input, or the chain's URDF twin
  const char* header;  // NAME_dynamics.hpp, whose banner has the operation counts
  const char* snapped_header;  // the same for the snapped code (null for the chains)
  bool floating_base, mimic_independent, lock_massless;  // dyngen's load options
  Functions generated;
  Functions snapped;  // the code dyngen --snap 1e-9 writes (null for the chains)
  Functions unrolled;  // the code dyngen --structure unrolled writes
  Functions copy;  // generated's code in a second library, at another address (null for chains)
};

/// Every package, in the order of bench/CMakeLists.txt.
const std::vector<Package>& packages();

/// The options dyngen loaded the package's robot with (snapped: those of its snapped code).
inline gen::LoadOptions load_options(const Package& p, bool snapped = false) {
  gen::LoadOptions options;
  options.floating_base = p.floating_base;
  options.mimic_independent = p.mimic_independent;
  options.lock_massless = p.lock_massless;
  if (snapped) options.snap = 1e-9;
  return options;
}

/// One call of a generated function at state s: tau, M (row-major) or qdd into out.
inline void call(const Functions& f, Algorithm a, const numerics::State& s, double* out) {
  switch (a) {
    case Computes::Other: break;
    case Computes::InverseDynamics: f.rnea(s.q.data(), s.qd.data(), s.qdd.data(), out); break;
    case Computes::MassMatrix: f.crba(s.q.data(), out); break;
    case Computes::ForwardDynamics: f.aba(s.q.data(), s.qd.data(), s.tau.data(), out); break;
  }
}

}  // namespace dyngen::bench
