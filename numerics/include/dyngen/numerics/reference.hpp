// The truth for every error figure: the runtime's own algorithms instantiated with MPFR
// numbers (mpfr::mpreal, 256 bits or more), on the double model converted exactly.
//
// Errors are norm-wise and relative: ||x - x_ref||_2 / max(||x_ref||_2, error_floor), with the
// difference and the norms taken in the exact type, so that the error of a float or double
// result is measured without rounding of its own.
#pragma once

#include <mpreal.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include <stdexcept>
#include <string>
#include <string_view>

#include "dyngen/aba.hpp"
#include "dyngen/algorithms.hpp"
#include "dyngen/crba.hpp"
#include "dyngen/numerics/random.hpp"
#include "dyngen/rnea.hpp"

namespace dyngen::numerics {

using Exact = mpfr::mpreal;

/// Bits of the exact type's significand at least: 77 decimal digits, far beyond double's 16.
inline constexpr int exact_bits = 256;

/// Bits for a robot whose forward dynamics may lose `digits_lost` decimal digits (the
/// conditioning estimate's aba_digits_lost): the reference runs the same algorithm and loses
/// them too, so it carries them on top of 40 digits to spare.
inline int reference_bits(double digits_lost) {
  return std::max(exact_bits, static_cast<int>(std::ceil((digits_lost + 40) * 3.33)));
}

/// The absolute floor of the relative error's denominator, in the output's units (N m, kg m^2,
/// rad/s^2): it only keeps an exactly zero reference from dividing by zero.
inline constexpr double error_floor = 1e-300;

template <class S>
std::vector<Exact> widen(std::span<const S> x) {
  std::vector<Exact> out;
  out.reserve(x.size());
  for (const S& xi : x) out.emplace_back(static_cast<double>(xi));
  return out;
}

/// The runtime on MPFR numbers of `bits` bits, for one model. mpreal numbers take MPFR's
/// default precision when they are made, so every call sets it to `bits` first.
class ExactDynamics {
 public:
  explicit ExactDynamics(const Model<double>& model, int bits = exact_bits)
      : bits_(bits), model_(cast_with_precision(model, bits)), ws_(model_) {}

  const Model<Exact>& model() const { return model_; }
  int bits() const { return bits_; }

  std::vector<Exact> rnea(std::span<const double> q, std::span<const double> qd,
                          std::span<const double> qdd) {
    mpfr::mpreal::set_default_prec(bits_);
    std::vector<Exact> tau(model_.nv);
    const std::vector<Exact> eq = widen(q), eqd = widen(qd), eqdd = widen(qdd);
    dyngen::rnea<Exact>(model_, ws_, eq, eqd, eqdd, tau);
    return tau;
  }

  std::vector<Exact> crba(std::span<const double> q) {
    mpfr::mpreal::set_default_prec(bits_);
    std::vector<Exact> M(static_cast<std::size_t>(model_.nv) * model_.nv);
    const std::vector<Exact> eq = widen(q);
    dyngen::crba<Exact>(model_, ws_, eq, M);
    return M;
  }

  std::vector<Exact> aba(std::span<const double> q, std::span<const double> qd,
                         std::span<const double> tau) {
    mpfr::mpreal::set_default_prec(bits_);
    std::vector<Exact> qdd(model_.nv);
    const std::vector<Exact> eq = widen(q), eqd = widen(qd), etau = widen(tau);
    dyngen::aba<Exact>(model_, ws_, eq, eqd, etau, qdd);
    return qdd;
  }

  /// Any algorithm of the runtime's table (algorithms.hpp) by name: its outputs, given its
  /// inputs in the table's order.
  std::vector<std::vector<Exact>> run(std::string_view algorithm,
                                      const std::vector<std::span<const double>>& inputs) {
    const AlgorithmSpec<Exact>* spec = find_algorithm<Exact>(algorithm);
    if (!spec) throw std::invalid_argument("no algorithm named " + std::string(algorithm));
    mpfr::mpreal::set_default_prec(bits_);
    std::vector<std::vector<Exact>> in, out;
    for (const std::span<const double>& x : inputs) in.push_back(widen(x));
    for (const ArraySpec& y : spec->outputs) out.emplace_back(extent_size(y.extent, model_));
    const std::vector<std::span<const Exact>> in_spans(in.begin(), in.end());
    const std::vector<std::span<Exact>> out_spans(out.begin(), out.end());
    spec->call(model_, ws_, in_spans, out_spans);
    return out;
  }

 private:
  static Model<Exact> cast_with_precision(const Model<double>& model, int bits) {
    mpfr::mpreal::set_default_prec(bits);
    return model.cast<Exact>();
  }

  int bits_;
  Model<Exact> model_;
  Workspace<Exact> ws_;
};

/// Rounds exact values to double.
inline std::vector<double> to_double(const std::vector<Exact>& x) {
  std::vector<double> out;
  out.reserve(x.size());
  for (const Exact& xi : x) out.push_back(xi.toDouble());
  return out;
}

/// ||x - ref||_2 / max(||ref||_2, error_floor), taken exactly; +inf when x is not finite.
template <class S>
double relative_error(std::span<const S> x, std::span<const Exact> ref) {
  Exact diff = 0, norm = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!std::isfinite(static_cast<double>(x[k]))) return std::numeric_limits<double>::infinity();
    const Exact d = Exact(static_cast<double>(x[k])) - ref[k];
    diff += d * d;
    norm += ref[k] * ref[k];
  }
  const Exact floor = error_floor;
  return (mpfr::sqrt(diff) / std::max(mpfr::sqrt(norm), floor)).toDouble();
}

template <class S>
double relative_error(const std::vector<S>& x, const std::vector<Exact>& ref) {
  return relative_error(std::span<const S>(x), std::span<const Exact>(ref));
}

/// A state whose torques are the exact inverse dynamics of its (q, qd, qdd), rounded to
/// double: forward dynamics then has an answer of the scale of qdd on any robot, however
/// light or heavy its links.
inline void set_consistent_torques(ExactDynamics& exact, State& s) {
  s.tau = to_double(exact.rnea(s.q, s.qd, s.qdd));
}

}  // namespace dyngen::numerics
