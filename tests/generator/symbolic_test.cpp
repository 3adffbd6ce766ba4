// The expression graph's rewrites are exact (docs/design.md, "Why tracing the runtime"): evaluating a
// simplified graph gives the bits of evaluating the same recording without rewrites, up to the
// sign of zero, for finite inputs. Also: CSE, commutative sharing, dead-node removal, and
// constant folding in the graph's own scalar type.
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <ostream>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "emit.hpp"
#include "files.hpp"
#include "robot.hpp"
#include "symbolic.hpp"
#include "trace.hpp"

namespace {

using namespace dyngen;
using namespace dyngen::gen;

template <class T>
using Bits = std::conditional_t<std::is_same_v<T, float>, std::uint32_t, std::uint64_t>;

/// Bitwise equality, except that +0 and -0 are equal (the one documented difference).
template <class T>
bool same_bits(T a, T b) {
  return (a == 0 && b == 0) || std::bit_cast<Bits<T>>(a) == std::bit_cast<Bits<T>>(b);
}

template <class T>
std::string show(T x) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g (%a)", static_cast<double>(x), static_cast<double>(x));
  return text;
}

template <class T>
T sin_of(T x) {
  T s, c;
  dyngen::sincos(x, s, c);
  return s;
}

template <class T>
T cos_of(T x) {
  T s, c;
  dyngen::sincos(x, s, c);
  return c;
}

/// Runs a recorded kernel call on values, as the emitted code does (dyngen_kernels.hpp): its
/// outputs laid end to end.
template <class T>
std::vector<T> run_call(const KernelRecord& call, const std::vector<std::vector<T>>& in) {
  std::vector<std::vector<T>> out;
  for (const std::size_t size : call.outputs) out.emplace_back(size);
  const auto& t = call.tables;
  if (call.kernel == "derivative_pairs")
    kernels::derivative_pairs(call.ints.at(0), call.ints.at(1), t.at(0).data(), t.at(1).data(),
                              t.at(2).data(), in.at(0).data(), in.at(1).data(), in.at(2).data(),
                              out.at(0).data(), out.at(1).data());
  else if (call.kernel == "neg_product")
    kernels::neg_product(call.ints.at(0), t.at(0).data(), t.at(1).data(), in.at(0).data(),
                         in.at(1).data(), out.at(0).data());
  else
    ADD_FAILURE() << "no kernel " << call.kernel;
  std::vector<T> flat;
  for (const std::vector<T>& array : out) flat.insert(flat.end(), array.begin(), array.end());
  return flat;
}

/// Runs a graph on input values, one operation per node, in T: what the emitted code does.
template <class T>
std::vector<T> evaluate(const Graph<T>& g, const std::vector<T>& inputs) {
  std::vector<T> v(g.nodes.size());
  std::vector<std::vector<T>> results(g.calls.size());
  for (std::size_t id = 0; id < g.nodes.size(); ++id) {
    const Node<T>& n = g.nodes[id];
    switch (n.op) {
      case Op::Call: {
        std::vector<std::vector<T>> in;
        for (const std::vector<int>& array : g.calls[n.a].inputs) {
          std::vector<T>& x = in.emplace_back();
          for (const int operand : array) x.push_back(v[operand]);
        }
        results[n.a] = run_call(g.calls[n.a], in);
        break;
      }
      case Op::Result: v[id] = results[g.nodes[n.a].a].at(n.input); break;
      case Op::Const: v[id] = n.value; break;
      case Op::Input: v[id] = inputs.at(n.input); break;
      case Op::Neg: v[id] = -v[n.a]; break;
      case Op::Add: v[id] = v[n.a] + v[n.b]; break;
      case Op::Sub: v[id] = v[n.a] - v[n.b]; break;
      case Op::Mul: v[id] = v[n.a] * v[n.b]; break;
      case Op::Div: v[id] = v[n.a] / v[n.b]; break;
      case Op::Sin: v[id] = sin_of(v[n.a]); break;
      case Op::Cos: v[id] = cos_of(v[n.a]); break;
      case Op::Fn:
        v[id] = call_function(static_cast<Function>(n.input), v[n.a], n.b >= 0 ? v[n.b] : T{});
        break;
    }
  }
  return v;
}

