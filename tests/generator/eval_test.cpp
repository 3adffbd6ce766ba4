// dyngen eval: JSON states in, the runtime's results out. The results are checked against each
// other through the JSON layer (RNEA's tau fed back as ABA's tau gives a back; M a + bias =
// tau), so a field in the wrong place or a number that does not round-trip fails.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

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

/// What dyngen eval writes for the states given as text, read from "<test>", in memory.
std::string eval_raw(const dyngen::Model<double>& model, const std::string& states,
                      bool derivatives = false, bool frames = false) {
  std::istringstream in(states);
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&buffer, &size);
  std::string error;
  try {
    evaluate(model, in, "<test>", out, {derivatives, frames});
  } catch (const InputError& e) {
    error = e.what();
  }
  std::fclose(out);
  const std::string text(buffer, size);
  std::free(buffer);
  if (!error.empty()) throw InputError(error);
  return text;
}

std::string eval_text(const dyngen::Model<double>& model, const json& states,
                      bool derivatives = false, bool frames = false) {
  return eval_raw(model, states.dump(), derivatives, frames);
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

/// A state of the model's sizes: q with unit quaternions at free and ball joints, v, and a or tau.
json state(const dyngen::Model<double>& model, int seed, const char* third) {
  std::vector<double> q, v, x;
  for (int k = 0; k < model.nq; ++k) q.push_back(std::sin(1.7 * k + seed));
  for (int i = 0; i < model.nbodies; ++i)
    if (const int o = dyngen::quaternion_offset(model.joint_type[i]); o >= 0) {
      double* w = &q[model.q_index[i] + o];
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
                                           EvalCase{"planar5.yaml", false},
                                           EvalCase{"coverage/ball_chain.yaml", true}),
                         [](const auto& info) {
                           const std::string file = info.param.robot.substr(
                               info.param.robot.find('/') + 1);  // npos + 1 = 0
                           return file.substr(0, file.find('.')) +
                                  (info.param.floating ? "_floating" : "");
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

/// The message of the InputError that eval throws for the states' text, or "" if it throws none.
std::string error_of(const dyngen::Model<double>& model, const std::string& states) {
  try {
    eval_raw(model, states);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Eval, BadStatesNameTheFileStateAndField) {
  const dyngen::Model<double> model = load_robot(models + "/ur5.urdf").model;
  const auto error = [&](const std::string& states) { return error_of(model, states); };
  const std::string six = "[0.1, 0.1, 0.1, 0.1, 0.1, 0.1]";
  const std::string good = R"({"q": )" + six + R"(, "v": )" + six + R"(, "a": )" + six + "}";
  EXPECT_EQ(error("{}"), R"(<test>: the states must be a JSON array of objects {"q", "v", "a" )"
                         R"(or "tau"}, not an object)");
  EXPECT_EQ(error("[" + good + ", 5]"),
            R"(<test>: state 1: must be a JSON object {"q", "v", "a" or "tau"}, not a number)");
  EXPECT_EQ(error(R"([{"v": )" + six + R"(, "a": )" + six + "}]"), R"(<test>: state 0: no "q")");
  EXPECT_EQ(error(R"([{"q": )" + six + R"(, "v": [0.1, 0.1, 0.1, 0.1, 0.1], "a": )" + six + "}]"),
            R"(<test>: state 0, field "v": must be an array of 6 numbers (nv), not 5)");
  EXPECT_EQ(error("[" + good + R"(, {"q": )" + six + R"(, "v": )" + six +
                  R"(, "a": [0, 0, "x", 0, 0, 0]}])"),
            R"(<test>: state 1, field "a"[2]: must be a number, not a string)");
  EXPECT_EQ(error(R"([{"q": 5}])"),
            R"(<test>: state 0, field "q": must be an array of 6 numbers, not a number)");
  EXPECT_EQ(error(R"([{"q": )" + six + R"(, "acc": )" + six + "}]"),
            R"(<test>: state 0: unknown field "acc" (expected q, v, a, tau))");
  EXPECT_EQ(error(R"([{"q": )" + six + R"(, "q": )" + six + "}]"),
            R"(<test>: state 0, field "q": given twice)");
  EXPECT_EQ(error(R"([{"q": )" + six + R"(, "v": )" + six + "}]"),
            R"(<test>: state 0: "v" without "a" or "tau")");
  const dyngen::Model<double> floating = load_robot(models + "/ur5.urdf", floating_base()).model;
  EXPECT_EQ(error_of(floating, R"([{"q": [0, 0, 0, 0.5, 0, 0, 0, 0, 0, 0, 0, 0, 0]}])"),
            "<test>: state 0, field \"q\"[3..6]: the quaternion (w, x, y, z) of free joint "
            "'floating_base' has length 0.5; it must be a unit quaternion");
  const dyngen::Model<double> ball = load_robot(models + "/coverage/ball_chain.yaml").model;
  EXPECT_EQ(error_of(ball, R"([{"q": [1, 0, 0, 0, 0, 0, 0, 0, 2, 1, 0, 0, 0]}])"),
            "<test>: state 0, field \"q\"[5..8]: the quaternion (w, x, y, z) of ball joint "
            "'wrist' has length 2; it must be a unit quaternion");
}

// 1e400 and its kin overflow double as JSON is read: bad input, named like any other
TEST(Eval, NumbersBeyondDoublesRangeNameTheFileStateAndField) {
  const dyngen::Model<double> model = load_robot(models + "/ur5.urdf").model;
  for (const std::string& number :
       std::vector<std::string>{"1e400", "-1e400", "2e308", "1" + std::string(400, '0')})
    EXPECT_EQ(error_of(model, R"([{"q": [0, 0, 0, 0, 0, 0]}, {"q": [0, 0, )" + number +
                                  ", 0, 0, 0]}]"),
              "<test>: state 1, field \"q\"[2]: " + number +
                  " is beyond double's range (±1.7976931348623157e+308)");
}

// A number that underflows reads as the nearest double, 0 or a subnormal: a finite number
TEST(Eval, NumbersThatUnderflowReadAsTheNearestDouble) {
  const dyngen::Model<double> model = load_robot(models + "/ur5.urdf").model;
  const auto with = [&](const std::string& number) {
    return eval_raw(model, R"([{"q": [0, 0.3, 0.2, 0.1, 0, )" + number + "]}]");
  };
  EXPECT_EQ(with("1e-400"), with("0"));
  EXPECT_EQ(with("-1e-400"), with("-0.0"));
  EXPECT_EQ(with("5e-324"), with("4.9406564584124654e-324"));
}

// NaN and the infinities have no spelling in JSON; those of other software are syntax errors
// named like bad numbers, with a hint
TEST(Eval, NanAndInfinityNameTheFileStateAndField) {
  const dyngen::Model<double> model = load_robot(models + "/ur5.urdf").model;
  for (const char* number : {"NaN", "nan", "-NaN", "Infinity", "-Infinity", "inf", "Inf"}) {
    const std::string error =
        error_of(model, std::string(R"([{"q": [0, )") + number + ", 0, 0, 0, 0]}]");
    EXPECT_EQ(error.find("<test>: state 0, field \"q\"[1]: not valid JSON at line 1, column "), 0u)
        << error;
    EXPECT_NE(error.find("; NaN and infinities are not JSON numbers, and eval takes finite "
                         "numbers only"),
              std::string::npos)
        << error;
  }
  EXPECT_EQ(error_of(model, R"([{"q": [0, 0,, 0, 0, 0]}])").find("NaN"), std::string::npos);
}

TEST(Eval, InvalidUtf8InTheStatesNamesTheState) {
  const dyngen::Model<double> model = load_robot(models + "/ur5.urdf").model;
  EXPECT_EQ(error_of(model, "[{\"q\xff\": [0, 0, 0, 0, 0, 0]}]"),
            "<test>: state 0: not valid JSON at line 1, column 5: syntax error while parsing "
            "object key - invalid string: ill-formed UTF-8 byte; last read: '\"q\xff'; expected "
            "string literal");
  EXPECT_EQ(error_of(model, "[{\"q\": [0, 0, \"\xfe\", 0, 0, 0]}]"),
            "<test>: state 0, field \"q\"[2]: not valid JSON at line 1, column 16: syntax error "
            "while parsing value - invalid string: ill-formed UTF-8 byte; last read: '\"\xfe'");
}

// A legged robot's states given without --floating-base: the count, and the option that fits it
TEST(Eval, AWrongCountSaysHowManyAndSuggestsTheFloatingBase) {
  const dyngen::Model<double> fixed = load_robot(models + "/solo12.urdf").model;
  const dyngen::Model<double> floating =
      load_robot(models + "/solo12.urdf", floating_base()).model;
  ASSERT_EQ(fixed.nq, 12);
  const auto numbers = [](int n) {
    return json(std::vector<double>(static_cast<std::size_t>(n), 0.0)).dump();
  };
  const std::string q12 = numbers(12);
  EXPECT_EQ(error_of(fixed, R"([{"q": )" + numbers(19) + "}]"),
            "<test>: state 0, field \"q\": must be an array of 12 numbers (nq), not 19: with "
            "--floating-base, the root would take 7 more (position and quaternion)");
  EXPECT_EQ(error_of(fixed, R"([{"q": )" + q12 + R"(, "v": )" + numbers(18) + R"(, "a": )" +
                                numbers(12) + "}]"),
            "<test>: state 0, field \"v\": must be an array of 12 numbers (nv), not 18: with "
            "--floating-base, the root would take 6 more (linear and angular velocity)");
  EXPECT_EQ(error_of(fixed, R"([{"q": )" + q12 + R"(, "v": )" + numbers(12) + R"(, "tau": )" +
                                numbers(18) + "}]"),
            "<test>: state 0, field \"tau\": must be an array of 12 numbers (nv), not 18: with "
            "--floating-base, the root would take 6 more (force and torque)");
  // no hint for a count that no free root explains, nor for a robot that has one
  EXPECT_EQ(error_of(fixed, R"([{"q": )" + numbers(13) + "}]"),
            "<test>: state 0, field \"q\": must be an array of 12 numbers (nq), not 13");
  EXPECT_EQ(error_of(floating, R"([{"q": )" + numbers(26) + "}]"),
            "<test>: state 0, field \"q\": must be an array of 19 numbers (nq), not 26");
}

/// A robot whose joint and link names hold invalid UTF-8 (0xfe, 0xff) and, in tip\xfe, the text
/// of its escape: three tips at different heights, at q = 0.
const char* invalid_names =
    "<?xml version=\"1.0\"?>\n<robot name=\"names\">\n<link name=\"base\"/>\n"
    "<link name=\"tip\xfe\"><inertial><mass value=\"1\"/><inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" "
    "iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/></inertial></link>\n"
    "<link name=\"tip\xff\"><inertial><mass value=\"1\"/><inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" "
    "iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/></inertial></link>\n"
    "<link name=\"tip\\xfe\"><inertial><mass value=\"1\"/><inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" "
    "iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/></inertial></link>\n"
    "<joint name=\"j\xfe\" type=\"continuous\"><parent link=\"base\"/><child link=\"tip\xfe\"/>"
    "<origin xyz=\"0 0 1\"/><axis xyz=\"0 0 1\"/></joint>\n"
    "<joint name=\"j\xff\" type=\"continuous\"><parent link=\"base\"/><child link=\"tip\xff\"/>"
    "<origin xyz=\"0 0 2\"/><axis xyz=\"0 0 1\"/></joint>\n"
    "<joint name=\"j3\" type=\"continuous\"><parent link=\"base\"/><child link=\"tip\\xfe\"/>"
    "<origin xyz=\"0 0 3\"/><axis xyz=\"0 0 1\"/></joint>\n</robot>\n";

// Names are written as the Python module reads them (python_text): the output stays valid UTF-8
// (json::parse checks it), each invalid byte is the text \xNN, and two frames whose names read
// the same are refused, so that no frame overwrites another.
TEST(Eval, InvalidUtf8NamesReadAsInPythonAndFramesStayApart) {
  LoadOptions options;
  options.frames = {"tip\xfe", "tip\xff"};
  const dyngen::Model<double> model = parse_robot("names.urdf", invalid_names, options).model;
  const json out = json::parse(eval_raw(model, R"([{"q": [0, 0, 0]}])", false, true));
  EXPECT_EQ(out["joints"], json::array({R"(j\xfe)", R"(j\xff)", "j3"}));
  const json& frames = out["results"][0]["frames"];
  ASSERT_EQ(frames.size(), 2u) << frames.dump();
  EXPECT_EQ(frames[R"(tip\xfe)"]["p"], json::array({0.0, 0.0, 1.0}));
  EXPECT_EQ(frames[R"(tip\xff)"]["p"], json::array({0.0, 0.0, 2.0}));
  options.frames.push_back("tip\\xfe");  // the text \xfe: reads as the byte 0xfe does
  const dyngen::Model<double> same = parse_robot("names.urdf", invalid_names, options).model;
  try {
    eval_raw(same, R"([{"q": [0, 0, 0]}])", false, true);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), R"(--frames: two frames are named 'tip\x5cxfe')");
  }
}

// Frames of the same name (the loader keeps one of each; a model built otherwise may not)
TEST(Eval, TwoFramesOfTheSameNameAreRefused) {
  LoadOptions options;
  options.frames = {"tool0", "wrist_1_link"};
  dyngen::Model<double> model = load_robot(models + "/ur5.urdf", options).model;
  model.frames[1].name = "tool0";
  const std::string q = R"([{"q": [0, 0, 0, 0, 0, 0]}])";
  try {
    eval_raw(model, q, false, true);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--frames: two frames are named 'tool0'");
  }
  EXPECT_NO_THROW(eval_raw(model, q));  // without --frames, frames are not written
}

/// Two prismatic joints along x: 1e308 each puts the tip at 2e308, while M (the masses) stays
/// finite; the tip's Jacobian, taken at its position, does not.
const char* prismatic_pair = R"(name: prismatic_pair
links:
  - {name: slider, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1},
     joint: {type: prismatic, axis: [1, 0, 0]}}
  - {name: tip, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1},
     joint: {type: prismatic, axis: [1, 0, 0]}}
)";

