// dyngen report end to end: it builds its harness against this build of dyngen, measures
// every variant and writes the four report files. The figures are checked against what must
// hold independently of the measurement: the generated code computes the runtime's bits, so
// their errors are identical; RNEA and CRBA stay within a few dozen units of roundoff; forward
// dynamics stays within the loss that the conditioning estimate (long double ABA pivots, not the
// MPFR reference) predicts; and times are positive.
#include <cmath>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "files.hpp"

namespace {

using dyngen::test::CliResult;
using dyngen::test::read;
using dyngen::test::run_dyngen;
using dyngen::test::ScratchTest;

const std::string models = DYNGEN_TEST_MODELS;

/// The result of one variant of one algorithm in report.json.
const nlohmann::json& result(const nlohmann::json& report, const std::string& algorithm,
                             const std::string& variant) {
  for (const nlohmann::json& r : report["results"])
    if (r["algorithm"] == algorithm && r["variant"] == variant) return r;
  ADD_FAILURE() << "no result for " << algorithm << " / " << variant;
  static const nlohmann::json none;
  return none;
}

using Report = ScratchTest;

TEST_F(Report, MeasuresEveryVariantOfEveryAlgorithm) {
  const std::filesystem::path out = dir / "report";
  const CliResult r = run_dyngen({"report", models + "/double_pendulum.urdf", "-o", out.string(),
                                  "--states", "40", "--min-time", "0.01", "--repetitions", "2",
                                  "--algorithms", "all"},
                                 dir);
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  for (const char* f : {"report.md", "report.json", "report.gp", "report.svg"})
    EXPECT_TRUE(std::filesystem::exists(out / f)) << f;
  EXPECT_NE(read(out / "report.svg").find("<svg"), std::string::npos);
  EXPECT_NE(r.out.find("[5/5] writing the report"), std::string::npos) << "progress is printed";

  const nlohmann::json report = nlohmann::json::parse(read(out / "report.json"));
  EXPECT_EQ(report["states"], 40);
  EXPECT_EQ(report["robot"], "2dof_planar");  // the name in the URDF
  const std::string markdown = read(out / "report.md");
  const double aba_loss = std::pow(10.0, report["conditioning"]["aba_digits_lost"].get<double>());
  for (const char* a : {"rnea", "crba", "aba", "gravity", "nle", "minv", "rnea_derivatives",
                        "aba_derivatives"}) {
    for (const char* scalar : {"double", "float"}) {
      const nlohmann::json& runtime = result(report, a, std::string("runtime ") + scalar);
      const nlohmann::json& generated = result(report, a, std::string("generated ") + scalar);
      // bit for bit: the same outputs, so exactly the same errors
      EXPECT_EQ(generated["median_error"], runtime["median_error"]) << a << " " << scalar;
      EXPECT_EQ(generated["worst_error"], runtime["worst_error"]) << a << " " << scalar;
      EXPECT_DOUBLE_EQ(runtime["speed_up"].get<double>(), 1.0);
    }
    for (const nlohmann::json& v : report["results"]) {
      if (v["algorithm"] != a) continue;
      const double eps = v["scalar"] == "float" ? 0x1p-24 : 0x1p-53;
      // measured: RNEA and CRBA 1.3e-15 / 4e-7 at worst; ABA 1.3e-13 / 5.7e-5 against an
      // estimated loss of 10^2.6, and what divides by ABA's pivots may lose as much;
      // rnea_derivatives 5.9e-15 (53 eps, at one of the 40 states; the median is 2 eps) and
      // 7.9e-7
      const std::string name = a;
      const bool pivots = name == "aba" || name == "minv" || name == "aba_derivatives";
      const double bound = (name == "rnea_derivatives" ? 100 : 50) * eps * (pivots ? aba_loss : 1.0);
      EXPECT_LT(v["worst_error"].get<double>(), bound) << a << " " << v["variant"];
      EXPECT_GT(v["median_ns"].get<double>(), 0.0);
      EXPECT_EQ(v["nonfinite"], 0);
      EXPECT_NE(markdown.find("| " + v["variant"].get<std::string>() + " |"), std::string::npos);
    }
  }
  EXPECT_EQ(result(report, "aba", "generated CRBA+LDLT double")["scalar"], "double");
  EXPECT_GT(report["conditioning"]["cond_M_max"].get<double>(), 1.0);
}

TEST_F(Report, OnlyTheRequestedAlgorithmsAndNonFiniteOutputs) {
  // the tip's inertia (1e-48 kg m^2) rounds to zero in float: the runtime's float ABA divides
  // by zero, and no float ABA can be generated
  const std::filesystem::path out = dir / "report";
  const CliResult r =
      run_dyngen({"report", models + "/coverage/tiny_tip.yaml", "-o", out.string(), "--algorithms",
                  "rnea,aba", "--states", "10", "--min-time", "0.01", "--repetitions", "1",
                  "--quiet"},
                 dir);
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_EQ(r.out, "") << "--quiet prints nothing";
  const nlohmann::json report = nlohmann::json::parse(read(out / "report.json"));
  ASSERT_FALSE(report["results"].empty());
  for (const nlohmann::json& v : report["results"]) EXPECT_NE(v["algorithm"], "crba");
  EXPECT_GE(report["conditioning"]["float_unrepresentable"].get<int>(), 1);
  EXPECT_EQ(result(report, "aba", "runtime float")["nonfinite"], 10);
  EXPECT_LT(result(report, "aba", "generated double")["worst_error"].get<double>(), 1e-6);
  const std::string markdown = read(out / "report.md");
  EXPECT_NE(markdown.find("| runtime float | inf | 10 non-finite |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("No generated float ABA"), std::string::npos) << markdown;
  for (const nlohmann::json& v : report["results"])
    EXPECT_FALSE(v["algorithm"] == "aba" && v["variant"] == "generated float");
}

TEST_F(Report, RefusesAbaOnMasslessJointsAndWritesNothing) {
  const std::filesystem::path out = dir / "report";
  const CliResult r = run_dyngen(
      {"report", models + "/romeo.urdf", "-o", out.string(), "--mimic-independent"}, dir);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("ABA is undefined"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--lock-massless"), std::string::npos) << r.err;
  for (const char* f : {"report.md", "report.json", "report.gp", "report.svg"})
    EXPECT_FALSE(std::filesystem::exists(out / f)) << f;
}

}  // namespace
