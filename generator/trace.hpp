// Runs the runtime's algorithms on the symbolic scalar for one model.
#pragma once

#include <string>
#include <vector>

#include "dyngen/algorithms.hpp"
#include "dyngen/model.hpp"
#include "symbolic.hpp"

namespace dyngen::gen {

/// An algorithm of the runtime's table (dyngen/algorithms.hpp), by its name: "rnea".
using Algorithm = std::string;

/// An extent as a C expression over the names of nq, nv, the numbers of frames and bodies and
/// the constraints' rows: "nv * nv", "nframes * 6 * nv", "nbodies * 10 * nv", "nc", "3".
std::string extent_text(const Extent& e, const std::string& nq, const std::string& nv,
                        const std::string& nframes, const std::string& nbodies,
                        const std::string& nc);

/// The names in the runtime's table, in its order.
std::vector<Algorithm> algorithm_names();

/// The names of the table's default set (in_default_set), in its order: what is generated
/// when --algorithms is not given.
std::vector<Algorithm> default_algorithm_names();

/// The table's entry for name (the same for every scalar but its call); throws
/// std::invalid_argument for a name not in it.
const AlgorithmSpec<double>& algorithm_spec(const Algorithm& name);

/// An array of a traced function with its length for the model.
struct ProgramArray {
  ArraySpec spec;
  std::size_t size;
};

/// One traced function: its graph, the arrays it reads and the nodes it stores.
template <class T>
struct Program {
  Algorithm algorithm;
  Graph<T> graph;
  std::vector<ProgramArray> inputs;   // in signature order
  std::vector<ProgramArray> outputs;  // in signature order, after the inputs
  std::vector<int> stored;            // node stored in each output entry, output by output
  /// The node of each own_angle_mimics body's angle, for a function of q: the plan reads their
  /// sines and cosines from the trig after q's.
  std::vector<int> mimic_angles;
};

/// The mimic joints that turn by an angle of their own (has_own_angle), in body order: the
/// trig holds the sine and cosine of the j-th one's at entry nq + j.
std::vector<int> own_angle_mimics(const Model<double>& model);

/// The first constant that an output depends on and that is not finite, or -1. The trace computes
/// with constants what it can (constant folding, the same operations as the runtime's), so such
/// a constant is a number that overflows at every state: the model's numbers are out of T's range.
template <class T>
int first_non_finite_constant(const Program<T>& program);

/// Kernel calls (dyngen/kernels.hpp) that would add fewer operations than this inlined are
/// inlined by default: their loops unrolled into the trace, which folds the work on exact zeros
/// and runs faster for small robots; above it, a call keeps the code of a 30-DoF robot's
/// derivatives small enough to compile in a minute (docs/performance.md, "Derivatives").
inline constexpr long default_call_kernels_from = 10000;

/// Traces `algorithm` on the model converted to T. With simplify = false the graph holds
/// every operation the runtime performs for the same call, for counting. Kernel calls that
/// would add at least call_kernels_from operations inlined stay calls; with vector_kernels (code
/// that runs the kernels in vector lanes: C++ on the host, one state at a time) so do those
/// that vector lanes run faster (vector_kernels_from); the others are inlined.
template <class T>
Program<T> trace(const Algorithm& algorithm, const Model<double>& model, bool simplify = true,
                 long call_kernels_from = default_call_kernels_from, bool vector_kernels = true);

}  // namespace dyngen::gen
