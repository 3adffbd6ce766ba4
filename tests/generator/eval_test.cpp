// dyngen eval: JSON states in, the runtime's results out. The results are checked against each
// other through the JSON layer (RNEA's tau fed back as ABA's tau gives a back; M a + bias =
// tau), so a field in the wrong place or a number that does not round-trip fails.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/resource.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dyngen/aba.hpp"
#include "dyngen/crba.hpp"
#include "dyngen/frames.hpp"
#include "dyngen/rnea.hpp"

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

/// What dyngen eval writes for the states, as text: read_states and write_results in memory.
std::string eval_text(const dyngen::Model<double>& model, const json& states,
                      bool derivatives = false, bool frames = false) {
  std::istringstream in(states.dump());
  const std::vector<EvalState> read = read_states(model, in, "<test>");
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&buffer, &size);
  std::string error;
  try {
    write_results(model, read, out, derivatives, frames);
  } catch (const InputError& e) {
    error = e.what();
  }
  std::fclose(out);
  const std::string text(buffer, size);
  std::free(buffer);
  if (!error.empty()) throw InputError(error);
  return text;
}

json evaluate(const dyngen::Model<double>& model, const json& states) {
  return json::parse(eval_text(model, states));
}

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

// The results are written one state at a time, as the whole tree's dump(2) was: the same text,
// here against a tree built from the runtime's own results.
TEST(Eval, WritesTheResultsAsTheirJsonTreeWouldBePrinted) {
  const dyngen::Model<double> model = load_robot(models + "/ur5.urdf").model;
  json states = json::array({state(model, 0, "a"), state(model, 1, "tau"), state(model, 2, "a")});
  states[2]["tau"] = states[1]["tau"];
  states.push_back({{"q", states[0]["q"]}});
  json results = json::array();
  dyngen::Workspace<double> ws(model);
  for (const json& s : states) {
    const std::vector<double> q = s["q"];
    std::vector<double> M(36), out(6);
    json r = json::object();
    dyngen::crba<double>(model, ws, q, M);
    for (int i = 0; i < 6; ++i) r["M"].push_back(std::vector<double>(&M[6 * i], &M[6 * i + 6]));
    if (s.contains("a")) {
      dyngen::rnea<double>(model, ws, q, s["v"].get<std::vector<double>>(),
                           s["a"].get<std::vector<double>>(), out);
      r["tau"] = out;
    }
    if (s.contains("tau")) {
      dyngen::aba<double>(model, ws, q, s["v"].get<std::vector<double>>(),
                          s["tau"].get<std::vector<double>>(), out);
      r["qdd"] = out;
    }
    results.push_back(r);
  }
  const json tree = {{"joints", dyngen::velocity_names(model)},
                     {"nq", 6},
                     {"nv", 6},
                     {"results", results}};
  EXPECT_EQ(eval_text(model, states), tree.dump(2) + "\n");
  const json empty = {{"joints", dyngen::velocity_names(model)},
                      {"nq", 6},
                      {"nv", 6},
                      {"results", json::array()}};
  EXPECT_EQ(eval_text(model, json::array()), empty.dump(2) + "\n");
}

