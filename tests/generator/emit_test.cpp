// Emission: constants print as C++ literals that read back to the same bits (docs/design.md, "The
// bit-for-bit contract"), and emitted code carries per-link provenance and none of the artifacts
// STYLE.md rules out (no "* 1", no "+ 0", no trailing whitespace, no tabs).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "dyngen/frames.hpp"
#include "backend.hpp"
#include "emit.hpp"
#include "generate.hpp"
#include "pattern.hpp"
#include "robot.hpp"
#include "trace.hpp"

namespace {

using namespace dyngen;
using namespace dyngen::gen;
using dyngen::test::Groups;
using dyngen::test::Pattern;

template <class T>
using Bits = std::conditional_t<std::is_same_v<T, float>, std::uint32_t, std::uint64_t>;

/// Values worth printing: raw generator bits (every finite value is possible), subnormals,
/// and the edges of the type.
template <class T>
std::vector<T> sample_values() {
  using L = std::numeric_limits<T>;
  std::vector<T> values = {T(0),        -T(0),          T(1),           T(-1),
                           T(0.1),      T(-0.1),        T(1) / T(3),    T(9.81),
                           T(1e16),     T(123456789),   L::epsilon(),   T(1) + L::epsilon(),
                           L::min(),    -L::min(),      L::max(),       L::lowest(),
                           L::denorm_min(),             -L::denorm_min()};
  std::mt19937_64 rng(20240601);
  const Bits<T> mantissa_mask = (Bits<T>(1) << (L::digits - 1)) - 1;
  const Bits<T> sign_bit = Bits<T>(1) << (sizeof(T) * 8 - 1);
  for (int k = 0; k < 100000; ++k) {
    const T raw = std::bit_cast<T>(static_cast<Bits<T>>(rng()));
    if (std::isfinite(raw)) values.push_back(raw);
    // subnormal: exponent field zero
    values.push_back(std::bit_cast<T>(static_cast<Bits<T>>(rng() & (mantissa_mask | sign_bit))));
  }
  return values;
}

/// Reads a literal the way a C++ compiler does: optional parentheses around a negative value,
/// an 'f' suffix for float. Fails the test if the text is not a floating literal.
template <class T>
T read_back(const std::string& text) {
  // each group, when it takes part, is not empty
  static const Pattern form(R"(^(\(-)?[0-9]+(\.[0-9]*)?(e[+-]?[0-9]+)?(f)?(\))?$)");
  const Groups m = form.match(text).value_or(Groups(6));
  EXPECT_FALSE(m[0].empty()) << "'" << text << "' is not a C++ literal";
  EXPECT_EQ(m[1].empty(), m[5].empty()) << text << ": unbalanced parentheses";
  EXPECT_FALSE(m[2].empty() && m[3].empty()) << text << ": an integer literal, not floating";
  EXPECT_EQ(!m[4].empty(), (std::is_same_v<T, float>)) << text << ": wrong suffix for the type";
  std::string number = text;
  if (!m[1].empty()) number = number.substr(1, number.size() - 2);
  if (!m[4].empty()) number.pop_back();
  char* end = nullptr;
  const T x = std::is_same_v<T, float> ? std::strtof(number.c_str(), &end)
                                       : static_cast<T>(std::strtod(number.c_str(), &end));
  EXPECT_EQ(*end, '\0') << text;
  return x;
}

template <class T>
class Literal : public ::testing::Test {};
using Scalars = ::testing::Types<double, float>;
TYPED_TEST_SUITE(Literal, Scalars);

TYPED_TEST(Literal, ReadsBackToTheSameBits) {
  using T = TypeParam;
  int failures = 0;
  for (const T x : sample_values<T>()) {
    const std::string text = literal(x);
    const T y = read_back<T>(text);
    if (std::bit_cast<Bits<T>>(x) != std::bit_cast<Bits<T>>(y)) {
      ADD_FAILURE() << std::hexfloat << static_cast<double>(x) << " printed as " << text
                    << " reads back as " << static_cast<double>(y);
      if (++failures == 5) return;
    }
    EXPECT_EQ(text.front() == '(', std::signbit(x)) << text;
  }
}

TYPED_TEST(Literal, IsShortest) {
  using T = TypeParam;
  // at most 17 (double) or 9 (float) significant digits, and short values stay short
  const std::size_t most = std::is_same_v<T, float> ? 9 : 17;
  for (const T x : sample_values<T>()) {
    const std::string text = literal(x);
    std::string digits;
    for (const char c : text.substr(0, text.find('e')))
      if (c >= '0' && c <= '9') digits += c;
    const std::size_t first = digits.find_first_not_of('0');
    const std::size_t last = digits.find_last_not_of('0');
    const std::size_t significant = first == std::string::npos ? 0 : last - first + 1;
    ASSERT_LE(significant, most) << text;
  }
  constexpr bool single = std::is_same_v<T, float>;
  EXPECT_EQ(literal(T(0.5)), single ? "0.5f" : "0.5");
  EXPECT_EQ(literal(T(-2)), single ? "(-2.0f)" : "(-2.0)");
  EXPECT_EQ(literal(-T(0)), single ? "(-0.0f)" : "(-0.0)");
}

TYPED_TEST(Literal, RejectsNonFiniteConstants) {
  using T = TypeParam;
  using L = std::numeric_limits<T>;
  for (const T x : {L::infinity(), -L::infinity(), L::quiet_NaN(), -L::quiet_NaN()})
    EXPECT_THROW(literal(x), std::runtime_error) << x;
}

// ---- emitted code for a small model

Generated generate_planar5(bool single_precision) {
  const Robot robot = load_robot(std::string(DYNGEN_TEST_MODELS) + "/planar5.yaml");
  GenerateOptions options;
  options.name = "planar5";
  options.single_precision = single_precision;
  options.options_text = "--algorithms rnea,crba,aba";  // as the command line fills it in
  return generate(robot, options);
}

std::string generated_source(bool single_precision) {
  for (const GeneratedFile& f : generate_planar5(single_precision).files)
    if (f.name == "planar5_dynamics.cpp") return f.text;
  ADD_FAILURE() << "no planar5_dynamics.cpp";
  return {};
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    lines.push_back(text.substr(pos, end - pos));
    pos = end + 1;
  }
  return lines;
}