/// Any finite value from raw generator bits (so the test does not depend on the standard
/// library's distributions), with the edge values the rewrites care about mixed in.
template <class T>
T random_value(std::mt19937_64& rng) {
  using L = std::numeric_limits<T>;
  static const T special[] = {T(0),         -T(0),    T(1),      T(-1),           T(2),
                              T(-0.5),      L::max(), L::min(),  L::denorm_min(), L::lowest(),
                              L::epsilon(), -L::min(), -L::denorm_min(), T(1) + L::epsilon()};
  if (rng() % 4 == 0) return special[rng() % std::size(special)];
  if (rng() % 8 == 0) {  // subnormal: exponent bits zero, random mantissa and sign
    const Bits<T> mantissa = static_cast<Bits<T>>(rng()) & ((Bits<T>(1) << (L::digits - 1)) - 1);
    const Bits<T> sign = static_cast<Bits<T>>(rng() & 1) << (sizeof(T) * 8 - 1);
    return std::bit_cast<T>(static_cast<Bits<T>>(sign | mantissa));
  }
  while (true) {
    const T x = std::bit_cast<T>(static_cast<Bits<T>>(rng()));
    if (std::isfinite(x)) return x;
  }
}

template <class T>
struct Expr {
  const char* name;
  std::function<int(Graph<T>&, int x, int y, T c, T d)> build;
  bool nonzero_x = false;  // 0/x -> 0 holds for non-zero x only
};

template <class T>
std::vector<Expr<T>> expressions() {
  using G = Graph<T>;
  auto k = [](G& g, T v) { return g.constant(v); };
  auto add = [](G& g, int a, int b) { return g.binary(Op::Add, a, b); };
  auto sub = [](G& g, int a, int b) { return g.binary(Op::Sub, a, b); };
  auto mul = [](G& g, int a, int b) { return g.binary(Op::Mul, a, b); };
  auto div = [](G& g, int a, int b) { return g.binary(Op::Div, a, b); };
  auto neg = [](G& g, int a) { return g.unary(Op::Neg, a); };
  return {
      {"x*1", [=](G& g, int x, int, T, T) { return mul(g, x, k(g, 1)); }},
      {"1*x", [=](G& g, int x, int, T, T) { return mul(g, k(g, 1), x); }},
      {"x*-1", [=](G& g, int x, int, T, T) { return mul(g, x, k(g, -1)); }},
      {"-1*x", [=](G& g, int x, int, T, T) { return mul(g, k(g, -1), x); }},
      {"x*0", [=](G& g, int x, int, T, T) { return mul(g, x, k(g, 0)); }},
      {"0*x", [=](G& g, int x, int, T, T) { return mul(g, k(g, 0), x); }},
      {"x*-0", [=](G& g, int x, int, T, T) { return mul(g, x, k(g, -T(0))); }},
      {"-0*x", [=](G& g, int x, int, T, T) { return mul(g, k(g, -T(0)), x); }},
      {"x+0", [=](G& g, int x, int, T, T) { return add(g, x, k(g, 0)); }},
      {"0+x", [=](G& g, int x, int, T, T) { return add(g, k(g, 0), x); }},
      {"x+-0", [=](G& g, int x, int, T, T) { return add(g, x, k(g, -T(0))); }},
      {"-0+x", [=](G& g, int x, int, T, T) { return add(g, k(g, -T(0)), x); }},
      {"x-0", [=](G& g, int x, int, T, T) { return sub(g, x, k(g, 0)); }},
      {"x--0", [=](G& g, int x, int, T, T) { return sub(g, x, k(g, -T(0))); }},
      {"0-x", [=](G& g, int x, int, T, T) { return sub(g, k(g, 0), x); }},
      {"-0-x", [=](G& g, int x, int, T, T) { return sub(g, k(g, -T(0)), x); }},
      {"0/x", [=](G& g, int x, int, T, T) { return div(g, k(g, 0), x); }, true},
      {"-0/x", [=](G& g, int x, int, T, T) { return div(g, k(g, -T(0)), x); }, true},
      {"x-x", [=](G& g, int x, int, T, T) { return sub(g, x, x); }},
      {"x/1", [=](G& g, int x, int, T, T) { return div(g, x, k(g, 1)); }},
      {"x/0", [=](G& g, int x, int, T, T) { return div(g, x, k(g, 0)); }},
      {"x/-1", [=](G& g, int x, int, T, T) { return div(g, x, k(g, -1)); }},
      {"-(-x)", [=](G& g, int x, int, T, T) { return neg(g, neg(g, x)); }},
      {"c+d", [=](G& g, int, int, T c, T d) { return add(g, k(g, c), k(g, d)); }},
      {"c-d", [=](G& g, int, int, T c, T d) { return sub(g, k(g, c), k(g, d)); }},
      {"c*d", [=](G& g, int, int, T c, T d) { return mul(g, k(g, c), k(g, d)); }},
      {"c/d", [=](G& g, int, int, T c, T d) { return div(g, k(g, c), k(g, d)); }},
      {"-c", [=](G& g, int, int, T c, T) { return neg(g, k(g, c)); }},
      {"sin c", [=](G& g, int, int, T c, T) { return g.unary(Op::Sin, k(g, c)); }},
      {"cos c", [=](G& g, int, int, T c, T) { return g.unary(Op::Cos, k(g, c)); }},
      {"((c+d)*c-d)/c", [=](G& g, int, int, T c, T d) {
         return div(g, sub(g, mul(g, add(g, k(g, c), k(g, d)), k(g, c)), k(g, d)), k(g, c));
       }},
      {"x*(c-c)", [=](G& g, int x, int, T c, T) { return mul(g, x, sub(g, k(g, c), k(g, c))); }},
      {"x*(c/c)+y", [=](G& g, int x, int y, T c, T) {
         return add(g, mul(g, x, div(g, k(g, c), k(g, c))), y);
       }},
      {"(x+c)+d", [=](G& g, int x, int, T c, T d) { return add(g, add(g, x, k(g, c)), k(g, d)); }},
      {"(x*1+0)*(y-0)-(0-x)", [=](G& g, int x, int y, T, T) {
         const int left = mul(g, add(g, mul(g, x, k(g, 1)), k(g, 0)), sub(g, y, k(g, 0)));
         return sub(g, left, sub(g, k(g, 0), x));
       }},
      {"-(-(x*y))+(c*d)*x", [=](G& g, int x, int y, T c, T d) {
         return add(g, neg(g, neg(g, mul(g, x, y))), mul(g, mul(g, k(g, c), k(g, d)), x));
       }},
      {"x*y+y*x-x*y", [=](G& g, int x, int y, T, T) {
         return sub(g, add(g, mul(g, x, y), mul(g, y, x)), mul(g, x, y));
       }},
      {"sin x*cos x+sin x", [=](G& g, int x, int, T, T) {
         const int s = g.unary(Op::Sin, x), c = g.unary(Op::Cos, x);
         return add(g, mul(g, s, c), g.unary(Op::Sin, x));
       }},
      {"(-1*x)*(y/1)-(0/x)", [=](G& g, int x, int y, T, T) {
         return sub(g, mul(g, mul(g, k(g, -1), x), div(g, y, k(g, 1))), div(g, k(g, 0), x));
       }, true},
  };
}