// --frames: each frame's R, p and base-axes J from the runtime, printed as dump(2) prints them
TEST(Eval, FramesArePrintedAsTheirJsonTreeWouldBe) {
  LoadOptions options;
  options.frames = {"tool0", "wrist_1_link"};
  options.floating_base = true;
  const dyngen::Model<double> model = load_robot(models + "/ur5.urdf", options).model;
  const json states = json::array({state(model, 0, "a")});
  const std::vector<double> q = states[0]["q"];
  dyngen::Workspace<double> ws(model);
  const std::size_t nv = static_cast<std::size_t>(model.nv);
  std::vector<double> M(nv * nv), tau(nv), R(18), p(6), J(12 * nv);
  dyngen::crba<double>(model, ws, q, M);
  dyngen::rnea<double>(model, ws, q, states[0]["v"].get<std::vector<double>>(),
                       states[0]["a"].get<std::vector<double>>(), tau);
  dyngen::frame_placements<double>(model, ws, q, R, p);
  dyngen::frame_jacobians<double>(model, ws, q, dyngen::JacobianAxes::World, J);
  json r = {{"tau", tau}};
  for (std::size_t i = 0; i < nv; ++i)
    r["M"].push_back(std::vector<double>(&M[nv * i], &M[nv * i + nv]));
  for (std::size_t f = 0; f < 2; ++f) {
    json& frame = r["frames"][model.frames[f].name];
    for (std::size_t i = 0; i < 3; ++i)
      frame["R"].push_back(std::vector<double>(&R[9 * f + 3 * i], &R[9 * f + 3 * i + 3]));
    frame["p"] = std::vector<double>(&p[3 * f], &p[3 * f + 3]);
    for (std::size_t i = 0; i < 6; ++i)
      frame["J"].push_back(std::vector<double>(&J[(6 * f + i) * nv], &J[(6 * f + i + 1) * nv]));
  }
  const json tree = {{"joints", dyngen::velocity_names(model)},
                     {"nq", model.nq},
                     {"nv", model.nv},
                     {"results", json::array({r})}};
  EXPECT_EQ(eval_text(model, states, false, true), tree.dump(2) + "\n");
  EXPECT_EQ(json::parse(eval_text(model, states, false, true))["results"][0]["frames"].size(), 2u);
}

// --derivatives against central differences of eval's own tau and qdd (what a user can do in a
// minute), and printed as dump(2) prints its tree
TEST(Eval, DerivativesAgreeWithCentralDifferences) {
  const dyngen::Model<double> model = load_robot(models + "/ur5.urdf").model;
  json s = state(model, 0, "a");
  s["tau"] = state(model, 1, "tau")["tau"];
  const std::string text = eval_text(model, json::array({s}), true);
  EXPECT_EQ(json::parse(text).dump(2) + "\n", text);
  const json r = json::parse(text)["results"][0];
  const double h = 1e-6;
  double worst = 0;
  for (int j = 0; j < 6; ++j) {
    for (const char* x : {"q", "v"}) {
      json plus = s, minus = s;
      plus[x][j] = s[x][j].get<double>() + h;
      minus[x][j] = s[x][j].get<double>() - h;
      const json rp = evaluate(model, json::array({plus}))["results"][0];
      const json rm = evaluate(model, json::array({minus}))["results"][0];
      for (const auto& [output, derivative] :
           {std::pair{"tau", std::string("dtau_d") + x}, std::pair{"qdd", std::string("dqdd_d") + x}}) {
        const Eigen::VectorXd fd = (vec(rp[output]) - vec(rm[output])) / (2 * h);
        for (int i = 0; i < 6; ++i)
          worst = std::max(worst, std::abs(r[derivative][i][j].get<double>() - fd[i]) /
                                      (1 + std::abs(fd[i])));
      }
    }
  }
  EXPECT_LT(worst, 1e-6);  // central differences at h = 1e-6: about 1e-9 truncation and rounding
  Eigen::MatrixXd M(6, 6), Minv(6, 6);
  for (int i = 0; i < 6; ++i) M.row(i) = vec(r["M"][i]), Minv.row(i) = vec(r["Minv"][i]);
  EXPECT_LT((Minv * M - Eigen::MatrixXd::Identity(6, 6)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Eval, DerivativesNeedAbasPivots) {
  // M^-1 comes with every state, so even a state without tau is refused
  const dyngen::Model<double> model =
      load_robot(models + "/romeo.urdf", independent_mimics()).model;
  const json s = {{"q", std::vector<double>(model.nq, 0.0)}};
  EXPECT_NO_THROW(eval_text(model, json::array({s})));
  try {
    eval_text(model, json::array({s}), true);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ABA is undefined"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--derivatives"), std::string::npos) << e.what();
  }
}

using EvalCommand = dyngen::test::ScratchTest;

/// A pendulum whose moment of inertia about its joint is 10 kg m^2 (1 kg, 0.1 m out, izz 9.99):
/// tau = 10 a without gravity, so a = 1e308 overflows tau, and qdd = tau / 10 never does.
const char* heavy_pendulum = R"(name: heavy_pendulum
gravity: [0, 0, 0]
links:
  - mass: 1
    com: [0.1, 0, 0]
    inertia: {ixx: 1, iyy: 9.99, izz: 9.99}
)";

