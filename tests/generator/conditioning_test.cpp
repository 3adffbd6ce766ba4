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

}  // namespace
