// The symbolic scalar: running the runtime's templates on Sym<T> records the exact sequence
// of floating-point operations that runtime<T> performs, as an expression graph.
//
// While recording, the graph applies only rewrites that IEEE-754 arithmetic makes exact for
// finite values (docs/design.md): constant folding in T, x*1, x*(-1), x*0, x+0, x-0, 0-x, x-x,
// 0/x, x/1, -(-x), negations moved out of products and quotients and absorbed by sums, and
// reuse of identical nodes. Nothing is reassociated or fused.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "dyngen/lie.hpp"
#include "dyngen/sincos.hpp"
#include "dyngen/trace_hook.hpp"

namespace dyngen::gen {

// Call: a kernel call, a = its index in Graph::calls; Result: an entry of its outputs, a = the
// Call node, input = the entry's index in the call's outputs laid end to end. Fn: a function of
// lie.h of a (and b), input = its Function.
enum class Op : std::uint8_t { Const, Input, Neg, Add, Sub, Mul, Div, Sin, Cos, Call, Result, Fn };
inline constexpr std::size_t op_kinds = 12;

/// The functions of lie.h (the exponential's and logarithm's coefficients) that Op::Fn calls.
enum class Function : std::uint8_t { HalfCos, HalfSinc, ExpC, ExpD, ExpE, LogAlpha, LogFactor };

/// A Function's name in lie.h (its float form adds "f") and its number of arguments.
struct FunctionInfo {
  const char* name;
  int arity;
};

inline constexpr FunctionInfo function_info[] = {
    {"dyngen_half_cos", 1}, {"dyngen_half_sinc", 1}, {"dyngen_exp_c", 1},     {"dyngen_exp_d", 1},
    {"dyngen_exp_e", 1},    {"dyngen_log_alpha", 1}, {"dyngen_log_factor", 2}};

inline const FunctionInfo& info(Function f) { return function_info[static_cast<int>(f)]; }

/// f at x (and y) in T, as the runtime and the generated code compute it.
template <class T>
T call_function(Function f, T x, T y) {
  switch (f) {
    case Function::HalfCos: return dyngen::half_cos(x);
    case Function::HalfSinc: return dyngen::half_sinc(x);
    case Function::ExpC: return dyngen::exp_c(x);
    case Function::ExpD: return dyngen::exp_d(x);
    case Function::ExpE: return dyngen::exp_e(x);
    case Function::LogAlpha: return dyngen::log_alpha(x);
    case Function::LogFactor: return dyngen::log_factor(x, y);
  }
  throw std::logic_error("unknown function");
}

template <class T>
struct Node {
  Op op;
  int a = -1, b = -1;  // operands (node ids)
  T value{};           // Const: the value; Input: unused
  int input = -1;      // Input: index into Graph::inputs; Result: see Op
  int body = -1;       // body whose step created the node (-1: none)
  Pass pass = Pass::Forward;
};

/// A recorded kernel call: what the emitter needs to print it.
struct KernelRecord {
  std::string kernel;
  std::vector<int> ints;
  std::vector<std::vector<int>> tables;
  std::vector<std::vector<int>> inputs;  // node ids of each array read
  std::vector<std::size_t> outputs;      // length of each array written
  std::vector<std::string> names;        // of the arrays read, then of those written
  std::array<long, op_kinds> ops{};      // operations its loops perform, by Op
  int first_result = -1;                 // node id of its first Result
  bool for_lanes = false;                // recorded only as vector lanes run it faster
};

/// Where the kernels run in vector lanes (Graph::vector_kernels), calls that inlining would
/// unroll into this many operations or more, but keep more than half of the loops' work (a
/// floating robot's M^-1 d tau), are faster as calls; below it the unrolled code is
/// (docs/performance.md, "The generator's limits").
inline constexpr long vector_kernels_from = 2000;

/// An input array element, e.g. q[3].
struct InputRef {
  std::string array;
  int index;
};

template <class T>
class Graph {
 public:
  /// simplify = false records every operation as the runtime performs it (for counting).
  explicit Graph(bool simplify = true) : simplify_(simplify) {}