TEST_F(EvalCommand, AnOutputThatOverflowsIsAnErrorNamingTheStateAndOutput) {
  const std::string spec = (dir / "pendulum.yaml").string();
  std::ofstream(spec) << heavy_pendulum;
  const json states = json::array({{{"q", {0}}, {"v", {0}}, {"a", {1}}},
                                   {{"q", {0}}, {"v", {0}}, {"a", {1e308}}}});
  const auto r = run_dyngen({"eval", spec, "--states", "-"}, dir, states.dump());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("dyngen eval: error: state 1: \"tau\"[0] is not finite (inf): the "
                       "inputs overflow"),
            std::string::npos)
      << r.err;
  // state 0 came out whole before the error; nothing of state 1 did
  EXPECT_NE(r.out.find("10.0"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("null"), std::string::npos) << r.out;
}

// A prismatic joint stretched to 1e300 m carries the last link's mass 1e300 m from the first
// joint, whose entry of M, m r^2, overflows.
const char* stretched_arm = R"(name: stretched_arm
links:
  - {mass: 1, com: [0.1, 0, 0], inertia: {ixx: 0.1, iyy: 0.1, izz: 0.1}}
  - {mass: 1, com: [0.1, 0, 0], inertia: {ixx: 0.1, iyy: 0.1, izz: 0.1},
     joint: {type: prismatic, axis: [1, 0, 0]}}
  - {mass: 1, com: [0.1, 0, 0], inertia: {ixx: 0.1, iyy: 0.1, izz: 0.1}}
)";

TEST_F(EvalCommand, AMassMatrixThatOverflowsNamesItsEntry) {
  const std::string spec = (dir / "arm.yaml").string();
  std::ofstream(spec) << stretched_arm;
  const auto r = run_dyngen({"eval", spec, "--states", "-"}, dir, R"([{"q": [0, 1e300, 0]}])");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err.find("dyngen eval: error: state 0: \"M\"[0][0] is not finite ("), 0u) << r.err;
  EXPECT_NE(r.err.find("): the inputs overflow\n"), std::string::npos) << r.err;
}

TEST_F(EvalCommand, StandardOutputThatCannotBeWrittenIsAnError) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string command = dyngen::test::shell_quoted(DYNGEN_EXECUTABLE) + " eval " +
                              dyngen::test::shell_quoted(models + "/planar5.yaml") +
                              " --states - >/dev/full 2>" +
                              dyngen::test::shell_quoted((dir / "err.txt").string());
  const std::string states = "[{\"q\": [0, 0, 0, 0, 0]}]";
  FILE* in = popen(command.c_str(), "w");
  ASSERT_NE(in, nullptr);
  std::fputs(states.c_str(), in);
  const int raw = pclose(in);
  ASSERT_TRUE(WIFEXITED(raw));
  EXPECT_EQ(WEXITSTATUS(raw), 1);
  const std::string err = dyngen::test::read(dir / "err.txt");
  EXPECT_NE(err.find("dyngen eval: error: cannot write the results to standard output: No space "
                     "left on device"),
            std::string::npos)
      << err;
}

// 200,000 states: neither their results nor the input's JSON tree are held (both took 470 MB),
// only the states' numbers (10 MB here).
TEST_F(EvalCommand, ManyStatesTakeLittleMemory) {
  json states = json::array();
  for (int k = 0; k < 200000; ++k)
    states.push_back({{"q", {0.001 * k, 0.2}}, {"v", {0.3, 0.4}}, {"a", {0.5, 0.6}}});
  const std::string file = (dir / "states.json").string();
  std::ofstream(file) << states.dump();
  states = json();
  const auto r = run_dyngen({"eval", models + "/double_pendulum.urdf", "--states", file}, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["results"].size(), 200000u);
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  EXPECT_LT(usage.ru_maxrss, 150 * 1024) << "kB, the largest of dyngen's";
}

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
