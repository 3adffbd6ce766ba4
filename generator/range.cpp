#include "range.hpp"

#include <algorithm>
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
  std::vector<double> q = rng.vector(model.nq, -q_range, q_range);
  for (int i = 0; i < model.nbodies; ++i)
    if (model.joint_type[i] == JointType::Free) {
      const std::vector<double> w = numerics::random_unit_quaternion(rng);
      std::copy(w.begin(), w.end(), q.begin() + model.q_index[i] + 3);
    }
  std::map<std::string, std::vector<T>> state;
  auto set = [&](const char* name, const std::vector<double>& x) {
    for (const double e : x) state[name].push_back(static_cast<T>(e));
  };
  set("q", q);
  set("v", rng.vector(model.nv, -v_range, v_range));
  set("a", rng.vector(model.nv, -x_range, x_range));
  set("tau", rng.vector(model.nv, -x_range, x_range));
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
  else
    throw std::logic_error("internal error: no range evaluation of kernel " + call.kernel);
}

/// The value of every live node at one state (dead ones 0), computed in T with the operations
/// of the generated code, so the bits it computes.
template <class T>
std::vector<T> evaluate(const Program<T>& program, const std::vector<bool>& live,
                        const std::map<std::string, std::vector<T>>& state) {
  const Graph<T>& g = program.graph;
  std::vector<T> x(g.nodes.size(), T(0));
  std::vector<std::vector<T>> results(g.calls.size());  // each call's outputs end to end
  for (std::size_t id = 0; id < g.nodes.size(); ++id) {
    if (!live[id]) continue;
    const Node<T>& n = g.nodes[id];
    const T a = n.a >= 0 ? x[n.a] : T(0), b = n.b >= 0 ? x[n.b] : T(0);
    T sin_a, cos_a;
    switch (n.op) {
      case Op::Const: x[id] = n.value; break;
      case Op::Input: {
        const InputRef& in = g.inputs[n.input];
        x[id] = state.at(in.array).at(static_cast<std::size_t>(in.index));
        break;
      }
      case Op::Neg: x[id] = -a; break;
      case Op::Add: x[id] = a + b; break;
      case Op::Sub: x[id] = a - b; break;
      case Op::Mul: x[id] = a * b; break;
      case Op::Div: x[id] = a / b; break;
      case Op::Sin:
      case Op::Cos:
        sincos(a, sin_a, cos_a);  // the runtime's, as the generated code calls it
        x[id] = n.op == Op::Sin ? sin_a : cos_a;
        break;
      case Op::Call: {
        const KernelRecord& call = g.calls[n.a];
        std::vector<std::vector<T>> in, out;
        for (const std::vector<int>& array : call.inputs) {
          std::vector<T>& v = in.emplace_back();
          for (const int e : array) v.push_back(x[e]);
        }
        for (const std::size_t size : call.outputs) out.emplace_back(size);
        run_call(call, in, out);
        for (const std::vector<T>& v : out)
          results[n.a].insert(results[n.a].end(), v.begin(), v.end());
        break;
      }
      case Op::Result:
        x[id] = results[g.nodes[n.a].a].at(static_cast<std::size_t>(n.input));
        break;
    }
  }
  return x;
}

/// |op(a, b)| in long double: what node n would be without T's range.
template <class T>
long double unbounded(const Node<T>& n, const std::vector<T>& x) {
  const long double a = n.a >= 0 ? x[n.a] : 0, b = n.b >= 0 ? x[n.b] : 0;
  switch (n.op) {
    case Op::Add: return std::fabs(a + b);
    case Op::Sub: return std::fabs(a - b);
    case Op::Mul: return std::fabs(a * b);
    case Op::Div: return std::fabs(a / b);
    default: return HUGE_VALL;  // a kernel's result: computed inside its loops
  }
}

}  // namespace

template <class T>
RangeEstimate estimate_range(const Program<T>& program, const Model<double>& model) {
  const Graph<T>& g = program.graph;
  std::vector<bool> live(g.nodes.size(), false);
  for (const int id : program.stored) live[id] = true;
  for (int id = static_cast<int>(g.nodes.size()) - 1; id >= 0; --id)
    if (live[id]) g.for_each_operand(id, [&](int x) { live[x] = true; });
  RangeEstimate estimate;
  for (const bool extreme : {false, true}) {
    Range& r = extreme ? estimate.extreme : estimate.typical;
    for (int s = 0; s < range_samples; ++s) {
      const std::vector<T> x = evaluate(program, live, sample_state<T>(model, extreme, s));
      for (std::size_t id = 0; id < x.size(); ++id) {
        const Node<T>& n = g.nodes[id];
        if (!live[id] || n.op == Op::Call || n.op == Op::Input || n.op == Op::Const) continue;
        const int node = static_cast<int>(id);
        if (std::isfinite(x[id])) {
          r.largest = std::max(r.largest, static_cast<long double>(std::fabs(x[id])));
        } else if (r.overflow < 0 || node <= r.overflow) {
          const long double would_be = unbounded(n, x);
          if (r.overflow != node || !(would_be <= r.overflow_value)) r.overflow_value = would_be;
          r.overflow = node;
        }
        if (n.op != Op::Div) continue;
        const long double d = std::fabs(x[n.b]);
        if (d < std::numeric_limits<T>::min() && (r.tiny_divisor < 0 || node <= r.tiny_divisor)) {
          if (r.tiny_divisor != node || d < r.divisor_value) r.divisor_value = d;
          r.tiny_divisor = node;
        }
      }
    }
  }
  return estimate;
}

template RangeEstimate estimate_range<double>(const Program<double>&, const Model<double>&);
template RangeEstimate estimate_range<float>(const Program<float>&, const Model<double>&);

}  // namespace dyngen::gen