template <class T>
class Rewrites : public ::testing::Test {};
using Scalars = ::testing::Types<double, float>;
TYPED_TEST_SUITE(Rewrites, Scalars);

TYPED_TEST(Rewrites, SimplifiedGraphComputesTheBitsOfTheUnsimplifiedOne) {
  using T = TypeParam;
  std::mt19937_64 rng(1234567);
  for (const Expr<T>& e : expressions<T>()) {
    int failures = 0;
    for (int sample = 0; sample < 4000 && failures < 3; ++sample) {
      const T x = random_value<T>(rng), y = random_value<T>(rng);
      const T c = random_value<T>(rng), d = random_value<T>(rng);
      if (e.nonzero_x && x == 0) continue;
      T result[2];
      for (const bool simplify : {false, true}) {
        Graph<T> g(simplify);
        const int ix = g.input("x", 0), iy = g.input("x", 1);
        const int out = e.build(g, ix, iy, c, d);
        result[simplify] = evaluate(g, {x, y})[out];
      }
      if (!same_bits(result[0], result[1])) {
        ++failures;
        ADD_FAILURE() << e.name << " with x = " << show(x) << ", y = " << show(y)
                      << ", c = " << show(c) << ", d = " << show(d) << ": unsimplified "
                      << show(result[0]) << ", simplified " << show(result[1]);
      }
    }
  }
}