class Emitted : public ::testing::TestWithParam<bool /*float*/> {};

TEST_P(Emitted, SectionHeadersNameLinkJointTypeAndPass) {
  const Robot robot = load_robot(std::string(DYNGEN_TEST_MODELS) + "/planar5.yaml");
  const Model<double>& model = robot.model;
  const std::string source = generated_source(GetParam());
  const Pattern header(
      R"(^    // ---- link '(\w+)' \((\d+)\) <- (base|'(\w+)' \((\d+)\)); joint '(\w+)': )"
      R"((.+); (forward pass|backward pass|kinematics|composite inertia|)"
      R"(a descendant's column of M carried up|velocity pass|articulated inertia pass|)"
      R"(acceleration pass)$)");
  std::set<std::pair<int, std::string>> sections;
  for (const std::string& line : lines_of(source)) {
    if (line.find("// ----") == std::string::npos || line == "    // ---- outputs") continue;
    const std::optional<Groups> match = header.match(line);
    ASSERT_TRUE(match) << line;
    const Groups& m = *match;
    const int body = std::stoi(m[2]);
    ASSERT_LT(body, model.nbodies) << line;
    EXPECT_EQ(m[1], model.body_name[body]) << line;
    const int parent = model.parent[body];
    if (parent < 0) {
      EXPECT_EQ(m[3], "base") << line;
    } else {
      EXPECT_EQ(m[4], model.body_name[parent]) << line;
      EXPECT_EQ(std::stoi(m[5]), parent) << line;
    }
    EXPECT_EQ(m[6], model.joint_name[body]) << line;
    EXPECT_EQ(m[7], joint_description(model, body)) << line;
    sections.insert({body, m[8]});
  }
  // every link does work in these passes of RNEA and ABA, but for the first link's velocity
  // pass: its velocity is its joint's, and its sin and cos are in joint_trig
  for (int i = 0; i < model.nbodies; ++i)
    for (const char* pass : {"forward pass", "velocity pass", "acceleration pass"})
      EXPECT_EQ(sections.count({i, pass}), i > 0 || pass != std::string("velocity pass"))
          << model.body_name[i] << ": " << pass;
  EXPECT_NE(source.find("joint 'link1_joint': revolute +z; forward pass"), std::string::npos);
  EXPECT_NE(source.find("joint 'link4_joint': prismatic axis (1, 0, 0); forward pass"),
            std::string::npos);
}

TEST_P(Emitted, NoTrivialOperationsOrUnfoldedConstants) {
  const bool single = GetParam();
  const std::string source = generated_source(single);
  for (const char* artifact : {"* 1.0;", "* 1.0f;", "+ 0.0;", "+ 0.0f;", "- 0.0;", "- 0.0f;",
                               " 1.0 * ", " 1.0f * ", " 0.0 + ", " 0.0f + ", "* (-1.0"})
    EXPECT_EQ(source.find(artifact), std::string::npos) << "'" << artifact << "'";
  const std::string type = single ? "float" : "double";
  const Pattern statement("^    const " + type + R"( (\w+) = (.+);$)");
  const Pattern binary(R"(^(\S+) ([-+*/]) (\S+)$)");
  const Pattern constant(R"(^\(?-?[0-9][0-9.e+-]*f?\)?$)");
  int statements = 0;
  for (const std::string& line : lines_of(source)) {
    const std::optional<Groups> s = statement.match(line);
    if (!s) continue;
    ++statements;
    const std::optional<Groups> b = binary.match((*s)[2]);
    if (!b) continue;
    const std::string lhs = (*b)[1], op = (*b)[2], rhs = (*b)[3];
    const bool cl = constant.match(lhs).has_value(), cr = constant.match(rhs).has_value();
    EXPECT_FALSE(cl && cr) << "unfolded constants: " << line;
    auto value = [](std::string t) {
      t.erase(std::remove_if(t.begin(), t.end(), [](char c) { return c == '(' || c == ')'; }),
              t.end());
      return std::strtod(t.c_str(), nullptr);
    };
    const bool zero = (cl && value(lhs) == 0) || (cr && value(rhs) == 0);
    const bool one = (cl && std::abs(value(lhs)) == 1) || (cr && std::abs(value(rhs)) == 1);
    if (op == "*") {
      EXPECT_FALSE(zero || one) << line;
    } else if (op == "/") {
      EXPECT_FALSE((cl && value(lhs) == 0) || (cr && value(rhs) == 1)) << line;
    } else {
      EXPECT_FALSE(zero) << line;
    }
  }
  EXPECT_GT(statements, 100) << "the statement pattern matched nothing";
}

TEST_P(Emitted, EveryGeneratedFileIsFreeOfTrailingWhitespaceAndTabs) {
  const Generated generated = generate_planar5(GetParam());
  EXPECT_EQ(generated.files.size(), 7u);
  for (const GeneratedFile& f : generated.files) {
    EXPECT_FALSE(f.text.empty()) << f.name;
    EXPECT_EQ(f.text.back(), '\n') << f.name;
    EXPECT_EQ(f.text.find('\t'), std::string::npos) << f.name;
    int number = 0;
    for (const std::string& line : lines_of(f.text)) {
      ++number;
      EXPECT_TRUE(line.empty() || line.back() != ' ') << f.name << ":" << number;
    }
  }
}

