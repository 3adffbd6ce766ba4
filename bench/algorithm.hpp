// The algorithms bench/ times against the peers and counts against the hand-written planar
// chain: the three that MuJoCo, KDL and planar_reference.hpp also compute.
#pragma once

namespace dyngen::bench {

enum class Algorithm { Rnea, Crba, Aba };

/// Its name in the runtime's table (dyngen/algorithms.hpp) and in the generated code.
inline const char* algorithm_name(Algorithm a) {
  return a == Algorithm::Rnea ? "rnea" : a == Algorithm::Crba ? "crba" : "aba";
}

}  // namespace dyngen::bench