  int constant(T value) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &value, sizeof(T));
    return intern({Op::Const, -1, -1, value}, Key{Op::Const, -1, -1, bits});
  }

  int input(const std::string& array, int index) {
    Node<T> n{Op::Input};
    n.input = static_cast<int>(inputs.size());
    inputs.push_back({array, index});
    return push(n);
  }

  int unary(Op op, int x);
  int binary(Op op, int x, int y);
  /// f(x) or f(x, y) (y >= 0), folded when its arguments are constants.
  int function(Function f, int x, int y = -1);

  bool is_const(int id) const { return nodes[id].op == Op::Const; }
  bool is_const(int id, T v) const { return is_const(id) && nodes[id].value == v; }

  void enter(int body, Pass pass) {
    body_ = body;
    pass_ = pass;
  }

  /// Kernel calls that would add at least this many operations inlined (their loops on the
  /// call's constants, folded) are recorded as calls; smaller ones, and every call of an
  /// unsimplified graph, run their loops on Sym (inlined).
  long call_kernels_from = 0;

  /// Whether the code will run the kernels' loops in vector lanes (C++ on the host): then a call
  /// is also recorded where inlining would add vector_kernels_from operations or more and keep
  /// more than half of the loops' operations, which two lanes do in fewer steps.
  bool vector_kernels = false;

  /// Records a kernel call (KernelHook), or returns false to have it inlined.
  template <class Run, class Call>
  bool record_call(const Call& call, const Run& run);

  /// The node ids an operation reads: a and b, or a Call's inputs.
  template <class F>
  void for_each_operand(int id, const F& f) const {
    const Node<T>& n = nodes[id];
    if (n.op == Op::Call) {
      for (const std::vector<int>& array : calls[n.a].inputs)
        for (const int x : array) f(x);
      return;
    }
    if (n.a >= 0) f(n.a);
    if (n.b >= 0) f(n.b);
  }

  std::vector<Node<T>> nodes;
  std::vector<InputRef> inputs;
  std::vector<KernelRecord> calls;

 private:
  struct Key {
    Op op;
    int a, b;
    std::uint64_t bits;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = static_cast<std::uint64_t>(k.op);
      h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.a));
      h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.b));
      h = h * 0x9E3779B97F4A7C15ull ^ k.bits;
      return static_cast<std::size_t>(h ^ (h >> 29));
    }
  };

  int push(Node<T> n) {
    n.body = body_;
    n.pass = pass_;
    nodes.push_back(n);
    return static_cast<int>(nodes.size()) - 1;
  }

  int intern(const Node<T>& n, const Key& key) {
    if (!simplify_ && n.op != Op::Const) return push(n);
    const auto it = cse_.find(key);
    if (it != cse_.end()) return it->second;
    const int id = push(n);
    cse_.emplace(key, id);
    return id;
  }

  static T eval(Op op, T x, T y) {
    switch (op) {
      case Op::Neg: return -x;
      case Op::Add: return x + y;
      case Op::Sub: return x - y;
      case Op::Mul: return x * y;
      case Op::Div: return x / y;
      case Op::Sin:
      case Op::Cos: {
        T sin_x, cos_x;
        sincos(x, sin_x, cos_x);  // the runtime's, as the generated code calls it
        return op == Op::Sin ? sin_x : cos_x;
      }
      default: throw std::logic_error("eval of a non-arithmetic node");
    }
  }

  bool simplify_;
  int body_ = -1;
  Pass pass_ = Pass::Forward;
  std::unordered_map<Key, int, KeyHash> cse_;
};

template <class T>
int Graph<T>::unary(Op op, int x) {
  if (simplify_) {
    if (is_const(x)) return constant(eval(op, nodes[x].value, T{}));
    if (op == Op::Neg && nodes[x].op == Op::Neg) return nodes[x].a;
  }
  return intern({op, x}, Key{op, x, -1, 0});
}

template <class T>
int Graph<T>::binary(Op op, int x, int y) {
  if (simplify_) {
    const bool cx = is_const(x), cy = is_const(y);
    if (cx && cy) return constant(eval(op, nodes[x].value, nodes[y].value));
    // Negations move outward and vanish into additions: rounding is symmetric, so
    // x - (-y) = x + y, x + (-y) = x - y, (-x) - y = -(x + y), (-x) y = -(x y), (-x) / y =
    // -(x / y) and c (-y) = (-c) y hold exactly (up to the sign of a zero result).
    const bool nx = nodes[x].op == Op::Neg, ny = nodes[y].op == Op::Neg;
    switch (op) {
      case Op::Add:
        if (cx && nodes[x].value == T(0)) return y;  // +-0 + y = y (up to the sign of zero)
        if (cy && nodes[y].value == T(0)) return x;
        if (ny) return binary(Op::Sub, x, nodes[y].a);
        if (nx) return binary(Op::Sub, y, nodes[x].a);
        break;
      case Op::Sub:
        if (x == y) return constant(T(0));  // finite x
        if (cy && nodes[y].value == T(0)) return x;
        if (cx && nodes[x].value == T(0)) return unary(Op::Neg, y);
        if (ny) return binary(Op::Add, x, nodes[y].a);
        if (nx) return unary(Op::Neg, binary(Op::Add, nodes[x].a, y));
        break;
      case Op::Mul:
        if (cx && nodes[x].value == T(0)) return constant(T(0));  // finite y
        if (cy && nodes[y].value == T(0)) return constant(T(0));
        if (cx && nodes[x].value == T(1)) return y;
        if (cy && nodes[y].value == T(1)) return x;
        if (cx && nodes[x].value == T(-1)) return unary(Op::Neg, y);
        if (cy && nodes[y].value == T(-1)) return unary(Op::Neg, x);
        if (cx && ny) return binary(Op::Mul, constant(-nodes[x].value), nodes[y].a);
        if (cy && nx) return binary(Op::Mul, nodes[x].a, constant(-nodes[y].value));
        if (nx && ny) return binary(Op::Mul, nodes[x].a, nodes[y].a);
        if (nx) return unary(Op::Neg, binary(Op::Mul, nodes[x].a, y));
        if (ny) return unary(Op::Neg, binary(Op::Mul, x, nodes[y].a));
        break;
      case Op::Div:
        if (cx && nodes[x].value == T(0)) return constant(T(0));  // finite, non-zero y
        if (cy && nodes[y].value == T(1)) return x;
        if (nx && ny) return binary(Op::Div, nodes[x].a, nodes[y].a);
        if (nx) return unary(Op::Neg, binary(Op::Div, nodes[x].a, y));
        if (ny) return unary(Op::Neg, binary(Op::Div, x, nodes[y].a));
        break;
      default: break;
    }
    // x + y = y + x and x * y = y * x exactly: one node for both orders
    if ((op == Op::Add || op == Op::Mul) && y < x) std::swap(x, y);
  }
  return intern({op, x, y}, Key{op, x, y, 0});
}

