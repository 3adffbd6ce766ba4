#include "eval.hpp"

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include <fmt/format.h>

#include "dyngen/aba.hpp"
#include "dyngen/crba.hpp"
#include "dyngen/rnea.hpp"
#include "robot.hpp"

namespace dyngen::gen {

namespace {

std::vector<double> numbers(const nlohmann::json& state, int index, const char* field, int size) {
  const auto it = state.find(field);
  if (it == state.end())
    throw InputError(fmt::format("state {}: no \"{}\"", index, field));
  if (!it->is_array() || static_cast<int>(it->size()) != size)
    throw InputError(fmt::format("state {}: \"{}\" must be an array of {} numbers", index, field,
                                 size));
  std::vector<double> x;
  for (const nlohmann::json& e : *it) {
    if (!e.is_number() || !std::isfinite(e.get<double>()))
      throw InputError(fmt::format("state {}: \"{}\"[{}] is not a finite number", index, field,
                                   x.size()));
    x.push_back(e.get<double>());
  }
  return x;
}

void check_quaternions(const Model<double>& model, const std::vector<double>& q, int index) {
  for (int i = 0; i < model.nbodies; ++i) {
    if (model.joint_type[i] != JointType::Free) continue;
    const double* w = &q[model.q_index[i] + 3];
    const double norm = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2] + w[3] * w[3]);
    if (!(std::abs(norm - 1) <= 1e-6))
      throw InputError(fmt::format(
          "state {}: \"q\"[{}..{}], the quaternion (w, x, y, z) of free joint '{}', has length "
          "{:.17g}; it must be a unit quaternion",
          index, model.q_index[i] + 3, model.q_index[i] + 6, model.joint_name[i], norm));
  }
}

}  // namespace

nlohmann::json read_states(const std::string& path) {
  std::stringstream text;
  if (path == "-") {
    text << std::cin.rdbuf();
  } else {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(fmt::format("{}: cannot read the file", path));
    text << in.rdbuf();
  }
  try {
    return nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(fmt::format("{}: not valid JSON: {}", path == "-" ? "<stdin>" : path,
                                 e.what()));
  }
}

nlohmann::json evaluate(const Model<double>& model, const nlohmann::json& states) {
  if (!states.is_array())
    throw InputError("the states must be a JSON array of objects {\"q\", \"v\", \"a\" or \"tau\"}");
  const int n = model.nv;
  Workspace<double> ws(model);
  std::vector<double> tau(n), qdd(n), M(n * n);
  bool aba_checked = false;
  nlohmann::json results = nlohmann::json::array();
  for (int s = 0; s < static_cast<int>(states.size()); ++s) {
    const nlohmann::json& state = states[s];
    if (!state.is_object()) throw InputError(fmt::format("state {}: not a JSON object", s));
    for (const auto& [key, value] : state.items())
      if (key != "q" && key != "v" && key != "a" && key != "tau")
        throw InputError(fmt::format("state {}: unknown field \"{}\" (expected q, v, a, tau)", s,
                                     key));
    const std::vector<double> q = numbers(state, s, "q", model.nq);
    check_quaternions(model, q, s);
    nlohmann::json result = nlohmann::json::object();
    if (state.contains("a") || state.contains("tau")) {
      const std::vector<double> v = numbers(state, s, "v", n);
      if (state.contains("a")) {
        rnea<double>(model, ws, q, v, numbers(state, s, "a", n), tau);
        result["tau"] = tau;
      }
      if (state.contains("tau")) {
        if (!aba_checked) {
          const std::string reason = aba_undefined_reason(model);
          if (!reason.empty())
            throw InputError(reason + ", or give \"a\" instead of \"tau\"");
          aba_checked = true;
        }
        aba<double>(model, ws, q, v, numbers(state, s, "tau", n), qdd);
        result["qdd"] = qdd;
      }
    } else if (state.contains("v")) {
      throw InputError(fmt::format("state {}: \"v\" without \"a\" or \"tau\"", s));
    }
    crba<double>(model, ws, q, M);
    nlohmann::json rows = nlohmann::json::array();
    for (int i = 0; i < n; ++i) rows.push_back(std::vector<double>(&M[i * n], &M[i * n] + n));
    result["M"] = rows;
    results.push_back(result);
  }
  return {{"joints", velocity_names(model)}, {"nq", model.nq}, {"nv", n}, {"results", results}};
}

}  // namespace dyngen::gen
