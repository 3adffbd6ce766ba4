// dyngen eval: JSON states in, the runtime's results out. The results are checked against each
// other through the JSON layer (RNEA's tau fed back as ABA's tau gives a back; M a + bias =
// tau), so a field in the wrong place or a number that does not round-trip fails.
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "eval.hpp"
#include "files.hpp"
#include "robot.hpp"

namespace {

using namespace dyngen::gen;
using nlohmann::json;
using dyngen::test::run_dyngen;
using dyngen::test::independent_mimics;
using dyngen::test::floating_base;

const std::string models = DYNGEN_TEST_MODELS;

Eigen::VectorXd vec(const json& x) {
  Eigen::VectorXd v(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) v[k] = x[k].get<double>();
  return v;
}

Eigen::MatrixXd mat(const json& rows) {
  Eigen::MatrixXd M(rows.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) M.row(i) = vec(rows[i]).transpose();
  return M;
}

/// A state of the model's sizes: q with unit quaternions at free joints, v, and a or tau.
json state(const dyngen::Model<double>& model, int seed, const char* third) {
  std::vector<double> q, v, x;
  for (int k = 0; k < model.nq; ++k) q.push_back(std::sin(1.7 * k + seed));
  for (int i = 0; i < model.nbodies; ++i)
    if (model.joint_type[i] == dyngen::JointType::Free) {
      double* w = &q[model.q_index[i] + 3];
      const double norm = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2] + w[3] * w[3]);
      for (int k = 0; k < 4; ++k) w[k] /= norm;
    }
  for (int k = 0; k < model.nv; ++k) v.push_back(std::cos(0.9 * k + seed));
  for (int k = 0; k < model.nv; ++k) x.push_back(std::sin(2.3 * k - seed));
  return {{"q", q}, {"v", v}, {third, x}};
}

struct EvalCase {
  std::string robot;
  bool floating;
};

class Eval : public ::testing::TestWithParam<EvalCase> {};

TEST_P(Eval, RneaAbaAndCrbaAgreeThroughJson) {
  LoadOptions options;
  options.floating_base = GetParam().floating;
  const dyngen::Model<double> model = load_robot(models + "/" + GetParam().robot, options).model;
  json states = json::array();
  for (int s = 0; s < 3; ++s) states.push_back(state(model, s, "a"));
  const json out = evaluate(model, states);
  ASSERT_EQ(out["nq"], model.nq);
  ASSERT_EQ(out["nv"], model.nv);
  ASSERT_EQ(out["joints"].size(), std::size_t(model.nv));
  ASSERT_EQ(out["results"].size(), states.size());

  // tau fed back: ABA returns a; the bias from a state with a = 0 closes M a + bias = tau
  json replay = json::array(), still = json::array();
  for (std::size_t s = 0; s < states.size(); ++s) {
    replay.push_back({{"q", states[s]["q"]}, {"v", states[s]["v"]}, {"tau", out["results"][s]["tau"]}});
    still.push_back({{"q", states[s]["q"]}, {"v", states[s]["v"]},
                     {"a", std::vector<double>(model.nv, 0.0)}});
  }
  const json back = evaluate(model, replay), bias = evaluate(model, still);
  for (std::size_t s = 0; s < states.size(); ++s) {
    const json& r = out["results"][s];
    EXPECT_FALSE(r.contains("qdd"));
    EXPECT_FALSE(back["results"][s].contains("tau"));
    const Eigen::VectorXd a = vec(states[s]["a"]), tau = vec(r["tau"]);
    const Eigen::MatrixXd M = mat(r["M"]);
    EXPECT_EQ(M, mat(back["results"][s]["M"]));
    EXPECT_LE((vec(back["results"][s]["qdd"]) - a).norm(), 1e-9 * a.norm());
    EXPECT_LE((M * a + vec(bias["results"][s]["tau"]) - tau).norm(), 1e-12 * tau.norm());
  }
}