TYPED_TEST(Rewrites, EachRewriteApplies) {
  using T = TypeParam;
  Graph<T> g;
  const int x = g.input("q", 0);
  const int zero = g.constant(0), one = g.constant(1), minus_one = g.constant(-1);
  EXPECT_EQ(g.binary(Op::Mul, x, one), x);
  EXPECT_EQ(g.binary(Op::Mul, one, x), x);
  EXPECT_EQ(g.binary(Op::Add, x, zero), x);
  EXPECT_EQ(g.binary(Op::Add, zero, x), x);
  EXPECT_EQ(g.binary(Op::Sub, x, zero), x);
  EXPECT_EQ(g.binary(Op::Div, x, one), x);
  EXPECT_TRUE(g.is_const(g.binary(Op::Mul, x, zero), 0));
  EXPECT_TRUE(g.is_const(g.binary(Op::Mul, zero, x), 0));
  EXPECT_TRUE(g.is_const(g.binary(Op::Div, zero, x), 0));
  const int x_minus_x = g.binary(Op::Sub, x, x);  // +0 for every finite x, -0 included
  EXPECT_TRUE(g.is_const(x_minus_x, 0));
  EXPECT_FALSE(std::signbit(g.nodes[x_minus_x].value));
  const int neg_x = g.unary(Op::Neg, x);
  EXPECT_EQ(g.nodes[neg_x].op, Op::Neg);
  EXPECT_EQ(g.binary(Op::Mul, x, minus_one), neg_x);
  EXPECT_EQ(g.binary(Op::Mul, minus_one, x), neg_x);
  EXPECT_EQ(g.binary(Op::Sub, zero, x), neg_x);
  EXPECT_EQ(g.unary(Op::Neg, neg_x), x);
  const int six = g.binary(Op::Mul, g.constant(2), g.constant(3));
  EXPECT_TRUE(g.is_const(six, 6));
  EXPECT_TRUE(g.is_const(g.unary(Op::Cos, zero), 1));
}

TYPED_TEST(Rewrites, NothingIsReassociatedOrFused) {
  using T = TypeParam;
  Graph<T> g;
  const int x = g.input("q", 0), y = g.input("q", 1);
  const int c = g.constant(T(0.1)), d = g.constant(T(0.2));
  const int inner = g.binary(Op::Add, x, c);
  const int outer = g.binary(Op::Add, inner, d);  // (x + c) + d, not x + (c + d)
  EXPECT_EQ(g.nodes[outer].op, Op::Add);
  EXPECT_TRUE(g.nodes[outer].a == inner || g.nodes[outer].b == inner);
  const int product = g.binary(Op::Mul, x, y);
  const int sum = g.binary(Op::Add, product, c);  // a*b + c stays a multiply and an add
  EXPECT_EQ(g.nodes[sum].op, Op::Add);
  EXPECT_EQ(g.nodes[product].op, Op::Mul);
  // x / x is not 1 for every finite x (0 / 0)
  EXPECT_EQ(g.nodes[g.binary(Op::Div, x, x)].op, Op::Div);
}

TYPED_TEST(Rewrites, CseReusesNodesAndSharesCommutativeOperands) {
  using T = TypeParam;
  Graph<T> g;
  const int x = g.input("q", 0), y = g.input("q", 1);
  const int xy = g.binary(Op::Mul, x, y);
  const std::size_t size = g.nodes.size();
  EXPECT_EQ(g.binary(Op::Mul, x, y), xy);
  EXPECT_EQ(g.binary(Op::Mul, y, x), xy);
  EXPECT_EQ(g.binary(Op::Add, x, y), g.binary(Op::Add, y, x));
  EXPECT_EQ(g.unary(Op::Sin, x), g.unary(Op::Sin, x));
  EXPECT_EQ(g.constant(T(0.25)), g.constant(T(0.25)));
  EXPECT_EQ(g.nodes.size(), size + 3) << "one add, one sin, one constant";
  // not commutative, so not shared
  EXPECT_NE(g.binary(Op::Sub, x, y), g.binary(Op::Sub, y, x));
  EXPECT_NE(g.binary(Op::Div, x, y), g.binary(Op::Div, y, x));
  // constants are told apart by their bits: -0 is its own constant
  EXPECT_NE(g.constant(T(0)), g.constant(-T(0)));
  EXPECT_TRUE(std::signbit(g.nodes[g.constant(-T(0))].value));
}

TYPED_TEST(Rewrites, UnsimplifiedGraphRecordsEveryOperation) {
  using T = TypeParam;
  Graph<T> g(false);
  const int x = g.input("q", 0), one = g.constant(1);
  const int a = g.binary(Op::Mul, x, one), b = g.binary(Op::Mul, x, one);
  EXPECT_NE(a, b);
  EXPECT_NE(a, x);
  EXPECT_EQ(g.nodes[g.binary(Op::Add, one, one)].op, Op::Add);
}

// ---- folding in the target type

