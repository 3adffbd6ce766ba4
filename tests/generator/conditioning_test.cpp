// The conditioning estimate at generation time: the banner records it and dyngen warns when the
// generated scalar will keep too few digits, or has no hardware on the --target processor.
// (That the estimate tracks the errors measured against the MPFR reference is
// tests/numerics/stiff_test's to check.)
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "files.hpp"
#include "generate.hpp"
#include "range.hpp"

namespace {

using namespace dyngen;
using namespace dyngen::gen;
using dyngen::test::CliResult;
using dyngen::test::run_dyngen;
using dyngen::test::ScratchTest;

const std::string models = DYNGEN_TEST_MODELS;

Generated generate_for(const Robot& robot, bool single) {
  GenerateOptions options;
  options.name = identifier(robot.name);
  options.single_precision = single;
  return generate(robot, options);
}

TEST(Conditioning, BannerRecordsTheEstimate) {
  const Generated g = generate_for(load_robot(models + "/ur5.urdf"), false);
  const std::string& header = g.files.front().text;
  EXPECT_NE(header.find("// Conditioning over 16 sampled states"), std::string::npos);
  EXPECT_NE(header.find("ABA may lose"), std::string::npos);
  EXPECT_TRUE(g.warnings.empty());
  // ur5's mass matrix is well conditioned (a few hundred, README of the peers tests)
  EXPECT_GT(g.conditioning.cond_M_max, 10.0);
  EXPECT_LT(g.conditioning.cond_M_max, 1e4);
}

// A pivot that is not positive leaves ABA no correct digit: the estimate must not read it as
// "0.0 digits lost" (log10 of a negative number is NaN, and max(0, NaN) is 0).
TEST(Conditioning, NonPositivePivotLosesEveryDigit) {
  for (const double pivot : {0.0, -3.4e-38, -1.0, std::nan("")}) {
    numerics::Conditioning c;
    c.pivot_min = pivot;
    c.pivot_joint = "floating_base";
    EXPECT_EQ(c.aba_digits_lost(), std::numeric_limits<double>::infinity()) << pivot;
    const std::string text = conditioning_text(c, true);
    EXPECT_NE(text.find("is not positive"), std::string::npos) << text;
    EXPECT_EQ(text.find("may lose"), std::string::npos) << text;
    EXPECT_EQ(text.find("0.0 digits"), std::string::npos) << text;
  }
}

/// A heavy upper arm and a thin rod that spins about its own long axis: the rod's joint moves
/// almost no inertia (1e-9 kg m^2) next to articulated inertias of order 1, so ABA's pivot for
/// it is about 1e-9 and float keeps no digit of its acceleration.
const char* spinning_rod = R"(name: spinning_rod
links:
  - mass: 20
    length: 0.5
    com: [0.25, 0, 0]
    inertia: {ixx: 0.05, iyy: 0.5, izz: 0.5}
  - mass: 1
    length: 0.5
    com: [0.25, 0, 0]
    inertia: {ixx: 1e-9, iyy: 0.02, izz: 0.02}
    joint: {axis: [1, 0, 0]}
)";

using ConditioningCli = ScratchTest;

TEST_F(ConditioningCli, WarnsWhenFloatWouldKeepTooFewDigits) {
  const std::string spec = (dir / "rod.yaml").string();
  std::ofstream(spec) << spinning_rod;
  const Robot robot = load_robot(spec);
  const Generated single = generate_for(robot, true), twice = generate_for(robot, false);
  EXPECT_GT(single.conditioning.aba_digits_lost(), 8.0);
  EXPECT_EQ(single.conditioning.pivot_joint, "link2_joint");
  ASSERT_EQ(single.warnings.size(), 1u);
  EXPECT_NE(single.warnings[0].find("ABA in float may keep only"), std::string::npos);
  EXPECT_TRUE(twice.warnings.empty()) << "double keeps about 7 digits, above the floor of 6";

  const CliResult r = run_dyngen({spec, "-o", (dir / "gen").string(), "--scalar", "float"}, dir);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("dyngen: warning: ABA in float may keep only"),
            std::string::npos)
      << r.err;
}