TEST_P(Emitted, StatementsUseTheScalarTypeAndItsLiterals) {
  const bool single = GetParam();
  const std::string source = generated_source(single);
  const std::string declaration = std::string("    const ") + (single ? "float " : "double ");
  const Pattern number(R"((^|[ (])([0-9]+\.[0-9]*(e[+-]?[0-9]+)?|[0-9]+e[+-]?[0-9]+)(f?)\b)");
  int literals = 0;
  for (const std::string& line : lines_of(source)) {
    if (line.rfind("    const ", 0) != 0) continue;
    EXPECT_EQ(line.rfind(declaration, 0), 0u) << line;
    const std::string expr = line.substr(line.find(" = "));
    for (const Groups& literal : number.find_all(expr)) {
      ++literals;
      EXPECT_EQ(literal[4].length() == 1, single) << line;
    }
  }
  EXPECT_GT(literals, 10);
}

TEST_P(Emitted, SinAndCosOnlyInJointTrigOncePerRevoluteAngle) {
  const Robot robot = load_robot(std::string(DYNGEN_TEST_MODELS) + "/planar5.yaml");
  const Model<double>& model = robot.model;
  const std::string source = generated_source(GetParam());
  const std::size_t trig_begin = source.find("void joint_trig(");
  const std::size_t trig_end = source.find("\n}\n", trig_begin);
  ASSERT_NE(trig_begin, std::string::npos);
  ASSERT_NE(trig_end, std::string::npos);
  const std::string trig = source.substr(trig_begin, trig_end - trig_begin);
  std::string rest = source;
  rest.erase(trig_begin, trig_end - trig_begin);
  // a plain f(q, ...) that reads only some angles computes those, in a marked block
  const std::string marker = "    // the angles this function reads\n";
  for (std::size_t at = rest.find(marker); at != std::string::npos; at = rest.find(marker, at)) {
    std::size_t end = at + marker.size();
    while (rest.compare(end, 17, "    dyngen_sincos") == 0) end = rest.find('\n', end) + 1;
    EXPECT_GT(end, at + marker.size()) << "an empty block of angles";
    rest.erase(at, end - at);
  }
  for (const char* call : {"sin(", "cos(", "sincos("})
    EXPECT_EQ(rest.find(call), std::string::npos) << call << " outside joint_trig";
  // each revolute angle once, in a call for one angle or for a run of them
  std::vector<int> calls(model.nq, 0);
  const Pattern single(
      R"(dyngen_sincosf?\(q\[(\d+)\], &trig\.sin_q\[\1\], &trig\.cos_q\[\1\]\);)");
  const Pattern run(R"(dyngen_sincosf?_array\(q \+ (\d+), trig\.sin_q \+ \1, trig\.cos_q \+ \1, )"
                     R"((\d+)\);)");
  for (const std::string& line : lines_of(trig)) {
    if (const std::optional<Groups> m = single.search(line)) {
      ++calls.at(std::stoi((*m)[1]));
    } else if (const std::optional<Groups> r = run.search(line)) {
      for (int k = std::stoi((*r)[1]); k < std::stoi((*r)[1]) + std::stoi((*r)[2]); ++k)
        ++calls.at(k);
    }
  }
  for (int i = 0; i < model.nbodies; ++i)
    EXPECT_EQ(calls[model.q_index[i]], is_revolute(model.joint_type[i]) ? 1 : 0)
        << model.joint_name[i];
}

// A function whose _trig form reads no angle (the configuration space's) computes no sin or
// cos for it: f zeroes its trig; the others fill theirs (C++, C and batches).
TEST(Emitted, NoSinOrCosForAFunctionThatReadsNoAngle) {
  const Robot robot = load_robot(std::string(DYNGEN_TEST_MODELS) + "/ur5.urdf");
  for (const std::string language : {"c++", "c"}) {
    GenerateOptions options;
    options.name = "ur5";
    options.language = language;
    options.batch = language == "c" ? 0 : 2;
    options.algorithms = {"rnea", "integrate", "difference", "integrate_derivatives",
                          "difference_derivatives"};
    int zeroed = 0, filled = 0;
    for (const GeneratedFile& f : generate(robot, options).files) {
      if (f.name.find("_dynamics.c") == std::string::npos && f.name != "ur5_batch.cpp") continue;
      // and their banners say so
      const std::string note = "(it reads no joint angle).";
      int notes = 0;
      for (std::size_t at = f.text.find(note); at != std::string::npos;
           at = f.text.find(note, at + 1))
        ++notes;
      EXPECT_EQ(notes, 4) << f.name;
      for (const std::string& a : options.algorithms) {
        const std::string wrapper = (language == "c" ? "ur5_" : "") + a +
                                    (f.name == "ur5_batch.cpp" ? "_batch(" : "(");
        const std::size_t at = f.text.find("\nvoid " + wrapper);
        ASSERT_NE(at, std::string::npos) << f.name << ": " << wrapper;
        const std::string body = f.text.substr(at, f.text.find("\n}\n", at) - at);
        const bool zeroes = body.find("// no angle is read") != std::string::npos;
        EXPECT_EQ(zeroes, a != "rnea") << f.name << ": " << body;
        const bool sines = body.find("joint_trig") != std::string::npos ||
                           body.find("sincos") != std::string::npos;
        EXPECT_EQ(sines, a == "rnea") << f.name << ": " << body;
        ++(zeroes ? zeroed : filled);
      }
    }
    EXPECT_EQ(zeroed, language == "c" ? 4 : 8) << language;
    EXPECT_EQ(filled, language == "c" ? 1 : 2) << language;
  }
}

// ---- the shared structure