TEST(ConstantFolding, FloatGraphRoundsEveryStepToFloat) {
  // 1 + 2^-24 is a tie that rounds to 1 in float; in double the two halves would add up to
  // 1 + 2^-23, which float represents exactly
  Graph<float> g;
  const int half_ulp = g.constant(0x1p-24f);
  const int sum = g.binary(Op::Add, g.binary(Op::Add, g.constant(1.0f), half_ulp), half_ulp);
  ASSERT_TRUE(g.is_const(sum));
  EXPECT_EQ(g.nodes[sum].value, 1.0f);
  EXPECT_NE(static_cast<float>(1.0 + 0x1p-24 + 0x1p-24), 1.0f) << "the test would be vacuous";
  // float overflow is folded as float: 2^100 * 2^100 is inf in float, not 2^200
  const int big = g.constant(0x1p100f);
  EXPECT_TRUE(std::isinf(g.nodes[g.binary(Op::Mul, big, big)].value));
}

TEST(ConstantFolding, DoubleGraphRoundsEveryStepToDouble) {
  Graph<double> g;
  const int half_ulp = g.constant(0x1p-53);
  const int sum = g.binary(Op::Add, g.binary(Op::Add, g.constant(1.0), half_ulp), half_ulp);
  ASSERT_TRUE(g.is_const(sum));
  EXPECT_EQ(g.nodes[sum].value, 1.0);
  // 1 + (2^-53 + 2^-105) lies just above a tie: double rounds it up, while rounding through
  // x87's 64-bit long double first lands on the tie and then rounds to even, down to 1
  const int above_tie = g.binary(Op::Add, g.constant(1.0), g.constant(0x1.0000000000001p-53));
  EXPECT_EQ(g.nodes[above_tie].value, 1 + 0x1p-52);
}

// the generated code calls dyngen::sincos, in float for float code
TEST(ConstantFolding, FloatSinAndCosAreTheFloatFunctions) {
  Graph<float> g;
  std::mt19937_64 rng(99);
  for (int k = 0; k < 1000; ++k) {
    const float x = random_value<float>(rng);
    const int c = g.constant(x);
    EXPECT_TRUE(same_bits(g.nodes[g.unary(Op::Sin, c)].value, sin_of(x))) << show(x);
    EXPECT_TRUE(same_bits(g.nodes[g.unary(Op::Cos, c)].value, cos_of(x))) << show(x);
  }
}

// ---- the symbolic scalar

TEST(Sym, ArithmeticRecordsIntoTheActiveGraphOnly) {
  Graph<double> g;
  {
    const Recording<double> recording(g);
    const Sym<double> x = Sym<double>::node(g.input("q", 0));
    const Sym<double> y = x * Sym<double>(1.0) + Sym<double>(0.0);
    EXPECT_EQ(y.id, x.id);
    EXPECT_EQ((-(-x)).id, x.id);
    EXPECT_EQ(g.nodes[sin(x).id].op, Op::Sin);
  }
  EXPECT_THROW(Sym<double>(1.0), std::logic_error);
}

// ---- dead nodes

TEST(DeadNodes, AreNeitherEmittedNorCounted) {
  Program<double> program;
  program.algorithm = "rnea";
  Graph<double>& g = program.graph;
  const int q0 = g.input("q", 0), q1 = g.input("q", 1);
  g.binary(Op::Mul, g.unary(Op::Sin, q0), q1);  // reaches no output
  program.stored = {g.binary(Op::Add, q0, q1)};
  program.outputs = {{tau_array, 1}};
  const std::string body = emit_code(program, Model<double>{}, Structure::Unrolled).body;
  EXPECT_EQ(body.find("sin"), std::string::npos) << body;
  EXPECT_EQ(body.find(" * "), std::string::npos) << body;
  EXPECT_NE(body.find("q[0] + q[1]"), std::string::npos) << body;
  const OpCounts live = count_ops(program), all = count_ops(program, false);
  EXPECT_EQ(live.total(), 1);
  EXPECT_EQ(live.add, 1);
  EXPECT_EQ(all.total(), 3);
  EXPECT_EQ(all.sin, 1);
}

// ---- whole traces of real robots

template <class T>
T uniform(std::mt19937_64& rng, double lo, double hi) {
  return static_cast<T>(lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1p-53);
}

struct TraceCase {
  std::string robot;
  Algorithm algorithm;
  bool single;  // float instead of double

  std::string name() const {
    const std::string file = robot.substr(robot.find_last_of('/') + 1);
    return file.substr(0, file.find('.')) + "_" + algorithm + (single ? "_float" : "_double");
  }
};

