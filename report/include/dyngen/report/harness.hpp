// dyngen report's harness (dyngen::report_harness): report/harness.cpp measures every variant;
// runtime.cpp and ldlt.cpp hold the runtime's algorithms and CRBA+LDL^T in double and float;
// reference.cpp the MPFR reference. They know no robot, and are compiled once, with dyngen.
// What dyngen report writes for a robot, variants.cpp, defines the robot's model and its
// variants (robot_model and add_variants below), and is linked with them.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <dyngen/algorithms.hpp>
#include <dyngen/numerics/random.hpp>

namespace dyngen_report {

/// A call of one way of computing an algorithm: its inputs x and outputs y in the order of the
/// runtime's table.
template <class S>
using Call = std::function<void(const S* const* x, S* const* y)>;

/// The robot's model, as its generated code was traced from it (variants.cpp).
dyngen::Model<double> robot_model();

/// Registers every variant with add_runtime and add (variants.cpp); the FMA variant only when
/// the processor has FMA instructions.
void add_variants(bool fma);

/// Registers the runtime's algorithm in scalar type S (harness.cpp).
template <class S>
void add_runtime(const std::string& algorithm);

/// Registers a variant: a way of computing an algorithm in scalar type S (harness.cpp).
template <class S>
void add(const std::string& algorithm, const std::string& variant, Call<S> f);

/// The runtime's table entry of an algorithm in scalar type S, or nullptr (runtime.cpp).
template <class S>
const dyngen::AlgorithmSpec<S>* runtime_algorithm(std::string_view name);

template <class S>
using CrbaFunction = void (*)(const S* q, S* M);
template <class S>
using RneaFunction = void (*)(const S* q, const S* v, const S* a, S* tau);

/// Forward dynamics through a CRBA, an RNEA and Eigen's LDL^T for a robot of nv degrees of
/// freedom (ldlt.cpp).
template <class S>
void ldlt_forward_dynamics(int nv, CrbaFunction<S> crba, RneaFunction<S> rnea, const S* q,
                           const S* v, const S* tau, S* qdd);

/// The MPFR reference: the runtime on numbers of at least 256 bits (reference.cpp).
class Reference {
 public:
  Reference(const dyngen::Model<double>& model, int bits);
  ~Reference();

  int bits() const;

  /// The floor of the relative error's denominator.
  static double error_floor();

  /// Sets the state's torques to the exact inverse dynamics of its (q, qd, qdd), rounded to
  /// double: forward dynamics then has an answer of the scale of qdd.
  void set_consistent_torques(dyngen::numerics::State& s);

  /// Computes an algorithm exactly at inputs x, in the order of the runtime's table.
  void compute(std::string_view algorithm, const std::vector<std::span<const double>>& x);

  /// The largest of the relative errors of outputs y against the last computed ones.
  double error(const std::vector<std::vector<double>>& y) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dyngen_report