/// How often each operation statement runs in one call of code: the body's own statements,
/// plus each shared function's statements once per call of it.
long statements_run(const EmittedCode& code, const std::string& algorithm) {
  const Pattern statement(R"(^    const double \w+ = .+;$)");
  const Pattern function("^static void (" + algorithm + R"(_shape_\d+)\()");
  std::map<std::string, long> per_function;
  std::string current;
  for (const std::string& line : lines_of(code.helpers)) {
    if (const std::optional<Groups> m = function.search(line)) current = (*m)[1];
    if (!current.empty() && statement.match(line)) ++per_function[current];
  }
  long run = 0;
  for (const std::string& line : lines_of(code.body)) {
    if (statement.match(line)) ++run;
    for (const auto& [name, count] : per_function)
      if (line.find(name + "(") != std::string::npos) run += count;
  }
  return run;
}

/// Calls check(robot, program, what) for solo12's RNEA, CRBA and ABA, fixed and floating: four
/// legs of the same build, whose sections share code.
template <class Check>
void for_each_solo12_function(Check check) {
  for (const bool floating : {false, true}) {
    LoadOptions load;
    load.floating_base = floating;
    const Robot robot = load_robot(std::string(DYNGEN_TEST_MODELS) + "/solo12.urdf", load);
    for (const Algorithm a : {"rnea", "crba", "aba"})
      check(robot, trace<double>(a, robot.model), a + (floating ? " floating" : ""));
  }
}

TEST(SharedStructure, RunsEveryOperationOfTheUnrolledCodeOnce) {
  for_each_solo12_function([](const Robot& robot, const Program<double>& program,
                               const std::string& what) {
    const std::string& a = program.algorithm;
    const EmittedCode unrolled = emit_code(program, robot.model, Structure::Unrolled);
    const EmittedCode shared = emit_code(program, robot.model, Structure::Shared);
    const OpCounts ops = count_ops(program);
    EXPECT_TRUE(unrolled.helpers.empty()) << what;
    EXPECT_EQ(unrolled.shared_sections, 0) << what;
    EXPECT_EQ(statements_run(unrolled, a), ops.total() - ops.sin - ops.cos) << what;
    // four legs of the same build: their sections share code
    EXPECT_GT(shared.shared_functions, 0) << what;
    EXPECT_GE(shared.shared_sections, 2 * shared.shared_functions) << what;
    EXPECT_EQ(statements_run(shared, a), ops.total() - ops.sin - ops.cos) << what;
    EXPECT_LT(shared.body.size() + shared.helpers.size(), unrolled.body.size()) << what;
  });
}

// ---- the lane structure

/// The operations one call of lane code performs: each scalar statement one, each vector
/// statement one per lane.
long lane_statements_run(const EmittedCode& code, const std::string& scalar = "double") {
  const Pattern statement("^    const " + scalar + R"( \w+ = .+;$)");
  const Pattern vector(R"(^    const lanes(\d) \w+ = .+;$)");
  long run = 0;
  for (const std::string& line : lines_of(code.body)) {
    if (statement.match(line)) ++run;
    else if (const std::optional<Groups> m = vector.match(line)) run += std::stol((*m)[1]);
  }
  return run;
}

TEST(LaneStructure, RunsEveryOperationOfTheUnrolledCodeOnce) {
  for_each_solo12_function([](const Robot& robot, const Program<double>& program,
                               const std::string& what) {
    const EmittedCode lanes = emit_code(program, robot.model, Structure::Lanes);
    const OpCounts ops = count_ops(program);
    EXPECT_EQ(lane_statements_run(lanes), ops.total() - ops.sin - ops.cos) << what;
    EXPECT_TRUE(lanes.helpers.empty()) << what;
    // four legs of the same build: two legs to a statement
    EXPECT_GT(lanes.lane_blocks, 0) << what;
    const auto statements = [](const std::string& body) {
      long count = 0;
      for (const std::string& line : lines_of(body)) count += line.starts_with("    const ");
      return count;
    };
    EXPECT_EQ(statements(lanes.body) + lanes.lane_operations / 2,
              statements(emit_code(program, robot.model, Structure::Unrolled).body))
        << what;
    EXPECT_NE(lanes.body.find("typedef double lanes2 __attribute__((vector_size(2 * "
                              "sizeof(double))));"),
              std::string::npos)
        << what;
  });
}

TEST(LaneStructure, FourFloatsToAStatement) {
  const Robot robot =
      load_robot(std::string(DYNGEN_TEST_MODELS) + "/solo12.urdf", LoadOptions{});
  const Program<float> program = trace<float>("rnea", robot.model);
  const EmittedCode lanes = emit_code(program, robot.model, Structure::Lanes);
  const OpCounts ops = count_ops(program);
  EXPECT_EQ(lane_statements_run(lanes, "float"), ops.total() - ops.sin - ops.cos);
  EXPECT_NE(lanes.body.find("const lanes4 "), std::string::npos);
}

// a chain has one link at each depth: nothing to put in lanes, the code is the unrolled code
TEST(LaneStructure, AChainIsUnrolled) {
  const Robot robot = load_robot(std::string(DYNGEN_TEST_MODELS) + "/ur5.urdf", LoadOptions{});
  for (const Algorithm a : {"rnea", "crba", "aba", "centroidal"}) {
    const Program<double> program = trace<double>(a, robot.model);
    const EmittedCode lanes = emit_code(program, robot.model, Structure::Lanes);
    EXPECT_EQ(lanes.lane_blocks, 0) << a;
    EXPECT_EQ(lanes.body, emit_code(program, robot.model, Structure::Unrolled).body) << a;
  }
}