void PrintTo(const TraceCase& c, std::ostream* os) { *os << c.name(); }

class Traced : public ::testing::TestWithParam<TraceCase> {};

template <class T>
void expect_traces_agree(const Model<double>& model, Algorithm algorithm,
                         long call_kernels_from = default_call_kernels_from) {
  const Program<T> simplified = trace<T>(algorithm, model, true, call_kernels_from);
  const Program<T> full = trace<T>(algorithm, model, false);
  ASSERT_EQ(simplified.graph.inputs.size(), full.graph.inputs.size());
  for (std::size_t k = 0; k < full.graph.inputs.size(); ++k) {
    ASSERT_EQ(simplified.graph.inputs[k].array, full.graph.inputs[k].array);
    ASSERT_EQ(simplified.graph.inputs[k].index, full.graph.inputs[k].index);
  }
  // simplifying removes operations, but from a program of one per output (integrate on an arm)
  const long full_ops = count_ops(full, false).total();
  if (full_ops > static_cast<long>(full.stored.size())) {
    EXPECT_LT(count_ops(simplified).total(), full_ops);
  }
  std::mt19937_64 rng(42);
  std::vector<T> inputs(full.graph.inputs.size());
  for (int sample = 0; sample < 50; ++sample) {
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      const bool angle = full.graph.inputs[k].array == "q";
      inputs[k] = sample == 0 ? T(0) : uniform<T>(rng, angle ? -4 : -20, angle ? 4 : 20);
    }
    const std::vector<T> a = evaluate(full.graph, inputs), b = evaluate(simplified.graph, inputs);
    ASSERT_EQ(full.stored.size(), simplified.stored.size());
    for (std::size_t k = 0; k < full.stored.size(); ++k) {
      const T x = a[full.stored[k]], y = b[simplified.stored[k]];
      // the rewrites are exact for finite values: where a value is not (sample 0's all-zero
      // quaternions have no logarithm), both give NaN, but not always of the same sign
      ASSERT_TRUE(same_bits(x, y) || (std::isnan(x) && std::isnan(y)))
          << "output entry " << k << " at sample " << sample
                                   << ": runtime " << show(x) << ", simplified " << show(y);
    }
  }
}


TEST_P(Traced, SimplifiedTraceComputesTheRuntimeBits) {
  const TraceCase& c = GetParam();
  const Robot r = load_robot(std::string(DYNGEN_TEST_MODELS) + "/" + c.robot, dyngen::test::independent_mimics());
  if (c.single) expect_traces_agree<float>(r.model, c.algorithm);
  else expect_traces_agree<double>(r.model, c.algorithm);
}

/// A simplified trace holds no node that a rewrite would have removed.
template <class T>
void expect_fully_simplified(const Graph<T>& g) {
  std::set<std::tuple<Op, int, int, Bits<T>>> seen;
  for (std::size_t id = 0; id < g.nodes.size(); ++id) {
    const Node<T>& n = g.nodes[id];
    if (n.op == Op::Input || n.op == Op::Call || n.op == Op::Result) continue;
    const auto key = std::tuple{n.op, n.a, n.b,
                                n.op == Op::Const ? std::bit_cast<Bits<T>>(n.value)
                                : n.op == Op::Fn  ? static_cast<Bits<T>>(n.input)
                                                  : Bits<T>(0)};
    EXPECT_TRUE(seen.insert(key).second) << "node " << id << " duplicates an earlier one";
    if (n.op == Op::Const) continue;
    const bool ca = g.is_const(n.a), cb = n.b >= 0 && g.is_const(n.b);
    EXPECT_FALSE(ca && (n.b < 0 || cb)) << "node " << id << " has only constant operands";
    auto is = [&](int operand, T v) { return operand >= 0 && g.is_const(operand, v); };
    switch (n.op) {
      case Op::Add:
      case Op::Mul:
        EXPECT_LE(n.a, n.b) << "node " << id << ": commutative operands not in order";
        break;
      case Op::Neg: EXPECT_NE(g.nodes[n.a].op, Op::Neg) << "node " << id; break;
      default: break;
    }
    const bool zero = is(n.a, 0) || is(n.b, 0);
    const bool one = is(n.a, 1) || is(n.b, 1) || is(n.a, -1) || is(n.b, -1);
    if (n.op == Op::Add || n.op == Op::Sub) {
      EXPECT_FALSE(zero) << "node " << id << " adds zero";
    } else if (n.op == Op::Mul) {
      EXPECT_FALSE(zero || one) << "node " << id << " multiplies by 0 or +-1";
    } else if (n.op == Op::Div) {
      EXPECT_FALSE(is(n.a, 0) || is(n.b, 1)) << "node " << id << " divides 0 or by 1";
    }
  }
}

