#include "range.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "dyngen/kernels.hpp"
#include "dyngen/numerics/random.hpp"

namespace dyngen::gen {

namespace {

/// State s of a kind: each input array by name, drawn as the generated check draws them and
/// rounded to T.
template <class T>
std::map<std::string, std::vector<T>> sample_state(const Model<double>& model, bool extreme,
                                                   int s) {
  numerics::Random rng(0x72616e6765 + static_cast<std::uint64_t>(2 * s + extreme));
  const double q_range = extreme ? 1e6 : 3.2, v_range = extreme ? 1e3 : 10,
               x_range = extreme ? 1e4 : 100;
  const auto configuration = [&] {
    std::vector<double> q = rng.vector(model.nq, -q_range, q_range);
    for (int i = 0; i < model.nbodies; ++i)
      if (const int o = quaternion_offset(model.joint_type[i]); o >= 0) {
        const std::vector<double> w = numerics::random_unit_quaternion(rng);
        std::copy(w.begin(), w.end(), q.begin() + model.q_index[i] + o);
      }
    return q;
  };
  std::map<std::string, std::vector<T>> state;
  auto set = [&](const char* name, const std::vector<double>& x) {
    for (const double e : x) state[name].push_back(static_cast<T>(e));
  };
  set("q", configuration());
  set("v", rng.vector(model.nv, -v_range, v_range));
  set("a", rng.vector(model.nv, -x_range, x_range));
  set("tau", rng.vector(model.nv, -x_range, x_range));
  set("q_target", configuration());
  set("anchors", rng.vector(model.nc, -1, 1));
  return state;
}

/// Runs a recorded kernel call on numbers: its ints, tables and arrays in the order the
/// emitted call passes them.
template <class T>
void run_call(const KernelRecord& call, const std::vector<std::vector<T>>& in,
              std::vector<std::vector<T>>& out) {
  const auto& t = call.tables;
  if (call.kernel == "derivative_pairs" && in.size() == 3 && out.size() == 2)
    kernels::derivative_pairs(call.ints.at(0), call.ints.at(1), t.at(0).data(), t.at(1).data(),
                              t.at(2).data(), in[0].data(), in[1].data(), in[2].data(),
                              out[0].data(), out[1].data());
  else if (call.kernel == "neg_product" && in.size() == 2 && out.size() == 1)
    kernels::neg_product(call.ints.at(0), t.at(0).data(), t.at(1).data(), in[0].data(),
                         in[1].data(), out[0].data());
  else if (call.kernel == "constrained_columns" && in.size() == 6 && out.size() == 3)
    kernels::constrained_columns(call.ints.at(0), call.ints.at(1), t.at(0).data(), t.at(1).data(),
                                 t.at(2).data(), t.at(3).data(), t.at(4).data(), in[0].data(),
                                 in[1].data(), in[2].data(), in[3].data(), in[4].data(),
                                 in[5].data(), out[0].data(), out[1].data(), out[2].data());
  else if (call.kernel == "inverse_blocks" && in.size() == 3 && out.size() == 2)
    kernels::inverse_blocks(call.ints.at(0), call.ints.at(1), in[0].data(), in[1].data(),
                            in[2].data(), out[0].data(), out[1].data());
  else
    throw std::logic_error("internal error: no range evaluation of kernel " + call.kernel);
}

/// |x op y| in long double: what a value would be without T's range.
long double unbounded(Op op, long double x, long double y) {
  switch (op) {
    case Op::Add: return std::fabs(x + y);
    case Op::Sub: return std::fabs(x - y);
    case Op::Mul: return std::fabs(x * y);
    case Op::Div: return std::fabs(x / y);
    default: return HUGE_VALL;  // a kernel's result: computed inside its loops
  }
}

constexpr int states = 2 * range_samples;  // the typical ones, then the extreme ones

template <class T>
using Lanes = std::array<T, states>;

/// Each input's value at every state, by the index of Graph::inputs.
template <class T>
std::vector<Lanes<T>> input_values(const Graph<T>& g, const Model<double>& model) {
  std::vector<Lanes<T>> values(g.inputs.size());
  for (int s = 0; s < states; ++s) {
    const auto state = sample_state<T>(model, s >= range_samples, s % range_samples);
    for (std::size_t k = 0; k < g.inputs.size(); ++k)
      values[k][s] = state.at(g.inputs[k].array).at(static_cast<std::size_t>(g.inputs[k].index));
  }
  return values;
}

/// A kernel call's outputs at every state, laid end to end, from its inputs' values.
template <class T>
std::vector<Lanes<T>> run_call(const KernelRecord& call, const auto& value_of) {
  std::vector<Lanes<T>> results;
  for (const std::size_t size : call.outputs) results.resize(results.size() + size);
  for (int s = 0; s < states; ++s) {
    std::vector<std::vector<T>> in, out;
    for (const std::vector<int>& array : call.inputs) {
      std::vector<T>& x = in.emplace_back();
      for (const int id : array) x.push_back(value_of(id)[s]);
    }
    for (const std::size_t size : call.outputs) out.emplace_back(size);
    run_call(call, in, out);
    std::size_t e = 0;
    for (const std::vector<T>& y : out)
      for (const T x : y) results[e++][s] = x;
  }
  return results;
}

}  // namespace

template <class T>
RangeEstimate estimate_range(const Program<T>& program, const Model<double>& model) {
  const Graph<T>& g = program.graph;
  const int n = static_cast<int>(g.nodes.size());
  // the live nodes, and the last that reads each: its value's slot is free after that
  std::vector<char> live(n, 0);
  for (const int id : program.stored) live[id] = 1;
  for (int id = n - 1; id >= 0; --id)
    if (live[id]) g.for_each_operand(id, [&](int x) { live[x] = 1; });
  std::vector<int> last(n, -1);
  for (int id = 0; id < n; ++id)
    if (live[id]) g.for_each_operand(id, [&](int x) { last[x] = id; });

  const std::vector<Lanes<T>> inputs = input_values(g, model);
  std::vector<Lanes<T>> values, results;  // values by slot; the current call's results
  std::vector<int> slot(n, -1), free_slots;
  const auto value_of = [&](int id) -> const Lanes<T>& { return values[slot[id]]; };
  RangeEstimate estimate;
  for (int id = 0; id < n; ++id) {
    if (!live[id]) continue;
    const Node<T>& node = g.nodes[id];
    if (free_slots.empty()) {
      free_slots.push_back(static_cast<int>(values.size()));
      values.emplace_back();
    }
    slot[id] = free_slots.back();
    free_slots.pop_back();
    Lanes<T>& y = values[slot[id]];
    const bool call = node.op == Op::Call || node.op == Op::Result;  // a: a call, not a value
    const Lanes<T>* a = node.a >= 0 && !call ? &value_of(node.a) : nullptr;
    const Lanes<T>* b = node.b >= 0 ? &value_of(node.b) : nullptr;
    const auto each = [&](const auto& f) {
      for (int s = 0; s < states; ++s) y[s] = f(s);
    };
    switch (node.op) {
      case Op::Const: y.fill(node.value); break;
      case Op::Input: y = inputs[node.input]; break;
      case Op::Neg: each([&](int s) { return -(*a)[s]; }); break;
      case Op::Add: each([&](int s) { return (*a)[s] + (*b)[s]; }); break;
      case Op::Sub: each([&](int s) { return (*a)[s] - (*b)[s]; }); break;
      case Op::Mul: each([&](int s) { return (*a)[s] * (*b)[s]; }); break;
      case Op::Div: each([&](int s) { return (*a)[s] / (*b)[s]; }); break;
      case Op::Sin:
      case Op::Cos:
        each([&](int s) {
          T sin_a, cos_a;
          sincos((*a)[s], sin_a, cos_a);  // the runtime's, as the generated code calls it
          return node.op == Op::Sin ? sin_a : cos_a;
        });
        break;
      case Op::Fn:
        each([&](int s) {
          return call_function(static_cast<Function>(node.input), (*a)[s], b ? (*b)[s] : T{});
        });
        break;
      case Op::Call: break;
      case Op::Result: y = results.at(static_cast<std::size_t>(node.input)); break;
    }
    if (node.op == Op::Call) results = run_call<T>(g.calls[node.a], value_of);
    if (node.op != Op::Const && node.op != Op::Input && node.op != Op::Call)
      for (const bool extreme : {false, true}) {
        Range& r = extreme ? estimate.extreme : estimate.typical;
        T largest = 0;  // NaN and the infinities fail the comparison
        bool finite = true;
        for (int s = extreme ? range_samples : 0; s < (extreme ? states : range_samples); ++s) {
          const T m = std::fabs(y[s]);
          largest = m > largest && m <= std::numeric_limits<T>::max() ? m : largest;
          finite = finite && m <= std::numeric_limits<T>::max();
        }
        r.largest = std::max(r.largest, static_cast<long double>(largest));
        if (finite || r.overflow >= 0) continue;
        // the first value beyond the range, and what it would be at its worst state
        r.overflow = id;
        for (int s = extreme ? range_samples : 0; s < (extreme ? states : range_samples); ++s) {
          const long double would_be = unbounded(node.op, a ? (*a)[s] : 0, b ? (*b)[s] : 0);
          if (!(std::fabs(y[s]) <= std::numeric_limits<T>::max()) &&
              !(would_be <= r.overflow_value))  // NaN (0 / 0) too
            r.overflow_value = would_be;
        }
      }
    // free the slots of the values no later node reads, this one's too if none does
    g.for_each_operand(id, [&](int x) {
      if (last[x] == id && slot[x] >= 0) free_slots.push_back(slot[x]), slot[x] = -1;
    });
    if (last[id] < 0) free_slots.push_back(slot[id]), slot[id] = -1;
  }
  return estimate;
}

template RangeEstimate estimate_range<double>(const Program<double>&, const Model<double>&);
template RangeEstimate estimate_range<float>(const Program<float>&, const Model<double>&);

}  // namespace dyngen::gen
