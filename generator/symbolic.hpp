// The symbolic scalar: running the runtime's templates on Sym<T> records the exact sequence
// of floating-point operations that runtime<T> performs, as an expression graph.
//
// While recording, the graph applies only rewrites that IEEE-754 arithmetic makes exact for
// finite values (docs/design.md): constant folding in T, x*1, x*(-1), x*0, x+0, x-0, 0-x, 0/x,
// x/1, -(-x), negations moved out of products and quotients and absorbed by sums, and reuse
// of identical nodes. Nothing is reassociated or fused.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "dyngen/sincos.hpp"
#include "dyngen/trace_hook.hpp"

namespace dyngen::gen {

enum class Op : std::uint8_t { Const, Input, Neg, Add, Sub, Mul, Div, Sin, Cos };

template <class T>
struct Node {
  Op op;
  int a = -1, b = -1;  // operands (node ids)
  T value{};           // Const: the value; Input: unused
  int input = -1;      // Input: index into Graph::inputs
  int body = -1;       // body whose step created the node (-1: none)
  Pass pass = Pass::Forward;
};

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

  bool is_const(int id) const { return nodes[id].op == Op::Const; }
  bool is_const(int id, T v) const { return is_const(id) && nodes[id].value == v; }

  void enter(int body, Pass pass) {
    body_ = body;
    pass_ = pass;
  }

  std::vector<Node<T>> nodes;
  std::vector<InputRef> inputs;

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

}  // namespace dyngen::gen

namespace dyngen {

template <class T>
struct TraceHook<gen::Sym<T>> {
  static void enter(int body, Pass pass) { gen::graph<T>().enter(body, pass); }
};

}  // namespace dyngen