// C and batch code have no lanes of their own: Lanes prints them unrolled
TEST(LaneStructure, OnlyInCppScalarCode) {
  const Robot robot =
      load_robot(std::string(DYNGEN_TEST_MODELS) + "/solo12.urdf", LoadOptions{});
  const Program<double> program = trace<double>("rnea", robot.model);
  GenerateOptions c, batch;
  c.name = batch.name = "solo";
  c.language = "c";
  batch.batch = 4;
  const std::unique_ptr<Backend> c_backend = std::move(package_backends(c).front()),
                                 batch_backend = std::move(package_backends(batch)[1]);
  for (const Dialect* d : {c_backend->dialect(), batch_backend->dialect()}) {
    const Dialect& dialect = *d;
    const EmittedCode lanes = emit_code(program, robot.model, Structure::Lanes, dialect);
    EXPECT_EQ(lanes.lane_blocks, 0);
    EXPECT_EQ(lanes.body, emit_code(program, robot.model, Structure::Unrolled, dialect).body);
  }
}

// Auto: lanes where limbs repeat; elsewhere code that fits the instruction cache stays in place
// and bigger code is shared
TEST(Structures, AutoPutsLimbsInLanesAndSharesOnlyBigFunctions) {
  for_each_solo12_function([&](const Robot& robot, const Program<double>& program,
                               const std::string& what) {
    const EmittedCode automatic = emit_code(program, robot.model, Structure::Auto);
    EXPECT_GT(automatic.lane_blocks, 0) << what;
    EXPECT_EQ(automatic.body, emit_code(program, robot.model, Structure::Lanes).body) << what;
  });
  // an arm's passes have one link at each depth (its CRBA, which carries several columns of M
  // through each joint, has lanes)
  int big_functions = 0, small_functions = 0;
  const Robot arm = load_robot(std::string(DYNGEN_TEST_MODELS) + "/iiwa14.urdf", LoadOptions{});
  for (const Algorithm a : {"rnea", "aba"}) {
    const Program<double> program = trace<double>(a, arm.model);
    const OpCounts ops = count_ops(program);  // sin and cos come from joint_trig
    const bool big = ops.total() - ops.sin - ops.cos >= min_shared_function_operations;
    const EmittedCode automatic = emit_code(program, arm.model, Structure::Auto);
    const EmittedCode chosen =
        emit_code(program, arm.model, big ? Structure::Shared : Structure::Unrolled);
    EXPECT_EQ(automatic.body, chosen.body) << a;
    EXPECT_EQ(automatic.helpers, chosen.helpers) << a;
    EXPECT_EQ(automatic.shared_functions > 0, big) << a;
    ++(big ? big_functions : small_functions);
  }
  EXPECT_GT(big_functions, 0);
  EXPECT_GT(small_functions, 0);
}

TEST(Structures, AutoCountsKernelLoopsAgainstTheLaneLimit) {
  // atlas floating's rnea_derivatives: under the limit in statements, over it with the pairs'
  // kernel, whose loops the compile-time budget of issue 13 was measured with
  LoadOptions options;
  options.floating_base = true;
  const Robot atlas = load_robot(std::string(DYNGEN_TEST_MODELS) + "/atlas.urdf", options);
  const Program<double> program = trace<double>("rnea_derivatives", atlas.model);
  ASSERT_FALSE(program.graph.calls.empty());
  EXPECT_GE(count_ops(program).total(), max_lane_function_operations);
  const EmittedCode automatic = emit_code(program, atlas.model, Structure::Auto);
  EXPECT_EQ(automatic.lane_blocks, 0);
  EXPECT_EQ(automatic.body, emit_code(program, atlas.model, Structure::Shared).body);
  EXPECT_GT(emit_code(program, atlas.model, Structure::Lanes).lane_blocks, 0);
}

TEST(GeneratedPackage, CopiesTheRuntimeSinCosVerbatim) {
  std::ifstream in(std::string(DYNGEN_SOURCE_DIR) + "/runtime/include/dyngen/sincos.h");
  const std::string runtime((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(runtime.empty());
  int copies = 0;
  for (const GeneratedFile& f : generate_planar5(false).files)
    if (f.name == "dyngen_sincos.h") {
      EXPECT_EQ(f.text, runtime);
      ++copies;
    }
  EXPECT_EQ(copies, 1);
}

INSTANTIATE_TEST_SUITE_P(Scalars, Emitted, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "float" : "double"; });

// --lang c prints the same program: the same statements in the same order, spelled for C
LoadOptions floating_base() {
  LoadOptions options;
  options.floating_base = true;
  return options;
}

TEST(CLanguage, PrintsTheStatementsOfTheCppCode) {
  const Robot robot =
      load_robot(std::string(DYNGEN_TEST_MODELS) + "/solo12.urdf", floating_base());
  std::map<std::string, std::vector<std::string>> statements;
  for (const std::string language : {"c++", "c"}) {
    GenerateOptions options;
    options.name = "solo";
    options.language = language;
    options.algorithms = {"rnea", "aba", "minv"};
    options.structure = Structure::Shared;  // Auto has lanes in C++ alone
    for (const GeneratedFile& f : generate(robot, options).files) {
      if (!f.name.starts_with("solo_dynamics.c")) continue;
      for (std::string line : lines_of(f.text)) {
        // statements, and calls of the shared functions
        if (!line.starts_with("    const double ") &&
            !(line.starts_with("        ") && line.find("_shape_") != std::string::npos))
          continue;
        for (std::size_t at; (at = line.find("trig->")) != std::string::npos;)
          line.replace(at, 6, "trig.");
        statements[language].push_back(line);
      }
    }
  }
  ASSERT_GT(statements["c++"].size(), 1000u);
  EXPECT_EQ(statements["c"], statements["c++"]);
}

// The header says which rotor inertias are built into M, in both languages, and a robot
// without any gets no such line.
TEST(Armature, TheHeaderListsTheRotorInertias) {
  LoadOptions load;
  load.armature = {{"all", 0.05}, {"elbow_joint", 0.3}};
  const std::string path = std::string(DYNGEN_TEST_MODELS) + "/ur5.urdf";
  const Robot geared = load_robot(path, load), bare = load_robot(path);
  for (const std::string language : {"c++", "c"}) {
    GenerateOptions options;
    options.name = "ur5";
    options.language = language;
    const std::string header = language == "c" ? "ur5_dynamics.h" : "ur5_dynamics.hpp";
    for (const auto* robot : {&geared, &bare})
      for (const GeneratedFile& f : generate(*robot, options).files) {
        if (f.name != header) continue;
        const std::size_t at = f.text.find("/// Rotor inertias (armature");
        if (robot == &bare) {
          EXPECT_EQ(at, std::string::npos) << language;
          continue;
        }
        ASSERT_NE(at, std::string::npos) << language;
        const std::string lines = f.text.substr(at, f.text.find("\n\n", at) - at);
        EXPECT_NE(lines.find("shoulder_pan_joint 0.05,"), std::string::npos) << lines;
        EXPECT_NE(lines.find("elbow_joint 0.3,"), std::string::npos) << lines;
      }
  }
}

TEST(CLanguage, RefusesAlgorithmsThatCallKernels) {
  const Robot robot =
      load_robot(std::string(DYNGEN_TEST_MODELS) + "/atlas.urdf", floating_base());
  GenerateOptions options;
  options.name = "atlas";
  options.language = "c";
  options.algorithms = {"rnea", "aba_derivatives"};
  try {
    generate(robot, options);
    ADD_FAILURE() << "generated";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("aba_derivatives of this robot calls kernels"),
              std::string::npos)
        << e.what();
  }
}

