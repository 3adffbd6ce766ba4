// The algorithms bench/ times against the peers and counts against the hand-written planar
// chain: the runtime table's entries that compute one of the three quantities that MuJoCo, KDL
// and planar_reference.hpp also compute (Computes, dyngen/algorithms.hpp). The peers' calls
// differ per quantity, so bench/ switches on it; the switches' Computes::Other does nothing,
// since compared_algorithms() never holds it.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "dyngen/algorithms.hpp"

namespace dyngen::bench {

/// A compared algorithm, by what it computes.
using Algorithm = Computes;

/// The compared algorithms, in the table's order.
inline const std::vector<Algorithm>& compared_algorithms() {
  static const std::vector<Algorithm> algorithms = [] {
    std::vector<Algorithm> out;
    for (const AlgorithmSpec<double>& a : algorithm_table<double>())
      if (a.computes != Computes::Other) out.push_back(a.computes);
    return out;
  }();
  return algorithms;
}

/// The compared algorithm named name, if one is.
inline std::optional<Algorithm> compared_algorithm(std::string_view name) {
  for (const Algorithm a : compared_algorithms())
    if (find_algorithm<double>(a)->name == name) return a;
  return std::nullopt;
}

/// Its name in the runtime's table and in the generated code (the table's names are string
/// literals, so the view ends in a null).
inline const char* algorithm_name(Algorithm a) { return find_algorithm<double>(a)->name.data(); }

}  // namespace dyngen::bench
