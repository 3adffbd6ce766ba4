// Where the algorithms say which body and pass they are working on. For arithmetic scalars
// this costs nothing; the generator specialises it for its symbolic scalar so that every
// recorded operation knows its link and pass, and the emitted code is grouped by them.
#pragma once

#include <cstdint>

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
  }
  return "?";
}

template <class S>
struct TraceHook {
  static void enter(int /*body*/, Pass /*pass*/) {}
};

}  // namespace dyngen