TEST_F(ConditioningCli, WarnsOfDoubleOnASinglePrecisionFpu) {
  const std::string urdf = models + "/ur5.urdf";
  const std::string warning = "double code runs in software floating point";
  for (const auto& [scalar, target, warns] :
       {std::tuple{"double", "cortex-m4f", true}, std::tuple{"double", "cortex-m33", true},
        std::tuple{"float", "cortex-m4f", false}, std::tuple{"double", "cortex-m7", false},
        std::tuple{"double", "host", false}}) {
    const CliResult r = run_dyngen({urdf, "-o", (dir / target).string(), "--scalar", scalar,
                                    "--target", target, "--algorithms", "rnea",
                                    "--no-measure"},
                                   dir);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err.find(warning) != std::string::npos, warns) << scalar << " " << target;
    std::ifstream in(dir / target / "ur5_dynamics.hpp");
    const std::string header((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(header.find(std::string("--target ") + target), std::string::npos)
        << "the banner records the target";
  }
  const CliResult unknown =
      run_dyngen({urdf, "-o", (dir / "x").string(), "--target", "cortex-m0"}, dir);
  EXPECT_EQ(unknown.status, 1);
  EXPECT_NE(unknown.err.find("--target"), std::string::npos) << unknown.err;
}

TEST_F(ConditioningCli, RefusesFloatAbaWhereTheFloatModelMovesNoInertia) {
  // the tip's inertia (1e-48 kg m^2) rounds to zero in float
  const std::string spec = models + "/coverage/tiny_tip.yaml";
  const CliResult refused =
      run_dyngen({spec, "-o", (dir / "f").string(), "--scalar", "float"}, dir);
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.err.find("ABA is undefined for this robot in float"), std::string::npos)
      << refused.err;
  EXPECT_NE(refused.err.find("'link2_joint'"), std::string::npos) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "f"));
  const CliResult twice = run_dyngen({spec, "-o", (dir / "d").string()}, dir);
  EXPECT_EQ(twice.status, 0) << twice.err;
  const CliResult without_aba = run_dyngen(
      {spec, "-o", (dir / "r").string(), "--scalar", "float", "--algorithms", "rnea,crba"}, dir);
  EXPECT_EQ(without_aba.status, 0) << without_aba.err;
}

// ---- the range of the traced values (range.hpp)

/// A program of one output, built by hand on ur5's inputs: make(graph) returns the stored node.
template <class Make>
Program<double> program_of(const Make& make) {
  Program<double> program;
  program.algorithm = "rnea";
  program.stored.push_back(make(program.graph));
  return program;
}

// v[0] * 1e306 stays below double's 1.8e308 while |v| <= 10 (typical states) and overflows once
// |v| > 180 (the extreme states' |v| reach 1e3); the estimate names that node, and what it would
// be without double's range, at most 1e3 * 1e306.
TEST(Range, FindsTheFirstValueBeyondTheScalarsRange) {
  const Model<double> model = load_robot(models + "/ur5.urdf").model;
  int product = -1;
  const Program<double> program = program_of([&](Graph<double>& g) {
    product = g.binary(Op::Mul, g.input("v", 0), g.constant(1e306));
    return g.binary(Op::Add, product, g.input("q", 1));
  });
  const RangeEstimate r = estimate_range(program, model);
  EXPECT_EQ(r.typical.overflow, -1);
  EXPECT_GT(r.typical.largest, 1e306L);
  EXPECT_LE(r.typical.largest, 1e307L + 4);
  EXPECT_EQ(r.extreme.overflow, product) << "the sum that reads it overflows after it";
  EXPECT_GT(r.extreme.overflow_value, static_cast<long double>(std::numeric_limits<double>::max()));
  EXPECT_LE(r.extreme.overflow_value, 1e309L);
  EXPECT_LE(r.extreme.largest, static_cast<long double>(std::numeric_limits<double>::max()));
}

