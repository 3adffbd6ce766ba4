// The definitions of the bit-for-bit comparison that dyngen/check.hpp declares (documented
// there): included by it, or by the one file that compiles them for a build's checks.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "dyngen/algorithms.hpp"
#include "dyngen/check.hpp"
#include "dyngen/model.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen::check {

/// A double from raw mt19937_64 bits: the same on every standard library.
inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

inline std::string show(double x) {
  char text[80];
  std::snprintf(text, sizeof text, "%.17g (%a)", x, x);
  return text;
}

template <class S>
std::string show(const std::vector<S>& xs) {
  std::string s;
  for (const S x : xs) s += (s.empty() ? "" : ", ") + show(static_cast<double>(x));
  return "[" + s + "]";
}

template <class S>
bool same_bits(S a, S b) {
  if (a == 0 && b == 0) return true;  // +0 and -0 may differ (docs/design.md)
  return std::memcmp(&a, &b, sizeof(S)) == 0;
}

/// Zeroed arrays of the lengths `arrays` have for `model`, each `copies` times.
template <class S>
Arrays<S> sized(const Model<S>& model, const std::vector<ArraySpec>& arrays,
                std::size_t copies = 1) {
  Arrays<S> x;
  for (const ArraySpec& a : arrays) x.emplace_back(extent_size(a.extent, model) * copies);
  return x;
}

/// The inputs of `spec` for state number s: configurations (q, q_target), v and the other arrays (a,
/// tau) random within their ranges, a free or ball joint's quaternion a unit one.
template <class S>
Arrays<S> make_inputs(const Model<S>& model, const AlgorithmSpec<S>& spec, States states, int s) {
  std::mt19937_64 rng(0x64796e67656e + static_cast<std::uint64_t>(s));
  const bool extreme = s >= states.random;
  const double q_range = extreme ? std::pow(10.0, 1 + (s % 6)) : 3.2;
  const double v_range = extreme ? 1e3 : 10.0;
  const double x_range = extreme ? 1e4 : 100.0;
  Arrays<S> x = sized(model, spec.inputs);
  for (std::size_t k = 0; k < x.size(); ++k) {
    const std::string_view name = spec.inputs[k].name;
    const bool configuration = spec.inputs[k].extent.size == Extent::Nq;
    const double range = configuration ? q_range : name == "v" ? v_range : x_range;
    for (S& e : x[k]) e = static_cast<S>(uniform(rng, -range, range));
    if (!configuration) continue;
    // the algorithms assume a unit quaternion: a huge one would overflow, and the contract
    // holds for computations that stay finite
    for (int i = 0; i < model.nbodies; ++i) {
      const int o = quaternion_offset(model.joint_type[i]);
      if (o < 0) continue;
      S* w = &x[k][model.q_index[i] + o];
      const double w0 = uniform(rng, -1, 1), w1 = uniform(rng, -1, 1), w2 = uniform(rng, -1, 1),
                   w3 = uniform(rng, -1, 1);
      const double norm = std::sqrt(w0 * w0 + w1 * w1 + w2 * w2 + w3 * w3);
      w[0] = static_cast<S>(w0 / norm), w[1] = static_cast<S>(w1 / norm);
      w[2] = static_cast<S>(w2 / norm), w[3] = static_cast<S>(w3 / norm);
    }
  }
  return x;
}

/// The first entry of output `output` where `generated` and `runtime` differ, with the inputs.
/// Equal NaNs would pass as equal bits but prove nothing: the states are finite and so must be
/// the outputs.
template <class S>
testing::AssertionResult same_outputs(const AlgorithmSpec<S>& spec, std::size_t output,
                                      States states, int s, const Arrays<S>& x,
                                      const std::vector<S>& generated,
                                      const std::vector<S>& runtime) {
  for (std::size_t k = 0; k < generated.size(); ++k) {
    if (same_bits(generated[k], runtime[k]) && std::isfinite(generated[k]) &&
        std::isfinite(runtime[k]))
      continue;
    testing::AssertionResult failure = testing::AssertionFailure();
    failure << spec.name << ": " << spec.outputs[output].name << "[" << k
            << "] differs or is not finite at state " << s
            << (s >= states.random ? " (extreme)" : " (random)") << "\n  generated "
            << show(static_cast<double>(generated[k])) << "\n  runtime   "
            << show(static_cast<double>(runtime[k]));
    for (std::size_t i = 0; i < x.size(); ++i)
      failure << "\n  " << spec.inputs[i].name << " = " << show(x[i]);
    return failure;
  }
  return testing::AssertionSuccess();
}

/// Fills every array with NaN, so that an output the function under test leaves unwritten fails
/// the comparison (a missed store of a zero would otherwise keep the zero put there before).
template <class S>
void poison(Arrays<S>& arrays) {
  for (std::vector<S>& a : arrays)
    std::fill(a.begin(), a.end(), std::numeric_limits<S>::quiet_NaN());
}

