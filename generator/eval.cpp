#include "eval.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string_view>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "dyngen/aba.hpp"
#include "dyngen/aba_derivatives.hpp"
#include "dyngen/crba.hpp"
#include "dyngen/frames.hpp"
#include "dyngen/minv.hpp"
#include "dyngen/rnea.hpp"
#include "dyngen/rnea_derivatives.hpp"
#include "robot.hpp"

namespace dyngen::gen {

namespace {

std::vector<double> numbers(const nlohmann::json& state, std::size_t index, const char* field,
                            int size) {
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

void check_quaternions(const Model<double>& model, const std::vector<double>& q,
                       std::size_t index) {
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

/// A state's fields, checked in a fixed order: unknown fields, q, v, a, tau.
EvalState state_of(const Model<double>& model, const nlohmann::json& state, std::size_t s) {
  if (!state.is_object()) throw InputError(fmt::format("state {}: not a JSON object", s));
  for (const auto& [key, value] : state.items())
    if (key != "q" && key != "v" && key != "a" && key != "tau")
      throw InputError(fmt::format("state {}: unknown field \"{}\" (expected q, v, a, tau)", s,
                                   key));
  EvalState out;
  out.q = numbers(state, s, "q", model.nq);
  check_quaternions(model, out.q, s);
  if (state.contains("a") || state.contains("tau")) {
    out.v = numbers(state, s, "v", model.nv);
    if (state.contains("a")) out.a = numbers(state, s, "a", model.nv);
    if (state.contains("tau")) out.tau = numbers(state, s, "tau", model.nv);
  } else if (state.contains("v")) {
    throw InputError(fmt::format("state {}: \"v\" without \"a\" or \"tau\"", s));
  }
  return out;
}

/// Writes text, or throws FileError with the system's reason.
void put(std::FILE* out, std::string_view text) {
  if (std::fwrite(text.data(), 1, text.size(), out) != text.size())
    throw FileError(fmt::format("cannot write the results to standard output: {}",
                                std::strerror(errno)));
}

/// An array as dump(2) prints it `spaces` deep: its lines after the first indented so much.
std::string array_text(const std::vector<double>& x, int spaces) {
  const std::string text = nlohmann::json(x).dump(2);
  std::string out;
  for (const char c : text) {
    out += c;
    if (c == '\n') out.append(static_cast<std::size_t>(spaces), ' ');
  }
  return out;
}

void check_finite(const std::vector<double>& x, std::size_t s, const std::string& field) {
  for (std::size_t k = 0; k < x.size(); ++k)
    if (!std::isfinite(x[k]))
      throw InputError(fmt::format("state {}: \"{}\"[{}] is not finite ({}): the inputs overflow",
                                   s, field, k, x[k]));
}

}  // namespace

std::vector<EvalState> read_states(const Model<double>& model, std::istream& in,
                                   const std::string& name) {
  using Event = nlohmann::json::parse_event_t;
  std::vector<EvalState> states;
  bool array = false, aba_checked = false;
  // each element of the top-level array is taken when parsed and dropped from the tree
  const auto take = [&](int depth, Event event, nlohmann::json& parsed) {
    if (depth == 0 && !array) {
      if (event != Event::array_start)
        throw InputError(
            "the states must be a JSON array of objects {\"q\", \"v\", \"a\" or \"tau\"}");
      array = true;
    }
    if (depth != 1 || (event != Event::object_end && event != Event::array_end &&
                       event != Event::value))
      return true;
    states.push_back(state_of(model, parsed, states.size()));
    if (!states.back().tau.empty() && !aba_checked) {
      const std::string reason = aba_undefined_reason(model);
      if (!reason.empty()) throw InputError(reason + ", or give \"a\" instead of \"tau\"");
      aba_checked = true;
    }
    return false;
  };
  try {
    [[maybe_unused]] const nlohmann::json emptied = nlohmann::json::parse(in, take);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(fmt::format("{}: not valid JSON: {}", name, e.what()));
  }
  if (in.bad()) throw InputError(fmt::format("{}: cannot read: {}", name, std::strerror(errno)));
  return states;
}

std::vector<EvalState> read_states(const Model<double>& model, const std::string& path) {
  if (path == "-") return read_states(model, std::cin, "<stdin>");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot read the file", path));
  return read_states(model, in, path);
}

void write_results(const Model<double>& model, const std::vector<EvalState>& states,
                   std::FILE* out, bool derivatives, bool frames) {
  const std::size_t n = static_cast<std::size_t>(model.nv);
  if (derivatives) {
    if (model.nv > Workspace<double>::max_matrix_nv)
      throw InputError(fmt::format("--derivatives: the robot has {} degrees of freedom, above the "
                                   "runtime's {} for M^-1 and the derivatives of ABA",
                                   model.nv, Workspace<double>::max_matrix_nv));
    // M^-1 comes with every state
    if (const std::string reason = aba_undefined_reason(model); !reason.empty())
      throw InputError(reason + ", or leave out --derivatives (its \"Minv\" needs ABA's pivots)");
  }
  Workspace<double> ws(model);
  std::vector<double> tau, qdd, M, Minv, dtau_dq, dtau_dv, dqdd_dq, dqdd_dv;
  const std::size_t nframes = model.frames.size();
  std::vector<double> R(9 * nframes), p(3 * nframes), J(6 * nframes * n);
  std::string head =
      nlohmann::json{{"joints", velocity_names(model)}, {"nq", model.nq}, {"nv", model.nv}}.dump(2);
  head.resize(head.size() - 2);  // "\n}": the results follow
  put(out, head + ",\n  \"results\": [");
  // a matrix as a list of rows, 6 spaces deep like "M"
  const auto matrix = [&](const char* key, const std::vector<double>& A, std::size_t s,
                          bool first) {
    for (std::size_t k = 0; k < A.size(); ++k)
      if (!std::isfinite(A[k]))
        throw InputError(fmt::format(
            "state {}: \"{}\"[{}][{}] is not finite ({}): the inputs overflow", s, key, k / n,
            k % n, A[k]));
    std::string text = fmt::format("{}\n      \"{}\": [", first ? "" : ",", key);
    for (std::size_t i = 0; i < n; ++i)
      text += fmt::format("{}\n        {}", i == 0 ? "" : ",",
                          array_text(std::vector<double>(&A[i * n], &A[i * n] + n), 8));
    return text + "\n      ]";
  };
  for (std::size_t s = 0; s < states.size(); ++s) {
    const EvalState& state = states[s];
    const bool with_a = !state.a.empty(), with_tau = !state.tau.empty();
    tau.assign(with_a ? n : 0, 0.0);
    qdd.assign(with_tau ? n : 0, 0.0);
    M.resize(n * n);
    if (with_a) rnea<double>(model, ws, state.q, state.v, state.a, tau);
    if (with_tau) aba<double>(model, ws, state.q, state.v, state.tau, qdd);
    crba<double>(model, ws, state.q, M);
    if (derivatives) {
      Minv.resize(n * n);
      dtau_dq.assign(with_a ? n * n : 0, 0.0);
      dtau_dv.assign(with_a ? n * n : 0, 0.0);
      dqdd_dq.assign(with_tau ? n * n : 0, 0.0);
      dqdd_dv.assign(with_tau ? n * n : 0, 0.0);
      if (with_a) rnea_derivatives<double>(model, ws, state.q, state.v, state.a, dtau_dq, dtau_dv);
      if (with_tau)
        aba_derivatives<double>(model, ws, state.q, state.v, state.tau, dqdd_dq, dqdd_dv, Minv);
      // "Minv" is minv's with or without tau: aba_derivatives' own, from M's factors, can
      // differ from it in the last bits
      minv<double>(model, ws, state.q, Minv);
    }
    check_finite(qdd, s, "qdd");
    check_finite(tau, s, "tau");
    // the keys in nlohmann::json's order: M, Minv, dqdd_dq, dqdd_dv, dtau_dq, dtau_dv, frames,
    // qdd, tau
    std::string text = fmt::format("{}\n    {{", s == 0 ? "" : ",") + matrix("M", M, s, true);
    if (derivatives) text += matrix("Minv", Minv, s, false);
    if (derivatives && with_tau)
      text += matrix("dqdd_dq", dqdd_dq, s, false) + matrix("dqdd_dv", dqdd_dv, s, false);
    if (derivatives && with_a)
      text += matrix("dtau_dq", dtau_dq, s, false) + matrix("dtau_dv", dtau_dv, s, false);
    if (frames) {
      frame_placements<double>(model, ws, state.q, R, p);
      frame_jacobians<double>(model, ws, state.q, JacobianAxes::World, J);
      check_finite(R, s, "frames\" R");
      check_finite(J, s, "frames\" J");
      nlohmann::json object = nlohmann::json::object();
      for (std::size_t f = 0; f < nframes; ++f) {
        nlohmann::json rows = nlohmann::json::array(), jacobian = nlohmann::json::array();
        for (std::size_t i = 0; i < 3; ++i)
          rows.push_back(std::vector<double>(&R[9 * f + 3 * i], &R[9 * f + 3 * i + 3]));
        for (std::size_t i = 0; i < 6; ++i)
          jacobian.push_back(std::vector<double>(&J[(6 * f + i) * n], &J[(6 * f + i + 1) * n]));
        object[model.frames[f].name] = {
            {"J", jacobian}, {"R", rows}, {"p", std::vector<double>(&p[3 * f], &p[3 * f + 3])}};
      }
      // dump(2) of the object, six spaces deep like "M"
      std::string dumped = object.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
      for (std::size_t at = 0; (at = dumped.find('\n', at)) != std::string::npos; at += 7)
        dumped.insert(at + 1, 6, ' ');
      text += ",\n      \"frames\": " + dumped;
    }
    if (with_tau) text += ",\n      \"qdd\": " + array_text(qdd, 6);
    if (with_a) text += ",\n      \"tau\": " + array_text(tau, 6);
    put(out, text + "\n    }");
  }
  put(out, states.empty() ? "]\n}\n" : "\n  ]\n}\n");
  if (std::fflush(out) != 0 || std::ferror(out))
    throw FileError(fmt::format("cannot write the results to standard output: {}",
                                std::strerror(errno)));
}

}  // namespace dyngen::gen