TEST_P(Traced, SimplifiedTraceHasNothingLeftToRewrite) {
  const TraceCase& c = GetParam();
  const Robot r = load_robot(std::string(DYNGEN_TEST_MODELS) + "/" + c.robot, dyngen::test::independent_mimics());
  if (c.single) expect_fully_simplified(trace<float>(c.algorithm, r.model).graph);
  else expect_fully_simplified(trace<double>(c.algorithm, r.model).graph);
}

std::vector<TraceCase> trace_cases() {
  std::vector<TraceCase> cases;
  for (const char* robot : {"planar5.yaml", "ur5.urdf", "panda.urdf"})
    for (const Algorithm& a : algorithm_names())
      for (const bool single : {false, true}) cases.push_back({robot, a, single});
  // the configuration space's functions of lie.h (Op::Fn) on a free joint and ball joints
  for (const char* a :
       {"integrate", "difference", "integrate_derivatives", "difference_derivatives"})
    for (const bool single : {false, true}) cases.push_back({"mjcf/ball.xml", a, single});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Robots, Traced, ::testing::ValuesIn(trace_cases()),
                         [](const auto& info) { return info.param.name(); });

// ---- kernel calls

/// The kernels that an algorithm's trace records as calls, in order.
template <class T>
std::vector<std::string> kernel_calls(const Program<T>& program) {
  std::vector<std::string> names;
  for (const KernelRecord& call : program.graph.calls) names.push_back(call.kernel);
  return names;
}

// Recorded as calls (the code of big robots), the kernels compute the runtime's bits: the
// recording keeps their arrays, results and order straight.
TEST(KernelCalls, RecordedCallsComputeTheRuntimeBits) {
  // pr2's pairs are in base coordinates, the form a kernel call takes (rnea_derivatives.hpp)
  for (const char* robot : {"ur5.urdf", "panda.urdf", "pr2.urdf"}) {
    SCOPED_TRACE(robot);
    const Model<double> model =
        load_robot(std::string(DYNGEN_TEST_MODELS) + "/" + robot, dyngen::test::independent_mimics()).model;
    for (const Algorithm a : {"rnea_derivatives", "aba_derivatives"}) {
      SCOPED_TRACE(a);
      expect_traces_agree<double>(model, a, 0);
      expect_traces_agree<float>(model, a, 0);
    }
  }
}

TEST(KernelCalls, SmallCallsAreInlinedAndBigOnesRecorded) {
  const Model<double> model =
      load_robot(std::string(DYNGEN_TEST_MODELS) + "/ur5.urdf").model;
  // ur5's pairs of joints are carried, which always unrolls them (rnea_derivatives.hpp)
  const std::vector<std::string> both{"neg_product", "neg_product"};
  EXPECT_EQ(kernel_calls(trace<double>("aba_derivatives", model, true, 0)), both);
  EXPECT_TRUE(kernel_calls(trace<double>("aba_derivatives", model)).empty());
  // the unsimplified trace, which counts the runtime's operations, runs every loop
  EXPECT_TRUE(kernel_calls(trace<double>("aba_derivatives", model, false, 0)).empty());
  // a call counts the operations of its loops: the inlined trace folds some of them away
  const OpCounts called = count_ops(trace<double>("aba_derivatives", model, true, 0));
  const OpCounts inlined = count_ops(trace<double>("aba_derivatives", model));
  EXPECT_GT(called.total(), inlined.total());
  const std::string code =
      emit_code(trace<double>("aba_derivatives", model, true, 0), model, Structure::Shared).body;
  EXPECT_NE(code.find("dyngen_kernels::neg_product("), std::string::npos);
  // the outputs that a kernel writes whole are passed to it, not copied
  EXPECT_NE(code.find("dqdd_dq: written by the kernel"), std::string::npos) << code;
  EXPECT_EQ(code.find("dqdd_dq[0] ="), std::string::npos);
}