// The calls taken for vector lanes (symbolic.hpp, vector_kernels_from) are C++'s, one state at a
// time: C output, which has no kernels, and a batch, which runs its states in the lanes, inline
// them, and compute the same bits (tests/generated checks both packages against the runtime)
TEST(KernelCalls, OnlyTheScalarCppCodeCallsKernelsForLanes) {
  const Robot robot =
      load_robot(std::string(DYNGEN_TEST_MODELS) + "/solo12.urdf", floating_base());
  GenerateOptions options;
  options.name = "solo";
  options.algorithms = {"aba_derivatives"};
  options.batch = 2;
  std::map<std::string, std::string> text;
  for (const GeneratedFile& f : generate(robot, options).files) text[f.name] = f.text;
  EXPECT_NE(text["solo_dynamics.cpp"].find("dyngen_kernels::neg_product("), std::string::npos);
  EXPECT_EQ(text["solo_batch.cpp"].find("dyngen_kernels::"), std::string::npos);
  options.batch = 0;
  options.language = "c";
  for (const GeneratedFile& f : generate(robot, options).files)
    EXPECT_EQ(f.text.find("kernels"), std::string::npos) << f.name;
}

// --batch prints the same program over lanes: the scalar code's statements, with each value a
// lane and each input and trig entry read from the lane loaded before the first statement
TEST(Batch, PrintsTheStatementsOfTheScalarCodeOverLanes) {
  const Robot robot =
      load_robot(std::string(DYNGEN_TEST_MODELS) + "/solo12.urdf", floating_base());
  GenerateOptions options;
  options.name = "solo";
  options.algorithms = {"rnea", "aba", "minv"};
  options.structure = Structure::Shared;  // Auto has lanes in the scalar code alone
  options.batch = 4;
  std::map<std::string, std::vector<std::string>> statements;
  for (const GeneratedFile& f : generate(robot, options).files) {
    if (f.name != "solo_dynamics.cpp" && f.name != "solo_batch.cpp") continue;
    for (std::string line : lines_of(f.text)) {
      if (f.name == "solo_dynamics.cpp") {
        if (!line.starts_with("    const double ")) continue;
        line.replace(0, 17, "    const lane ");
        // q[3] -> q3, trig.sin_q[3] -> sin_q3
        static const Pattern input(R"(\b(q|v|a|tau)\[(\d+)\])"),
            angle(R"(trig\.(sin|cos)_q\[(\d+)\])");
        line = angle.replace(input.replace(line, "$1$2"), "$1_q$2");
      } else if (!line.starts_with("    const lane ")) {
        continue;
      }
      statements[f.name].push_back(line);
    }
  }
  ASSERT_GT(statements["solo_dynamics.cpp"].size(), 1000u);
  EXPECT_EQ(statements["solo_batch.cpp"], statements["solo_dynamics.cpp"]);
}

TEST(JointDescription, NamesAxisAlignedAndGeneralJoints) {
  Model<double> m;
  m.nbodies = 4;
  m.joint_type = {JointType::RevoluteX, JointType::RevoluteY, JointType::Revolute,
                  JointType::Prismatic};
  m.joint_axis = {{1, 0, 0}, {0, -1, 0}, {0.6, 0, 0.8}, {0, 0, 1}};
  EXPECT_EQ(joint_description(m, 0), "revolute +x");
  EXPECT_EQ(joint_description(m, 1), "revolute -y");
  EXPECT_EQ(joint_description(m, 2), "revolute axis (0.6, 0, 0.8)");
  EXPECT_EQ(joint_description(m, 3), "prismatic axis (0, 0, 1)");
}

TEST(Banner, RecordsWhatSnapChanged) {
  LoadOptions load;
  load.snap = 1e-9;
  const Robot robot = load_robot(std::string(DYNGEN_TEST_MODELS) + "/iiwa14.urdf", load);
  ASSERT_TRUE(robot.snapped);
  EXPECT_GT(robot.snapped->snapped, 0);
  GenerateOptions options;
  options.name = "iiwa14";
  const std::string header = generate(robot, options).files.front().text;
  EXPECT_NE(header.find("// Model snapped (--snap): " + std::to_string(robot.snapped->snapped) +
                        " of "),
            std::string::npos)
      << header.substr(0, 2000);
}