// an output of --frames that overflows names its frame (it was "frames\" J"[1][0])
TEST(Eval, AFrameOutputThatOverflowsNamesTheFrame) {
  LoadOptions options;
  options.frames = {"tip"};
  const dyngen::Model<double> model = parse_robot("pair.yaml", prismatic_pair, options).model;
  EXPECT_NO_THROW(eval_raw(model, R"([{"q": [1e308, 0]}])", false, true));
  try {
    eval_raw(model, R"([{"q": [1e308, 0]}, {"q": [1e308, 1e308]}])", false, true);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find(
                  "<test>: state 1: frame 'tip': \"J\"[1][0] is not finite ("),
              0u)
        << e.what();
  }
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

// --frames: each frame's R, p, base-axes J and (v given) Jdot_v from the runtime, printed as
// dump(2) prints them
TEST(Eval, FramesArePrintedAsTheirJsonTreeWouldBe) {
  LoadOptions options;
  options.frames = {"tool0", "wrist_1_link"};
  options.floating_base = true;
  const dyngen::Model<double> model = load_robot(models + "/ur5.urdf", options).model;
  const json states = json::array({state(model, 0, "a")});
  const std::vector<double> q = states[0]["q"];
  dyngen::Workspace<double> ws(model);
  const std::size_t nv = static_cast<std::size_t>(model.nv);
  std::vector<double> M(nv * nv), tau(nv), R(18), p(6), J(12 * nv), Jdot_v(12);
  dyngen::crba<double>(model, ws, q, M);
  dyngen::rnea<double>(model, ws, q, states[0]["v"].get<std::vector<double>>(),
                       states[0]["a"].get<std::vector<double>>(), tau);
  dyngen::frame_placements<double>(model, ws, q, R, p);
  dyngen::frame_jacobians<double>(model, ws, q, dyngen::JacobianAxes::World, J);
  dyngen::frame_bias_accelerations<double>(model, ws, q, states[0]["v"].get<std::vector<double>>(),
                                           dyngen::JacobianAxes::World, Jdot_v);
  json r = {{"tau", tau}};
  for (std::size_t i = 0; i < nv; ++i)
    r["M"].push_back(std::vector<double>(&M[nv * i], &M[nv * i + nv]));
  for (std::size_t f = 0; f < 2; ++f) {
    json& frame = r["frames"][model.frames[f].name];
    for (std::size_t i = 0; i < 3; ++i)
      frame["R"].push_back(std::vector<double>(&R[9 * f + 3 * i], &R[9 * f + 3 * i + 3]));
    frame["p"] = std::vector<double>(&p[3 * f], &p[3 * f + 3]);
    frame["Jdot_v"] = std::vector<double>(&Jdot_v[6 * f], &Jdot_v[6 * f + 6]);
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

// --contacts: what a user checks from eval's own output in a minute, with the feet's frames
// (--frames): rnea(q, v, qdd) = tau + J^T lambda, J qdd + Jdot_v = 0 for the constrained qdd,
// and the impulse's J v_plus = 0 and M (v_plus - v) = J^T impulse
TEST(Eval, ContactsPrintForcesThatSatisfyTheDefiningEquations) {
  LoadOptions options;
  options.floating_base = true;
  options.contacts = {"FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"};
  options.frames = options.contacts;
  const dyngen::Model<double> model = load_robot(models + "/solo12.urdf", options).model;
  const json states = json::array({state(model, 2, "tau")});
  const std::string text = eval_text(model, states, false, true);
  EXPECT_EQ(json::parse(text).dump(2) + "\n", text);
  const json out = json::parse(text);
  EXPECT_EQ(out["nc"], 12);
  EXPECT_EQ(out["constraints"][3], "HR_FOOT:3d");
  const json& r = out["results"][0];
  const Eigen::VectorXd qdd = vec(r["qdd"]), lambda = vec(r["lambda"]), v = vec(states[0]["v"]);
  const Eigen::VectorXd v_plus = vec(r["v_plus"]), impulse = vec(r["impulse"]);
  ASSERT_EQ(lambda.size(), 12);
  Eigen::MatrixXd J(12, model.nv);
  Eigen::VectorXd Jdot_v(12);
  for (int f = 0; f < 4; ++f) {
    const json& frame = r["frames"][options.contacts[static_cast<std::size_t>(f)]];
    for (int i = 0; i < 3; ++i) {
      J.row(3 * f + i) = vec(frame["J"][i]).transpose();
      Jdot_v[3 * f + i] = frame["Jdot_v"][i].get<double>();
    }
  }
  json with_a = states;
  with_a[0]["a"] = r["qdd"];
  const Eigen::VectorXd tau = vec(states[0]["tau"]);
  const Eigen::VectorXd rnea = vec(evaluate(model, with_a)["results"][0]["tau"]);
  const double scale = tau.norm() + (J.transpose() * lambda).norm();
  EXPECT_LE((rnea - tau - J.transpose() * lambda).norm(), 1e-12 * scale);
  EXPECT_LE((J * qdd + Jdot_v).norm(), 1e-12 * (J.norm() * qdd.norm() + Jdot_v.norm()));
  EXPECT_LE((J * v_plus).norm(), 1e-12 * J.norm() * v.norm());
  EXPECT_LE((mat(r["M"]) * (v_plus - v) - J.transpose() * impulse).norm(),
            1e-12 * (J.transpose() * impulse).norm());
  EXPECT_GT(lambda.norm(), 1.0);
}

// With --derivatives, contact_dynamics' six derivatives; their v and tau columns against central
// differences of eval's own qdd and lambda (h = 1e-6: truncation and rounding about 1e-9).
TEST(Eval, ContactDerivativesAreThoseOfContactDynamics) {
  LoadOptions options;
  options.floating_base = true;
  options.contacts = {"FL_FOOT", "HR_FOOT:6d"};
  const dyngen::Model<double> model = load_robot(models + "/solo12.urdf", options).model;
  const json states = json::array({state(model, 3, "tau")});
  const std::string text = eval_text(model, states, true);
  EXPECT_EQ(json::parse(text).dump(2) + "\n", text);  // the keys in dump's order
  const json r = json::parse(text)["results"][0];
  const auto rows = [](const json& x) {
    Eigen::MatrixXd A(x.size(), x[0].size());
    for (std::size_t i = 0; i < x.size(); ++i) A.row(i) = vec(x[i]).transpose();
    return A;
  };
  const double h = 1e-6;
  for (const char* wrt : {"v", "tau"}) {
    const Eigen::MatrixXd dqdd = rows(r[std::string("dqdd_d") + wrt]);
    const Eigen::MatrixXd dlambda = rows(r[std::string("dlambda_d") + wrt]);
    ASSERT_EQ(dqdd.rows(), model.nv);
    ASSERT_EQ(dlambda.rows(), model.nc);
    ASSERT_EQ(dlambda.cols(), model.nv);
    Eigen::MatrixXd fd_qdd(model.nv, model.nv), fd_lambda(model.nc, model.nv);
    for (int c = 0; c < model.nv; ++c) {
      json plus = states, minus = states;
      plus[0][wrt][c] = states[0][wrt][c].get<double>() + h;
      minus[0][wrt][c] = states[0][wrt][c].get<double>() - h;
      const json p = evaluate(model, plus)["results"][0], m = evaluate(model, minus)["results"][0];
      fd_qdd.col(c) = (vec(p["qdd"]) - vec(m["qdd"])) / (2 * h);
      fd_lambda.col(c) = (vec(p["lambda"]) - vec(m["lambda"])) / (2 * h);
    }
    EXPECT_LE((dqdd - fd_qdd).cwiseAbs().maxCoeff(), 1e-6 * fd_qdd.cwiseAbs().maxCoeff()) << wrt;
    EXPECT_LE((dlambda - fd_lambda).cwiseAbs().maxCoeff(), 1e-6 * fd_lambda.cwiseAbs().maxCoeff())
        << wrt;
  }
  EXPECT_EQ(rows(r["dqdd_dq"]).rows(), model.nv);
  EXPECT_EQ(rows(r["dlambda_dq"]).rows(), model.nc);
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
  EXPECT_NE(r.err.find("dyngen eval: error: <stdin>: state 1: \"tau\"[0] is not finite (inf): "
                       "the inputs overflow"),
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
  EXPECT_EQ(r.err.find("dyngen eval: error: <stdin>: state 0: \"M\"[0][0] is not finite ("), 0u)
      << r.err;
  EXPECT_NE(r.err.find("): the inputs overflow\n"), std::string::npos) << r.err;
}

// A number beyond double's range is bad input (it exited 2 with nlohmann's message): exit 1,
// naming the file, state and field; the states before it stay written, and the output lacks its
// closing brackets, so that no reader takes it for whole
TEST_F(EvalCommand, ANumberBeyondDoublesRangeExitsWithOne) {
  const std::string file = (dir / "states.json").string();
  std::ofstream(file) << R"([{"q": [0, 0, 0, 0, 0]}, {"q": [0, 0, 0, 1e400, 0]}])";
  const auto r = run_dyngen({"eval", models + "/planar5.yaml", "--states", file}, dir);
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "dyngen eval: error: " + file + ": state 1, field \"q\"[3]: 1e400 is beyond "
                   "double's range (±1.7976931348623157e+308)\n");
  EXPECT_NE(r.out.find("\"M\""), std::string::npos) << r.out;
  EXPECT_THROW(json::parse(r.out), json::parse_error);
  ASSERT_GT(r.out.size(), 6u);
  EXPECT_EQ(r.out.substr(r.out.size() - 6), "\n    }") << "state 0 whole, nothing of state 1";
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

/// The peak resident set of `dyngen eval ROBOT --states STATES` in kB (wait4's), its standard
/// output going to `out`.
long eval_peak_kb(const std::string& robot, const std::filesystem::path& states,
                  const std::filesystem::path& out) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0 || dup2(fd, STDOUT_FILENO) < 0) _exit(127);
    std::vector<std::string> args{DYNGEN_EXECUTABLE, "eval", robot, "--states", states.string()};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  if (pid < 0 || wait4(pid, &status, 0, &usage) != pid || !WIFEXITED(status) ||
      WEXITSTATUS(status) != 0)
    return -1;
  return usage.ru_maxrss;
}

// 100,000 states are read one at a time: the peak is that of no state, where holding their
// numbers alone would take 4.8 MB (and took 19 MB as vectors).
TEST_F(EvalCommand, ManyStatesAreNotHeld) {
  const std::string states = (dir / "states.json").string(), none = (dir / "none.json").string();
  std::ofstream(none) << "[]";
  {
    std::ofstream out(states);
    out << "[";
    for (int k = 0; k < 100000; ++k)
      out << (k ? "," : "") << R"({"q": [)" << 0.001 * k << R"(, 0.2], "v": [0.3, 0.4], "a": )"
          << "[0.5, 0.6]}";
    out << "]";
  }
  const std::string robot = models + "/double_pendulum.urdf";
  const long empty = eval_peak_kb(robot, none, dir / "out.json");
  const long many = eval_peak_kb(robot, states, dir / "out.json");
  ASSERT_GT(empty, 0);
  ASSERT_GT(many, 0);
  EXPECT_EQ(json::parse(dyngen::test::read(dir / "out.json"))["results"].size(), 100000u);
  EXPECT_LT(many - empty, 2 * 1024) << "kB more than with no state (" << empty << " kB)";
}

// A chain just above the runtime's limit for nv^2 buffers (so that the workspace holds none):
// one state's results are written as they are computed, so that its peak exceeds that of no
// state by M (8 nv^2 bytes, 8 MB) and a row's text, not by the results' 30 MB of text (it was
// 54 MB more).
TEST_F(EvalCommand, ALargeRobotsResultsAreNotHeld) {
  const int n = dyngen::Workspace<double>::max_matrix_nv + 1;
  const std::string spec = (dir / "chain.yaml").string(), one = (dir / "one.json").string(),
                    none = (dir / "none.json").string();
  {
    std::ofstream out(spec);
    out << "name: chain\nlinks:\n";
    for (int k = 0; k < n; ++k)
      out << "  - {mass: 1, com: [0.05, 0, 0], inertia: {ixx: 0.01, iyy: 0.02, izz: 0.02}, "
          << "length: 0.1, joint: {type: revolute, axis: [" << k % 2 << ", " << (k + 1) % 2
          << ", 0]}}\n";
  }
  std::ofstream(none) << "[]";
  std::ofstream(one) << json::array({{{"q", std::vector<double>(n, 0.1)}}}).dump();
  const long empty = eval_peak_kb(spec, none, dir / "out.json");
  const long peak = eval_peak_kb(spec, one, dir / "out.json");
  ASSERT_GT(empty, 0);
  ASSERT_GT(peak, 0);
  const std::uintmax_t text = std::filesystem::file_size(dir / "out.json");
  EXPECT_GT(text, 28u << 20) << "bytes of results";
  const long M = 8L * n * n / 1024;
  EXPECT_LT(peak - empty, M + 4 * 1024)
      << "kB more than with no state (" << empty << " kB), where M takes " << M << " kB";
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
  EXPECT_NE(malformed.err.find("dyngen eval: error: <stdin>: state 0: not valid JSON at line 1, "
                               "column 3: "),
            std::string::npos)
      << malformed.err;
  EXPECT_TRUE(malformed.out.empty());
  const auto missing =
      run_dyngen({"eval", models + "/ur5.urdf", "--states", (dir / "none.json").string()}, dir);
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.err.find("cannot read the file"), std::string::npos) << missing.err;
  // a directory opens, and fails at the first read (it exited 2 with libstdc++'s message)
  const auto directory =
      run_dyngen({"eval", models + "/ur5.urdf", "--states", dir.string()}, dir);
  EXPECT_EQ(directory.status, 1);
  EXPECT_NE(directory.err.find(dir.string() + ": cannot read: Is a directory"), std::string::npos)
      << directory.err;
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
