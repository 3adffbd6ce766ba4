// Where the algorithms say which body and pass they are working on, and how they call kernels.
// For arithmetic scalars this costs nothing; the generator specialises it for its symbolic
// scalar so that every recorded operation knows its link and pass, and the emitted code is
// grouped by them, and so that a kernel's loops can become one recorded call.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace dyngen {

enum class Pass : std::uint8_t {
  Forward,             // RNEA: velocities, accelerations, body forces
  Backward,            // RNEA: joint forces
  Kinematics,          // CRBA: joint transforms
  CompositeInertia,    // CRBA: composite inertias and mass-matrix entries
  Column,              // CRBA: a descendant's column of M carried up to this body
  Velocity,            // ABA: velocities and bias forces
  ArticulatedInertia,  // ABA: articulated inertias
  Acceleration,        // ABA: joint accelerations
  Pairs,               // derivatives: the entries of pairs of joints (a kernel)
  Product,             // derivatives: a matrix product (a kernel)
  Factor,              // derivatives: M = L^T D L and its inverse
  Frames,              // frames: the placements and accelerations of the frames on a body
  JacobianColumns,     // frames, centre of mass, centroidal momentum: a joint's columns
  Constraints,         // constraints: their accelerations, operational space and solve
  Configuration,       // integrate, difference: the joint's exponential or logarithm
};

inline const char* pass_name(Pass p) {
  switch (p) {
    case Pass::Forward: return "forward pass";
    case Pass::Backward: return "backward pass";
    case Pass::Kinematics: return "kinematics";
    case Pass::CompositeInertia: return "composite inertia";
    case Pass::Column: return "a descendant's column of M carried up";
    case Pass::Velocity: return "velocity pass";
    case Pass::ArticulatedInertia: return "articulated inertia pass";
    case Pass::Acceleration: return "acceleration pass";
    case Pass::Pairs: return "pairs of joints";
    case Pass::Product: return "matrix product";
    case Pass::Factor: return "factorisation of M";
    case Pass::Frames: return "its frames";
    case Pass::JacobianColumns: return "its joint's Jacobian columns";
    case Pass::Constraints: return "constraints";
    case Pass::Configuration: return "configuration space";
  }
  return "?";
}

template <class S>
struct TraceHook {
  static void enter(int /*body*/, Pass /*pass*/) {}
};

/// A call of a function of dyngen::kernels (kernels.hpp), described for a tracer: the kernel's
/// parameters are its int arguments, then its int tables (model data), then the arrays it reads,
/// then those it writes, in that order; names name the tables, then the arrays.
template <class S>
struct KernelCall {
  std::string_view kernel;
  std::span<const int> ints;
  std::span<const std::span<const int>> tables;
  std::span<const std::span<const S>> inputs;
  std::span<const std::span<S>> outputs;
  std::span<const std::string_view> names;
};

/// For arithmetic scalars a kernel runs; the generator specialises this for its symbolic scalar,
/// which may record the call as one operation instead of running its loops.
template <class S>
struct KernelHook {
  template <class Run>
  static bool record(const KernelCall<S>& /*call*/, const Run& /*run*/) {
    return false;
  }
};

/// Runs a kernel: run(inputs, outputs) calls it on the call's arrays, unless a tracer records
/// the call instead.
template <class S, class Run>
void run_kernel(const KernelCall<S>& call, const Run& run) {
  if (!KernelHook<S>::record(call, run)) run(call.inputs, call.outputs);
}

}  // namespace dyngen