TEST(SnapNote, NamesTheConstantsThatSnappingWouldMakeExact) {
  // iiwa14's URDF writes its right angles as rounded decimals; the loaded snapped model says
  // how many constants --snap 1e-9 moves, and the note without --snap must say the same
  LoadOptions load;
  load.snap = suggested_snap;
  const std::string iiwa14 = std::string(DYNGEN_TEST_MODELS) + "/iiwa14.urdf";
  const Robot snapped = load_robot(iiwa14, load);
  ASSERT_TRUE(snapped.snapped);
  ASSERT_GT(snapped.snapped->snapped, 0);
  const std::string note = snap_note(load_robot(iiwa14).model);
  EXPECT_EQ(note.rfind("note: " + std::to_string(snapped.snapped->snapped) + " of " +
                           std::to_string(snapped.snapped->entries) + " model constants",
                       0),
            0u)
      << note;
  EXPECT_NE(note.find("--snap 1e-09"), std::string::npos) << note;
  // nothing left to snap: no note
  EXPECT_EQ(snap_note(snapped.model), "");
  EXPECT_EQ(snap_note(load_robot(std::string(DYNGEN_TEST_MODELS) + "/planar5.yaml").model), "");
}

/// Operations of the generated frame_jacobians for the frames named (every link's if none),
/// and the number of frames.
std::pair<long, long> jacobian_operations(const std::string& file, bool floating_base,
                                          const std::vector<std::string>& frames) {
  LoadOptions load;
  load.floating_base = floating_base;
  load.frames = frames;
  load.all_frames = frames.empty();
  const Robot robot = load_robot(std::string(DYNGEN_TEST_MODELS) + "/" + file, load);
  GenerateOptions options;
  options.name = "robot";
  options.algorithms = {"frame_jacobians"};
  return {generate(robot, options).counts.front().generated.total(),
          static_cast<long>(robot.model.frames.size())};
}

// Selecting a frame costs its chain and no other frame's: ur5's tool0 alone costs at most the
// full set's average plus the Jacobian of the body tool0 is fixed on (wrist_3_link's origin: the
// chain's placements, which every frame on it shares) and the lever arm of that body's own
// column, which is zero at its origin (p - p folds, then its cross product with the axis: 3
// subtractions, 6 multiplications and 3 subtractions); code for all frames would cost the full
// set. A quadruped's four feet cost four times one foot's at most.
TEST(FrameSelection, OneFrameCostsOnlyItsChain) {
  const long tool0 = jacobian_operations("ur5.urdf", false, {"tool0"}).first;
  const long wrist = jacobian_operations("ur5.urdf", false, {"wrist_3_link"}).first;
  const auto [every, frames] = jacobian_operations("ur5.urdf", false, {});
  const long own_lever_arm = 3 + 6 + 3;
  EXPECT_LE(tool0, every / frames + wrist + own_lever_arm)
      << "all " << frames << " frames: " << every;
  EXPECT_LT(tool0, every);
  const long foot = jacobian_operations("solo12.urdf", true, {"FL_FOOT"}).first;
  const long feet =
      jacobian_operations("solo12.urdf", true, {"FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"})
          .first;
  EXPECT_LE(feet, 4 * foot);
  EXPECT_GT(feet, 3 * foot) << "the legs share nothing but the base";
}

// The outputs of an array with a block per frame say whose block begins, in frame order.
TEST(FrameSelection, OutputsNameTheFrameOfEachBlock) {
  LoadOptions load;
  load.frames = {"tool0", "ee_link"};
  const Robot robot = load_robot(std::string(DYNGEN_TEST_MODELS) + "/ur5.urdf", load);
  GenerateOptions options;
  options.name = "ur5";
  options.algorithms = {"frame_jacobians"};
  std::string source;
  for (const GeneratedFile& f : generate(robot, options).files)
    if (f.name == "ur5_dynamics.cpp") source = f.text;
  const std::size_t tool0 = source.find("    // frame 'tool0'\n    J[0] = ");
  const std::size_t ee_link = source.find("    // frame 'ee_link'\n    J[36] = ");
  EXPECT_NE(tool0, std::string::npos);
  EXPECT_NE(ee_link, std::string::npos);
  EXPECT_LT(tool0, ee_link);
}

// ---- exact zeros of the outputs: a loop, not a store each

/// What the outputs section of a generated file's function `function` leaves in its array
/// `array` of `size` entries (of each state in batch code): per entry, how many statements write
/// it (loops and stores; the loop over a whole array that stores then overwrite counts for
/// nothing where they do) and whether it ends 0; and the most stores of 0 in a row.
struct OutputWrites {
  std::vector<int> writes;
  std::vector<bool> zero;
  int zero_stores_in_a_row = 0;
};