template <class T>
int Graph<T>::function(Function f, int x, int y) {
  if (simplify_ && is_const(x) && (y < 0 || is_const(y)))
    return constant(call_function(f, nodes[x].value, y < 0 ? T{} : nodes[y].value));
  Node<T> n{Op::Fn, x, y};
  n.input = static_cast<int>(f);
  return intern(n, Key{Op::Fn, x, y, static_cast<std::uint64_t>(f)});
}

template <class T>
inline thread_local Graph<T>* active_graph = nullptr;

/// Makes a graph the one Sym<T> arithmetic records into, for the scope's lifetime.
template <class T>
class Recording {
 public:
  explicit Recording(Graph<T>& g) : previous_(active_graph<T>) { active_graph<T> = &g; }
  ~Recording() { active_graph<T> = previous_; }
  Recording(const Recording&) = delete;
  Recording& operator=(const Recording&) = delete;

 private:
  Graph<T>* previous_;
};

template <class T>
Graph<T>& graph() {
  if (!active_graph<T>) throw std::logic_error("Sym arithmetic outside a Recording");
  return *active_graph<T>;
}

/// A scalar whose arithmetic appends nodes to the active graph.
template <class T>
struct Sym {
  int id;
  Sym() : id(graph<T>().constant(T(0))) {}
  explicit Sym(T value) : id(graph<T>().constant(value)) {}
  explicit Sym(int value) : Sym(T(value)) {}
  static Sym node(int id) { return Sym(id, Raw{}); }

 private:
  struct Raw {};
  Sym(int node_id, Raw) : id(node_id) {}
};

template <class T> Sym<T> operator+(Sym<T> x, Sym<T> y) { return Sym<T>::node(graph<T>().binary(Op::Add, x.id, y.id)); }
template <class T> Sym<T> operator-(Sym<T> x, Sym<T> y) { return Sym<T>::node(graph<T>().binary(Op::Sub, x.id, y.id)); }
template <class T> Sym<T> operator*(Sym<T> x, Sym<T> y) { return Sym<T>::node(graph<T>().binary(Op::Mul, x.id, y.id)); }
template <class T> Sym<T> operator/(Sym<T> x, Sym<T> y) { return Sym<T>::node(graph<T>().binary(Op::Div, x.id, y.id)); }
template <class T> Sym<T> operator-(Sym<T> x) { return Sym<T>::node(graph<T>().unary(Op::Neg, x.id)); }
template <class T> Sym<T> sin(Sym<T> x) { return Sym<T>::node(graph<T>().unary(Op::Sin, x.id)); }
template <class T> Sym<T> cos(Sym<T> x) { return Sym<T>::node(graph<T>().unary(Op::Cos, x.id)); }
template <class T>
Sym<T> half_cos(Sym<T> x) {
  return Sym<T>::node(graph<T>().function(Function::HalfCos, x.id));
}
template <class T>
Sym<T> half_sinc(Sym<T> x) {
  return Sym<T>::node(graph<T>().function(Function::HalfSinc, x.id));
}
template <class T>
Sym<T> exp_c(Sym<T> x) {
  return Sym<T>::node(graph<T>().function(Function::ExpC, x.id));
}
template <class T>
Sym<T> exp_d(Sym<T> x) {
  return Sym<T>::node(graph<T>().function(Function::ExpD, x.id));
}
template <class T>
Sym<T> exp_e(Sym<T> x) {
  return Sym<T>::node(graph<T>().function(Function::ExpE, x.id));
}
template <class T>
Sym<T> log_alpha(Sym<T> x) {
  return Sym<T>::node(graph<T>().function(Function::LogAlpha, x.id));
}
template <class T>
Sym<T> log_factor(Sym<T> s2, Sym<T> c) {
  return Sym<T>::node(graph<T>().function(Function::LogFactor, s2.id, c.id));
}