// Where the kernels run in vector lanes, a floating quadruped's M^-1 d tau is a call: inlined it
// would keep most of the loops' work (symbolic.hpp, vector_kernels_from); an arm's stays inlined
TEST(KernelCalls, VectorLanesTakeTheCallsThatInliningWouldKeepMostOf) {
  LoadOptions floating;
  floating.floating_base = true;
  const Model<double> solo =
      load_robot(std::string(DYNGEN_TEST_MODELS) + "/solo12.urdf", floating).model;
  const Program<double> called = trace<double>("aba_derivatives", solo);
  const std::vector<std::string> both{"neg_product", "neg_product"};
  ASSERT_EQ(kernel_calls(called), both);
  for (const KernelRecord& call : called.graph.calls) EXPECT_TRUE(call.for_lanes);
  const Program<double> inlined =
      trace<double>("aba_derivatives", solo, true, default_call_kernels_from, false);
  EXPECT_TRUE(kernel_calls(inlined).empty());
  // a call counts its loops' operations, which the inlined trace folds in part
  EXPECT_GT(count_ops(called).total(), count_ops(inlined).total());
  const Model<double> ur5 = load_robot(std::string(DYNGEN_TEST_MODELS) + "/ur5.urdf").model;
  EXPECT_TRUE(kernel_calls(trace<double>("aba_derivatives", ur5)).empty());
}

TEST(KernelCalls, CarriedDerivativePairsStayUnderTheLaneLimitOnEveryTestRobot) {
  // carried pairs are unrolled (rnea_derivatives.hpp, max_carried_path_joints): the limit on
  // path joints must keep the code of the robots it admits within what auto puts in lanes,
  // and send atlas floating, whose compile time issue 13 bounds, to base coordinates and a
  // kernel call
  int carried = 0;
  for (const char* name : {"double_pendulum", "ur5", "iiwa14", "panda", "solo12", "anymal_c",
                           "baxter", "pr2", "romeo", "atlas"})
    for (const bool floating : {false, true}) {
      LoadOptions options;
      options.floating_base = floating;
      options.mimic_independent = true;  // panda's fingers
      const Model<double> model =
          load_robot(std::string(DYNGEN_TEST_MODELS) + "/" + name + ".urdf", options).model;
      if (!carries_derivative_pairs(model)) continue;
      const Program<double> program = trace<double>("rnea_derivatives", model);
      EXPECT_TRUE(program.graph.calls.empty()) << name << (floating ? " floating" : "");
      EXPECT_LT(count_ops(program).total(), max_lane_function_operations) << name;
      ++carried;
    }
  EXPECT_EQ(carried, 15);  // all but pr2, romeo and atlas floating (over 128 path joints)
  LoadOptions options;
  options.floating_base = true;
  const Model<double> atlas =
      load_robot(std::string(DYNGEN_TEST_MODELS) + "/atlas.urdf", options).model;
  EXPECT_FALSE(carries_derivative_pairs(atlas));
  EXPECT_EQ(trace<double>("rnea_derivatives", atlas).graph.calls.size(), 1u);
}

TEST(KernelCalls, OperationsByPassAddUpAndACallCountsInItsPass) {
  // pr2 is past max_carried_path_joints, in base coordinates: its pairs are inlined without
  // vector lanes' calls (a call with them), a call from 0 operations
  const Model<double> model =
      load_robot(std::string(DYNGEN_TEST_MODELS) + "/pr2.urdf", dyngen::test::independent_mimics())
          .model;
  const Program<double> inlined =
      trace<double>("rnea_derivatives", model, true, default_call_kernels_from, false);
  ASSERT_TRUE(inlined.graph.calls.empty());
  const Program<double> called = trace<double>("rnea_derivatives", model, true, 0);
  for (const Program<double>* program : {&inlined, &called}) {
    const std::map<Pass, OpCounts> by_pass = count_ops_by_pass(*program);
    std::vector<Pass> passes;
    long total = 0;
    for (const auto& [pass, c] : by_pass) passes.push_back(pass), total += c.total();
    EXPECT_EQ(passes, (std::vector<Pass>{Pass::Forward, Pass::Backward, Pass::Pairs}));
    EXPECT_EQ(total, count_ops(*program).total());
  }
  // the kernel's loops count in the pairs' pass; the call reads every entry of its inputs, so
  // the passes before it keep work that the inlined trace folds away
  ASSERT_EQ(called.graph.calls.size(), 1u);
  long kernel = 0;
  for (const long n : called.graph.calls[0].ops) kernel += n;
  const auto a = count_ops_by_pass(inlined), b = count_ops_by_pass(called);
  EXPECT_EQ(b.at(Pass::Pairs).total(), kernel);
  EXPECT_GE(b.at(Pass::Forward).total(), a.at(Pass::Forward).total());
  EXPECT_GE(b.at(Pass::Backward).total(), a.at(Pass::Backward).total());
}

}  // namespace