OutputWrites output_writes(const std::string& source, const std::string& function,
                           const std::string& array, std::size_t size) {
  OutputWrites w{std::vector<int>(size, 0), std::vector<bool>(size, false)};
  const std::string lanes = R"((?: \* lanes)?)";
  const Pattern loop(R"(    for \(int k = (\d+))" + lanes + R"(; k < (\d+))" + lanes +
                     R"(; \+\+k\) )" + array + R"(\[k\] = 0\.0f?;.*)");
  const Pattern store("    (?:" + array + R"(\[(\d+)\] = (.+)|store\()" + array +
                      R"( \+ (\d+) \* lanes, (.+)\));)");
  std::vector<int> loops(size, 0), stores(size, 0);
  bool inside = false, outputs = false, filled = false;
  int row = 0;
  for (const std::string& line : lines_of(source)) {
    inside = inside || line.starts_with("void " + function + "(");
    if (!inside) continue;
    if (line == "}") break;
    outputs = outputs || line == "    // ---- outputs";
    if (!outputs) continue;
    if (const std::optional<Groups> m = loop.match(line)) {
      const std::size_t begin = std::stoul((*m)[1]);
      const std::size_t end = std::min<std::size_t>(std::stoul((*m)[2]), size);
      filled = filled || (begin == 0 && end == size);
      for (std::size_t k = begin; k < end; ++k) ++loops[k], w.zero[k] = true;
      row = 0;
    } else if (const std::optional<Groups> st = store.match(line)) {
      // a scalar store (groups 1 and 2) or a lane store (3 and 4)
      const Groups& g = *st;
      const std::size_t k = std::stoul(g[1].empty() ? g[3] : g[1]);
      const std::string value = g[1].empty() ? g[4] : g[2];
      if (k >= size) continue;
      ++stores[k];
      w.zero[k] = value == "0.0" || value == "0.0f";
      row = w.zero[k] ? row + 1 : 0;
      w.zero_stores_in_a_row = std::max(w.zero_stores_in_a_row, row);
    }
  }
  for (std::size_t k = 0; k < size; ++k)
    w.writes[k] = loops[k] + stores[k] - (filled && stores[k] > 0 ? 1 : 0);
  return w;
}

// Every entry of the frames' Jacobians is written, once (or by the fill and then its own store),
// the entries left 0 are 0 in the runtime's Jacobian at a random state, and no run of zeros is
// stored one entry at a time: in C++, C and batch code, for ur5 with the frames ee_link, tool0
// and base (base's block, J[72] to J[107], is all zero: a run in an array of fewer zeros than
// not), solo12 floating with every frame and a star of 12 links on one base (arrays mostly zero,
// filled by one loop: a star's frame has its own joint's column only).
TEST(OutputZeros, EveryEntryWrittenAndTheZerosByLoops) {
  std::string star = "<robot name=\"star\">\n  <link name=\"base\"/>\n";
  for (int i = 1; i <= 12; ++i)
    star += fmt::format(
        "  <link name=\"l{0}\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" "
        "izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\n"
        "  <joint name=\"j{0}\" type=\"continuous\"><parent link=\"base\"/><child link=\"l{0}\"/>"
        "<origin xyz=\"0.1 0 0\" rpy=\"0 0 {0}\"/><axis xyz=\"0 1 0\"/></joint>\n",
        i);
  star += "</robot>\n";
  LoadOptions floating = floating_base();
  floating.all_frames = true;
  LoadOptions three_frames;
  three_frames.frames = {"ee_link", "tool0", "base"};
  const std::string models = DYNGEN_TEST_MODELS;
  const Robot robots[] = {load_robot(models + "/ur5.urdf", three_frames),
                          load_robot(models + "/solo12.urdf", floating),
                          parse_robot("star.urdf", star, {})};
  for (const Robot& robot : robots) {
    const Model<double>& model = robot.model;
    std::mt19937_64 rng(40);
    std::vector<double> q(model.nq);
    for (double& x : q) x = static_cast<double>(rng() >> 11) * 0x1.0p-53 * 6 - 3;
    for (int i = 0; i < model.nbodies; ++i)
      if (model.joint_type[i] == JointType::Free) std::fill_n(&q[model.q_index[i] + 3], 4, 0.5);
    const std::size_t size = model.frames.size() * 6 * model.nv;
    std::vector<double> J(size);
    Workspace<double> ws(model);
    frame_jacobians<double>(model, ws, q, JacobianAxes::World, J);
    for (const auto& [language, batch] : {std::pair{"c++", 0}, std::pair{"c", 0},
                                          std::pair{"c++", 2}}) {
      GenerateOptions options;
      options.name = "robot";
      options.language = language;
      options.batch = batch;
      options.algorithms = {"frame_jacobians"};
      for (const GeneratedFile& f : generate(robot, options).files) {
        const bool c = f.name == "robot_dynamics.c", cpp = f.name == "robot_dynamics.cpp";
        if (!c && !cpp && f.name != "robot_batch.cpp") continue;
        const std::string function = c ? "robot_frame_jacobians_trig"
                                     : cpp ? "frame_jacobians_trig"
                                           : "frame_jacobians_batch_trig";
        const std::string where = robot.name + " " + f.name;
        const OutputWrites w = output_writes(f.text, function, "J", size);
        for (std::size_t k = 0; k < size; ++k) {
          EXPECT_EQ(w.writes[k], 1) << where << ": J[" << k << "]";
          if (w.zero[k]) {
            EXPECT_EQ(J[k], 0.0) << where << ": J[" << k << "]";
          }
        }
        EXPECT_LT(w.zero_stores_in_a_row, 8) << where;
        const std::string base_block = c || cpp ? "for (int k = 72; k < 108; ++k) J[k] = 0.0;"
                                                : "for (int k = 72 * lanes; k < 108 * lanes; "
                                                  "++k) J[k] = 0.0;";
        if (robot.name == "ur5") {
          EXPECT_NE(f.text.find(base_block), std::string::npos) << where;
        }
      }
    }
    if (robot.name != "star") continue;
    // every frame's Jacobian has 11 zero columns of 6: one loop fills the 864 entries, then each
    // frame's own column is stored, 6 entries at most
    GenerateOptions options;
    options.name = "star";
    options.algorithms = {"frame_jacobians"};
    for (const GeneratedFile& f : generate(robot, options).files) {
      if (f.name != "star_dynamics.cpp") continue;
      EXPECT_NE(f.text.find("    for (int k = 0; k < 864; ++k) J[k] = 0.0;  // "),
                std::string::npos);
      const std::size_t stores = Pattern(R"(\n    J\[\d+\] = )").find_all(f.text).size();
      EXPECT_LE(stores, 12u * 6);
    }
  }
}

}  // namespace
