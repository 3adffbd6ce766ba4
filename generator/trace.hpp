// Runs the runtime's algorithms on the symbolic scalar for one model.
#pragma once

#include <string>
#include <vector>

#include "dyngen/model.hpp"
#include "symbolic.hpp"

namespace dyngen::gen {

enum class Algorithm { Rnea, Crba, Aba };

const char* algorithm_name(Algorithm a);

/// One traced function: its graph, the input arrays it reads and the nodes it stores.
template <class T>
struct Program {
  Algorithm algorithm;
  Graph<T> graph;
  std::vector<std::string> input_arrays;  // in signature order, each of length nv
  std::string output_array;
  int output_size = 0;
  std::vector<int> outputs;  // node stored in output_array[k]
};

/// The first constant that an output depends on and that is not finite, or -1. The trace computes
/// with constants what it can (constant folding, the same operations as the runtime's), so such
/// a constant is a number that overflows at every state: the model's numbers are out of T's range.
template <class T>
int first_non_finite_constant(const Program<T>& program);

/// Traces `algorithm` on the model converted to T. With simplify = false the graph holds
/// every operation the runtime performs for the same call, for counting.
template <class T>
Program<T> trace(Algorithm algorithm, const Model<double>& model, bool simplify = true);

}  // namespace dyngen::gen