// A division by zero is not finite at every state, and has no value to report.
TEST(Range, ADivisionByZeroOverflowsEverywhere) {
  const Model<double> model = load_robot(models + "/ur5.urdf").model;
  const Program<double> program = program_of([](Graph<double>& g) {
    return g.binary(Op::Div, g.input("tau", 2), g.constant(0.0));
  });
  const RangeEstimate r = estimate_range(program, model);
  EXPECT_EQ(r.typical.overflow, 2) << "node 2, after tau[2] and the constant";
  EXPECT_FALSE(std::isfinite(r.typical.overflow_value));
  EXPECT_EQ(r.extreme.overflow, r.typical.overflow);
}

/// The l1-l2 chain of tests/generator/bad/float_overflow_typical.yaml, 1e4 times lighter: float
/// holds its values at typical states (up to 4e36), and RNEA's and ABA's products overflow it at
/// extreme ones (|v| to 1e3, tau to 1e4).
const char* heavy_and_long = R"(name: heavy
links:
  - name: l1
    mass: 1e8
    length: 1e13
    com: [1e13, 0, 0]
    inertia: {ixx: 1e15, iyy: 1e15, izz: 1e15}
  - name: l2
    mass: 1e8
    length: 1e13
    com: [1e13, 0, 0]
    inertia: {ixx: 1e15, iyy: 1e15, izz: 1e15}
)";

TEST_F(ConditioningCli, WarnsWhereFloatOverflowsAtExtremeStatesOnly) {
  const std::string spec = (dir / "heavy.yaml").string();
  std::ofstream(spec) << heavy_and_long;
  const Generated g = generate_for(load_robot(spec), true);
  std::string warnings;
  for (const std::string& w : g.warnings) warnings += w + "\n";
  for (const char* part :
       {"rnea overflows in float at extreme states", "aba overflows in float at extreme states",
        "at link 'l2' (forward pass) reaches", "beyond float's largest number 3.4e+38",
        "--scalar double"})
    EXPECT_NE(warnings.find(part), std::string::npos) << part << " not in " << warnings;
  EXPECT_EQ(warnings.find("crba"), std::string::npos) << "M is q's alone: " << warnings;
  const std::string& header = g.files.front().text;
  for (const char* part :
       {"keeping about 15.3 in double and 6.5 in float (none in float at extreme states, where "
        "it overflows)",
        "//   rnea overflows at extreme states, where it keeps no digit: a product at link 'l2'"})
    EXPECT_NE(header.find(part), std::string::npos) << part;
  EXPECT_TRUE(generate_for(load_robot(spec), false).warnings.empty()) << "double holds them";
}

// No false alarm: the shared robots and the stiff ones keep their values within float's range
// by more than 17 orders of magnitude (docs/numerics.md, "Range"); atlas's derivatives call
// kernels, which the estimate runs on numbers.
TEST(Range, NoWarningForTheSharedAndStiffRobotsInFloat) {
  LoadOptions floating;
  floating.floating_base = true;
  const std::vector<std::string> dynamics = {"rnea", "crba", "aba", "minv", "centroidal"};
  const std::vector<std::tuple<std::string, LoadOptions, std::vector<std::string>>> robots = {
      {"ur5.urdf", {}, dynamics},
      {"atlas.urdf", floating, {"rnea", "aba", "rnea_derivatives", "aba_derivatives"}},
      {"stiff/light_limbs.urdf", floating, dynamics},
      {"stiff/thin_rods12.yaml", {}, dynamics},
      {"stiff/tapered50_0p9.yaml", {}, dynamics}};
  for (const auto& [file, load, algorithms] : robots) {
    GenerateOptions options;
    options.name = "robot";
    options.single_precision = true;
    options.algorithms = algorithms;
    const Generated g = generate(load_robot(models + "/" + file, load), options);
    for (const std::string& w : g.warnings) EXPECT_EQ(w.find("overflow"), std::string::npos) << w;
    EXPECT_NE(g.conditioning_text.find("float's largest number is 3.4e+38"), std::string::npos)
        << file;
    if (file == "atlas.urdf") {
      EXPECT_NE(g.files[1].text.find("dyngen_kernels::"), std::string::npos) << g.files[1].name;
    }
  }
}

}  // namespace