/// The runtime's algorithm `name` for `model`, called on arrays.
template <class S>
class Runtime {
 public:
  Runtime(const Model<S>& model, const char* name)
      : model_(model), spec_(find_algorithm<S>(name)), ws_(model) {}
  const AlgorithmSpec<S>* spec() const { return spec_; }
  void operator()(const Arrays<S>& x, Arrays<S>& y) {
    const std::vector<std::span<const S>> in(x.begin(), x.end());
    const std::vector<std::span<S>> out(y.begin(), y.end());
    spec_->call(model_, ws_, in, out);
  }

 private:
  const Model<S>& model_;
  const AlgorithmSpec<S>* spec_;
  Workspace<S> ws_;
};

template <class S>
void bit_for_bit(const Model<S>& model, States states, const char* name, Function<S> generated) {
  Runtime<S> runtime(model, name);
  ASSERT_NE(runtime.spec(), nullptr) << "the runtime has no algorithm " << name;
  const AlgorithmSpec<S>& spec = *runtime.spec();
  Arrays<S> expected = sized(model, spec.outputs), mine = sized(model, spec.outputs);
  for (int s = 0; s < states.all(); ++s) {
    const Arrays<S> x = make_inputs(model, spec, states, s);
    runtime(x, expected);
    poison(mine);
    generated(x, mine);
    for (std::size_t k = 0; k < expected.size(); ++k)
      ASSERT_TRUE(same_outputs(spec, k, states, s, x, mine[k], expected[k]));
  }
}

template <class S>
void batch_bit_for_bit(const Model<S>& model, States states, int lanes, const char* name,
                       Function<S> batch, ManyFunction<S> many) {
  Runtime<S> runtime(model, name);
  ASSERT_NE(runtime.spec(), nullptr) << "the runtime has no algorithm " << name;
  const AlgorithmSpec<S>& spec = *runtime.spec();
  const std::size_t width = static_cast<std::size_t>(lanes);
  Arrays<S> expected = sized(model, spec.outputs), mine = sized(model, spec.outputs);
  Arrays<S> x_lanes = sized(model, spec.inputs, width), y_lanes = sized(model, spec.outputs, width);
  for (int first = 0; first < states.all(); first += lanes) {
    std::vector<Arrays<S>> xs;
    for (std::size_t l = 0; l < width; ++l) {
      xs.push_back(make_inputs(model, spec, states, (first + int(l)) % states.all()));
      for (std::size_t k = 0; k < x_lanes.size(); ++k)
        for (std::size_t i = 0; i < xs[l][k].size(); ++i) x_lanes[k][i * width + l] = xs[l][k][i];
    }
    poison(y_lanes);
    batch(x_lanes, y_lanes);
    for (std::size_t l = 0; l < width; ++l) {
      runtime(xs[l], expected);
      for (std::size_t k = 0; k < mine.size(); ++k) {
        for (std::size_t i = 0; i < mine[k].size(); ++i) mine[k][i] = y_lanes[k][i * width + l];
        ASSERT_TRUE(same_outputs(spec, k, states, (first + int(l)) % states.all(), xs[l], mine[k],
                                 expected[k]))
            << "in lane " << l << " of " << lanes;
      }
    }
  }
  const int count = 2 * lanes + 1;
  const std::size_t rows = static_cast<std::size_t>(count);
  Arrays<S> x_rows = sized(model, spec.inputs, rows), y_rows = sized(model, spec.outputs, rows);
  std::vector<Arrays<S>> xs;
  for (int s = 0; s < count; ++s) {
    xs.push_back(make_inputs(model, spec, states, s));
    for (std::size_t k = 0; k < x_rows.size(); ++k)
      std::copy(xs[s][k].begin(), xs[s][k].end(),
                x_rows[k].begin() + static_cast<std::ptrdiff_t>(s * xs[s][k].size()));
  }
  poison(y_rows);
  many(count, x_rows, y_rows);
  for (int s = 0; s < count; ++s) {
    runtime(xs[s], expected);
    for (std::size_t k = 0; k < mine.size(); ++k) {
      std::copy_n(y_rows[k].begin() + static_cast<std::ptrdiff_t>(s * mine[k].size()),
                  mine[k].size(), mine[k].begin());
      ASSERT_TRUE(same_outputs(spec, k, states, s, xs[s], mine[k], expected[k]))
          << "in the function over " << count << " states";
    }
  }
}

template <class S>
void model_matches(const Model<S>& model, int nq, int nv, const char* const* names) {
  ASSERT_EQ(model.nq, nq);
  ASSERT_EQ(model.nv, nv);
  const std::vector<std::string> velocity = velocity_names(model);
  for (int k = 0; k < nv; ++k) EXPECT_EQ(velocity[std::size_t(k)], names[k]);
}

}  // namespace dyngen::check