template <class T>
template <class Run, class Call>
bool Graph<T>::record_call(const Call& call, const Run& run) {
  if (!simplify_) return false;
  // runs the loops in a scratch graph, on inputs made by input(array entry, index)
  const auto run_in = [&](Graph<T>& scratch, const auto& input) {
    const Recording<T> recording(scratch);
    std::vector<std::vector<Sym<T>>> in, out;
    for (const auto& array : call.inputs) {
      std::vector<Sym<T>>& x = in.emplace_back();
      for (std::size_t k = 0; k < array.size(); ++k)
        x.push_back(Sym<T>::node(input(array[k], static_cast<int>(k))));
    }
    for (const auto& array : call.outputs) out.emplace_back(array.size());
    std::vector<std::span<const Sym<T>>> in_spans(in.begin(), in.end());
    std::vector<std::span<Sym<T>>> out_spans(out.begin(), out.end());
    run(std::span<const std::span<const Sym<T>>>(in_spans),
        std::span<const std::span<Sym<T>>>(out_spans));
    return out;
  };
  // count the loops' operations on fresh inputs in a scratch graph that keeps every operation
  KernelRecord record;
  {
    Graph<T> scratch(false);
    run_in(scratch, [&](const Sym<T>&, int k) { return scratch.input("x", k); });
    for (const Node<T>& n : scratch.nodes) ++record.ops[static_cast<std::size_t>(n.op)];
    record.ops[static_cast<std::size_t>(Op::Const)] = 0;
    record.ops[static_cast<std::size_t>(Op::Input)] = 0;
  }
  // what inlining would add: the loops on the call's constants, folded, with the rest fresh
  long inlined = 0;
  {
    Graph<T> scratch(true);
    const std::vector<std::vector<Sym<T>>> out = run_in(scratch, [&](const Sym<T>& x, int k) {
      return is_const(x.id) ? scratch.constant(nodes[x.id].value) : scratch.input("x", k);
    });
    std::vector<char> live(scratch.nodes.size(), 0);
    std::vector<int> stack;
    for (const auto& array : out)
      for (const Sym<T>& y : array) stack.push_back(y.id);
    while (!stack.empty()) {
      const int id = stack.back();
      stack.pop_back();
      if (id < 0 || live[id]) continue;
      live[id] = 1;
      const Node<T>& n = scratch.nodes[id];
      if (n.op != Op::Const && n.op != Op::Input) ++inlined;
      stack.push_back(n.a), stack.push_back(n.b);
    }
  }
  long loops = 0;
  for (const long n : record.ops) loops += n;
  const bool faster = vector_kernels && inlined >= vector_kernels_from && 2 * inlined > loops;
  if (inlined < call_kernels_from && !faster) return false;

  record.kernel = call.kernel;
  record.for_lanes = inlined < call_kernels_from;
  record.ints.assign(call.ints.begin(), call.ints.end());
  for (const auto& table : call.tables) record.tables.emplace_back(table.begin(), table.end());
  for (const auto& array : call.inputs) {
    std::vector<int>& ids = record.inputs.emplace_back();
    for (const Sym<T>& x : array) ids.push_back(x.id);
  }
  for (const auto& array : call.outputs) record.outputs.push_back(array.size());
  for (const auto& name : call.names) record.names.emplace_back(name);
  Node<T> node{Op::Call};
  node.a = static_cast<int>(calls.size());
  const int call_id = push(node);
  record.first_result = static_cast<int>(nodes.size());
  calls.push_back(std::move(record));
  int entry = 0;
  for (const auto& array : call.outputs)
    for (Sym<T>& y : array) {
      Node<T> result{Op::Result};
      result.a = call_id;
      result.input = entry++;
      y = Sym<T>::node(push(result));
    }
  return true;
}

}  // namespace dyngen::gen

namespace dyngen {

template <class T>
struct TraceHook<gen::Sym<T>> {
  static void enter(int body, Pass pass) { gen::graph<T>().enter(body, pass); }
};

template <class T>
struct KernelHook<gen::Sym<T>> {
  template <class Run>
  static bool record(const KernelCall<gen::Sym<T>>& call, const Run& run) {
    return gen::graph<T>().record_call(call, run);
  }
};

}  // namespace dyngen
