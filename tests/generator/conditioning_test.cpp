// The conditioning estimate at generation time: the banner records it, dyngen warns when the
// generated scalar will keep too few digits, and the ABA estimate tracks the error that ABA
// really makes against the MPFR reference, from above and from below.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "dyngen/numerics/reference.hpp"
#include "files.hpp"
#include "generate.hpp"
#include "test_support.hpp"

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
  EXPECT_NE(single.warnings[0].find("ABA in float is expected to keep only"), std::string::npos);
  EXPECT_TRUE(twice.warnings.empty()) << "double keeps about 7 digits, above the floor of 6";

  const CliResult r = run_dyngen({spec, "-o", (dir / "gen").string(), "--scalar", "float"}, dir);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("dyngen: warning: ABA in float is expected to keep only"),
            std::string::npos)
      << r.err;
}

/// Worst ABA error over the states, in scalar S, against the MPFR reference at S's inputs.
template <class S>
double worst_aba_error(const Model<double>& model, int states) {
  numerics::ExactDynamics exact(model);
  const Model<S> m = model.cast<S>();
  Workspace<S> ws(m);
  numerics::Random rng(11);
  double worst = 0;
  for (int k = 0; k < states; ++k) {
    numerics::State s = numerics::random_state(model, rng);
    numerics::set_consistent_torques(exact, s);
    if (std::is_same_v<S, float>) s = numerics::round_to_float(s);
    const std::vector<S> q(s.q.begin(), s.q.end()), qd(s.qd.begin(), s.qd.end()),
        tau(s.tau.begin(), s.tau.end());
    std::vector<S> qdd(m.nv);
    aba<S>(m, ws, q, qd, tau, qdd);
    worst = std::max(worst, numerics::relative_error(qdd, exact.aba(s.q, s.qd, s.tau)));
  }
  return worst;
}

// Measured on the shared robots, fixed and floating, 40 states: the worst error lies between
// 0.054 (solo12, double) and 8.5 (pr2 floating, float) times eps * 10^aba_digits_lost. The
// bounds leave a factor of about 6 above and 13 below.
TEST(Conditioning, AbaEstimateTracksMeasuredError) {
  for (const test::RobotFile& file : test::robot_files()) {
    for (const bool floating : {false, true}) {
      const Model<double> model = test::load_for_aba(file, floating);
      const numerics::Conditioning c = numerics::estimate_conditioning(model, 16, 1);
      const double loss = std::pow(10.0, c.aba_digits_lost());
      const double in_double = worst_aba_error<double>(model, 40) / (0x1p-53 * loss);
      const double in_float = worst_aba_error<float>(model, 40) / (0x1p-24 * loss);
      std::printf("measured %s%s: ABA digits lost %.2f, worst error / (eps 10^lost) %.3g double, "
                  "%.3g float\n", file.name.c_str(), floating ? " floating" : "",
                  c.aba_digits_lost(), in_double, in_float);
      for (const double ratio : {in_double, in_float}) {
        EXPECT_LT(ratio, 50.0) << file.name << (floating ? " floating" : "");
        EXPECT_GT(ratio, 0.004) << file.name << (floating ? " floating" : "");
      }
    }
  }
}

}  // namespace
