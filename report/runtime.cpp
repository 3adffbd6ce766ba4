// The runtime's algorithms in double and float, compiled with the generated code's exact-math
// flags, as they are timed against it.
#include <dyngen/algorithms.hpp>

#include "dyngen/report/harness.hpp"

namespace dyngen_report {

template <class S>
const dyngen::AlgorithmSpec<S>* runtime_algorithm(std::string_view name) {
  return dyngen::find_algorithm<S>(name);
}

template const dyngen::AlgorithmSpec<double>* runtime_algorithm<double>(std::string_view);
template const dyngen::AlgorithmSpec<float>* runtime_algorithm<float>(std::string_view);

}  // namespace dyngen_report