INSTANTIATE_TEST_SUITE_P(Robots, Eval,
                         ::testing::Values(EvalCase{"ur5.urdf", false},
                                           EvalCase{"ur5.urdf", true},
                                           EvalCase{"solo12.urdf", true},
                                           EvalCase{"planar5.yaml", false}),
                         [](const auto& info) {
                           const std::string& r = info.param.robot;
                           return r.substr(0, r.find('.')) + (info.param.floating ? "_floating" : "");
                         });

TEST(Eval, FloatingBaseNamesItsVelocityEntries) {
  const dyngen::Model<double> model =
      load_robot(models + "/ur5.urdf", floating_base()).model;
  const json out = evaluate(model, json::array({state(model, 0, "a")}));
  EXPECT_EQ(out["nq"], 13);
  EXPECT_EQ(out["nv"], 12);
  EXPECT_EQ(out["joints"][0], "floating_base:vx");
  EXPECT_EQ(out["joints"][5], "floating_base:wz");
  EXPECT_EQ(out["joints"][6], "shoulder_pan_joint");
}

/// The message of the InputError that evaluate throws, or "" if it throws none.
std::string error_of(const json& states, bool floating = false) {
  const dyngen::Model<double> model =
      load_robot(models + "/ur5.urdf", floating ? floating_base() : LoadOptions{}).model;
  try {
    evaluate(model, states);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Eval, BadStatesNameTheStateAndField) {
  const std::vector<double> six(6, 0.1), five(5, 0.1);
  EXPECT_NE(error_of(json::object()).find("must be a JSON array"), std::string::npos);
  EXPECT_NE(error_of(json::array({{{"v", six}, {"a", six}}})).find("state 0: no \"q\""),
            std::string::npos);
  EXPECT_NE(error_of(json::array({{{"q", six}, {"v", five}, {"a", six}}}))
                .find("state 0: \"v\" must be an array of 6 numbers"),
            std::string::npos);
  EXPECT_NE(error_of(json::array({{{"q", six}, {"v", six}, {"a", six}},
                                  {{"q", six}, {"v", six}, {"a", {0, 0, "x", 0, 0, 0}}}}))
                .find("state 1: \"a\"[2] is not a finite number"),
            std::string::npos);
  EXPECT_NE(error_of(json::array({{{"q", six}, {"v", six}, {"acc", six}}}))
                .find("unknown field \"acc\""),
            std::string::npos);
  std::vector<double> q(13, 0.0);
  q[3] = 0.5;  // quaternion (0.5, 0, 0, 0)
  EXPECT_NE(error_of(json::array({{{"q", q}}}), true).find("must be a unit quaternion"),
            std::string::npos);
}

using EvalCommand = dyngen::test::ScratchTest;

TEST_F(EvalCommand, PrintsJsonForStatesOnStdin) {
  const std::vector<double> six(6, 0.1);
  const json states = json::array({{{"q", six}, {"v", six}, {"tau", six}}});
  const auto r = run_dyngen({"eval", models + "/ur5.urdf", "--states", "-"}, dir, states.dump());
  ASSERT_EQ(r.status, 0) << r.err;
  const json out = json::parse(r.out);
  EXPECT_EQ(out["results"][0]["qdd"].size(), 6u);
  EXPECT_EQ(out["results"][0]["M"].size(), 6u);
}

TEST_F(EvalCommand, BadInputExitsNonZeroWithMessage) {
  const auto malformed = run_dyngen({"eval", models + "/ur5.urdf", "--states", "-"}, dir, "[{");
  EXPECT_EQ(malformed.status, 1);
  EXPECT_NE(malformed.err.find("<stdin>: not valid JSON"), std::string::npos) << malformed.err;
  EXPECT_TRUE(malformed.out.empty());
  const auto missing =
      run_dyngen({"eval", models + "/ur5.urdf", "--states", (dir / "none.json").string()}, dir);
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.err.find("cannot read the file"), std::string::npos) << missing.err;
}

TEST(Eval, AbaOnMasslessJointsIsRefused) {
  const dyngen::Model<double> model =
      load_robot(models + "/romeo.urdf", independent_mimics()).model;
  try {
    evaluate(model, json::array({state(model, 0, "tau")}));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ABA is undefined"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--lock-massless"), std::string::npos) << e.what();
  }
}

}  // namespace
