#include "eval.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string_view>
#include <vector>

#include "dyngen/aba.hpp"
#include "dyngen/aba_derivatives.hpp"
#include "dyngen/constrained.hpp"
#include "dyngen/contact_derivatives.hpp"
#include "dyngen/crba.hpp"
#include "dyngen/frames.hpp"
#include "dyngen/minv.hpp"
#include "dyngen/regressor.hpp"
#include "dyngen/rnea.hpp"
#include "dyngen/rnea_derivatives.hpp"
#include "names.hpp"
#include "robot.hpp"

namespace dyngen::gen {

namespace {

using json = nlohmann::json;

/// A state's fields, in the order their errors are reported.
enum Field : std::size_t { Q, V, A, Tau, no_field };
constexpr std::array<const char*, 4> field_names{"q", "v", "a", "tau"};

/// One state as read: each field's numbers, at most as many as the model takes (so that a long
/// array costs no memory), and how many the file gave.
struct State {
  static constexpr std::size_t absent = SIZE_MAX;
  std::array<std::vector<double>, 4> x;
  std::array<std::size_t, 4> count{absent, absent, absent, absent};
  bool has(Field f) const { return count[f] != absent; }
};

std::size_t field_size(const Model<double>& model, Field f) {
  return static_cast<std::size_t>(f == Q ? model.nq : model.nv);
}

/// Why a field's length is wrong, and --floating-base when that length is what a free root
/// would make it.
std::string length_error(const Model<double>& model, Field f, std::size_t given) {
  const std::size_t size = field_size(model, f), more = f == Q ? 7 : 6;
  std::string text = fmt::format("must be an array of {} numbers ({}), not {}", size,
                                 f == Q ? "nq" : "nv", given);
  bool floating = false;
  for (int i = 0; i < model.nbodies; ++i)
    floating |= model.parent[i] < 0 && model.joint_type[i] == JointType::Free;
  constexpr std::array<const char*, 4> root{"position and quaternion",
                                            "linear and angular velocity",
                                            "linear and angular acceleration", "force and torque"};
  if (!floating && given == size + more)
    text += fmt::format(": with --floating-base, the root would take {} more ({})", more, root[f]);
  return text;
}

/// Whether the token that a syntax error stopped at ends in a spelling of NaN or infinity
/// (NaN, nan, Infinity, inf, ...), which other software writes and JSON has not.
bool spells_nonfinite(const std::string& token) {
  std::size_t start = token.size();
  while (start > 0 && std::isalpha(static_cast<unsigned char>(token[start - 1]))) --start;
  std::string word = token.substr(start);
  for (char& c : word) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return !word.empty() && (std::string_view("nan").substr(0, word.size()) == word ||
                           std::string_view("infinity").substr(0, word.size()) == word);
}

/// nlohmann::json's SAX events for the array of states (depth 0: before it, 1: in it, 2: in a
/// state, 3: in a field's array), gathered into one state at a time, which is checked and
/// handed to `take` as soon as its object closes. Each error throws InputError naming the file,
/// the state and the field being read.
class StateReader {
 public:
  using Take = std::function<void(const State&, std::size_t)>;

  StateReader(const Model<double>& model, const std::string& name, Take take)
      : model_(model), name_(name), take_(std::move(take)) {}

  bool null() { misplaced("null"); }
  bool boolean(bool) { misplaced("a boolean"); }
  bool number_integer(json::number_integer_t x) { return number(static_cast<double>(x)); }
  bool number_unsigned(json::number_unsigned_t x) { return number(static_cast<double>(x)); }
  bool number_float(json::number_float_t x, const json::string_t&) { return number(x); }
  bool string(json::string_t&) { misplaced("a string"); }
  bool binary(json::binary_t&) { misplaced("binary data"); }

  bool start_object(std::size_t) {
    if (depth_ != 1) misplaced("an object");
    state_ = State{};
    depth_ = 2;
    return true;
  }

  bool key(json::string_t& key) {
    const auto it = std::find(field_names.begin(), field_names.end(), key);
    if (it == field_names.end())
      fail(fmt::format("unknown field \"{}\" (expected q, v, a, tau)", key));
    field_ = static_cast<Field>(it - field_names.begin());
    if (state_.has(field_)) fail("given twice");
    return true;
  }

  bool end_object() {
    complete();
    take_(state_, index_++);
    depth_ = 1;
    return true;
  }

  bool start_array(std::size_t) {
    if (depth_ == 1 || depth_ == 3) misplaced("an array");
    if (depth_ == 2) state_.count[field_] = 0;
    ++depth_;
    return true;
  }

  bool end_array() {
    --depth_;  // a field's array closes into its state, the states' into nothing
    field_ = no_field;
    return true;
  }

  bool parse_error(std::size_t, const std::string& token, const json::exception& e) {
    if (e.id == 406)  // out_of_range: a number that overflows double
      fail(fmt::format("{} is beyond double's range (±{:.17g})", token,
                       std::numeric_limits<double>::max()));
    // "[json.exception.parse_error.101] parse error at line 1, column 3: syntax error ..."
    const std::string what = e.what();
    const std::size_t at = what.find(" at line ");
    fail("not valid JSON" + (at == std::string::npos ? ": " + what : what.substr(at)) +
         (spells_nonfinite(token) ? "; NaN and infinities are not JSON numbers, and eval takes "
                                    "finite numbers only"
                                  : ""));
  }

 private:
  /// The file, and the state, field and entry being read.
  std::string location() const {
    std::string text = name_;
    if (depth_ >= 1) text += fmt::format(": state {}", index_);
    if (field_ != no_field) text += fmt::format(", field \"{}\"", field_names[field_]);
    if (depth_ == 3) text += fmt::format("[{}]", state_.count[field_]);
    return text;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(location() + ": " + what);
  }

  [[noreturn]] void misplaced(const std::string& kind) const {
    if (depth_ == 0)
      throw InputError(name_ + ": the states must be a JSON array of objects {\"q\", \"v\", \"a\" "
                               "or \"tau\"}, not " + kind);
    if (depth_ == 1) fail("must be a JSON object {\"q\", \"v\", \"a\" or \"tau\"}, not " + kind);
    if (depth_ == 2)
      fail(fmt::format("must be an array of {} numbers, not {}", field_size(model_, field_), kind));
    fail("must be a number, not " + kind);
  }

  bool number(double x) {
    if (depth_ != 3) misplaced("a number");
    if (state_.count[field_]++ < field_size(model_, field_)) state_.x[field_].push_back(x);
    return true;
  }

  /// Checks the closed state: q, v, a and tau present where needed and of the model's lengths,
  /// free joints' quaternions of unit length, and ABA defined when tau is given.
  void complete() {
    const auto need = [&](Field f) {
      if (!state_.has(f)) fail(fmt::format("no \"{}\"", field_names[f]));
      field_ = f;
      if (state_.count[f] != field_size(model_, f)) fail(length_error(model_, f, state_.count[f]));
      field_ = no_field;
    };
    need(Q);
    check_quaternions();
    if (state_.has(A) || state_.has(Tau)) {
      need(V);
      if (state_.has(A)) need(A);
      if (state_.has(Tau)) need(Tau);
    } else if (state_.has(V)) {
      fail("\"v\" without \"a\" or \"tau\"");
    }
    if (state_.has(Tau) && !aba_checked_) {
      field_ = Tau;
      const std::string reason = aba_undefined_reason(model_);
      if (!reason.empty()) fail(reason + ", or give \"a\" instead of \"tau\"");
      aba_checked_ = true;
      field_ = no_field;
    }
  }

  void check_quaternions() const {
    for (int i = 0; i < model_.nbodies; ++i) {
      const JointType t = model_.joint_type[i];
      const int o = quaternion_offset(t);
      if (o < 0) continue;
      const int k = model_.q_index[i] + o;
      const double* w = &state_.x[Q][static_cast<std::size_t>(k)];
      const double norm = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2] + w[3] * w[3]);
      if (!(std::abs(norm - 1) <= 1e-6))
        throw InputError(fmt::format(
            "{}: state {}, field \"q\"[{}..{}]: the quaternion (w, x, y, z) of {} joint '{}' "
            "has length {:.17g}; it must be a unit quaternion",
            name_, index_, k, k + 3, t == JointType::Ball ? "ball" : "free",
            model_.joint_name[i], norm));
    }
  }

  const Model<double>& model_;
  const std::string& name_;
  Take take_;
  int depth_ = 0;
  std::size_t index_ = 0;  // of the state being read
  Field field_ = no_field;
  State state_;
  bool aba_checked_ = false;
};

/// An output of a state: its key, as dump(2) quotes it, and its `size` numbers, a list of rows
/// of `columns` or (columns 0) an array.
struct Output {
  const char* key;
  const double* x;
  std::size_t size, columns;
};

/// Computes each state's results and writes them as nlohmann::json's dump(2) would print the
/// whole tree, its keys in dump's order: M, Minv, Y, dlambda_dq, dlambda_dtau, dlambda_dv,
/// dqdd_dq, dqdd_dtau, dqdd_dv, dtau_dq, dtau_dv, frames, impulse, lambda, qdd, tau, v_plus. The
/// head is written with the first result, so that a bad first state leaves nothing written.
class ResultWriter {
 public:
  ResultWriter(const Model<double>& model, const std::string& name, std::FILE* out,
               const EvalOptions& options);
  void write(const State& state, std::size_t s);
  void finish();

 private:
  void compute(const State& state);
  std::vector<Output> frame_outputs(std::size_t f, bool with_v) const;
  void check_finite(const Output& output, std::size_t s, const std::string& frame = "") const;
  void put(std::string_view text);
  void put_key(std::string_view key, int indent, bool first);
  void put_output(const Output& output, int indent, bool first);
  void put_array(const double* x, std::size_t size, int indent);
  void start();

  const Model<double>& model_;
  const std::string& name_;
  std::FILE* out_;
  EvalOptions options_;
  std::size_t n_;
  Workspace<double> ws_;
  std::vector<double> tau_, qdd_, M_, Minv_, dtau_dq_, dtau_dv_, dqdd_dq_, dqdd_dv_, Y_, R_, p_, J_,
      Jdot_v_, lambda_, v_plus_, impulse_;
  // with --contacts: d qdd / d tau and d lambda / d(q, v, tau), nc x nv
  std::vector<double> dqdd_dtau_, dlambda_dq_, dlambda_dv_, dlambda_dtau_;
  std::vector<std::string> frame_keys_;   // python_text of each frame's name, quoted
  std::vector<std::size_t> frame_order_;  // the frames in their keys' order
  json row_ = json::array();  // put_array's, kept for its capacity
  std::string text_;          // likewise
  bool started_ = false;
};

ResultWriter::ResultWriter(const Model<double>& model, const std::string& name,
                           std::FILE* out, const EvalOptions& options)
    : model_(model), name_(name), out_(out), options_(options),
      n_(static_cast<std::size_t>(model.nv)), ws_(model) {
  if (options.derivatives) {
    if (model.nv > Workspace<double>::max_matrix_nv)
      throw InputError(fmt::format("--derivatives: the robot has {} degrees of freedom, above the "
                                   "runtime's {} for M^-1 and the derivatives of ABA",
                                   model.nv, Workspace<double>::max_matrix_nv));
    // M^-1 comes with every state
    if (const std::string reason = aba_undefined_reason(model); !reason.empty())
      throw InputError(reason + ", or leave out --derivatives (its \"Minv\" needs ABA's pivots)");
  }
  if (!options.frames) return;
  // names as the Python module reads them; two frames that read the same are refused, so no
  // frame's results overwrite another's
  for (const Frame<double>& frame : model.frames) frame_keys_.push_back(python_text(frame.name));
  frame_order_.resize(frame_keys_.size());
  std::iota(frame_order_.begin(), frame_order_.end(), std::size_t{0});
  std::sort(frame_order_.begin(), frame_order_.end(),
            [&](std::size_t i, std::size_t j) { return frame_keys_[i] < frame_keys_[j]; });
  for (std::size_t k = 1; k < frame_order_.size(); ++k)
    if (frame_keys_[frame_order_[k]] == frame_keys_[frame_order_[k - 1]])
      throw InputError(fmt::format("--frames: two frames are named '{}'",
                                   safe_text(frame_keys_[frame_order_[k]])));
  for (std::string& key : frame_keys_) key = json(key).dump();
  R_.resize(9 * frame_keys_.size());
  p_.resize(3 * frame_keys_.size());
  J_.resize(6 * frame_keys_.size() * n_);
  Jdot_v_.resize(6 * frame_keys_.size());
}

void ResultWriter::compute(const State& state) {
  const bool with_a = state.has(A), with_tau = state.has(Tau);
  const std::size_t nn = n_ * n_;
  tau_.assign(with_a ? n_ : 0, 0.0);
  qdd_.assign(with_tau ? n_ : 0, 0.0);
  M_.resize(nn);
  if (with_a) rnea<double>(model_, ws_, state.x[Q], state.x[V], state.x[A], tau_);
  lambda_.assign(with_tau ? static_cast<std::size_t>(model_.nc) : 0, 0.0);
  if (with_tau && model_.nc > 0)
    contact_dynamics<double>(model_, ws_, state.x[Q], state.x[V], state.x[Tau], qdd_, lambda_);
  else if (with_tau)
    aba<double>(model_, ws_, state.x[Q], state.x[V], state.x[Tau], qdd_);
  const bool impulses = model_.nc > 0 && state.has(V);
  v_plus_.assign(impulses ? n_ : 0, 0.0);
  impulse_.assign(impulses ? static_cast<std::size_t>(model_.nc) : 0, 0.0);
  if (impulses) impulse_dynamics<double>(model_, ws_, state.x[Q], state.x[V], v_plus_, impulse_);
  crba<double>(model_, ws_, state.x[Q], M_);
  if (options_.derivatives) {
    Minv_.resize(nn);
    dtau_dq_.assign(with_a ? nn : 0, 0.0);
    dtau_dv_.assign(with_a ? nn : 0, 0.0);
    dqdd_dq_.assign(with_tau ? nn : 0, 0.0);
    dqdd_dv_.assign(with_tau ? nn : 0, 0.0);
    const bool constrained = with_tau && model_.nc > 0;
    const std::size_t nc_nv = constrained ? static_cast<std::size_t>(model_.nc) * n_ : 0;
    dqdd_dtau_.assign(constrained ? nn : 0, 0.0);
    for (std::vector<double>* d : {&dlambda_dq_, &dlambda_dv_, &dlambda_dtau_})
      d->assign(nc_nv, 0.0);
    if (with_a)
      rnea_derivatives<double>(model_, ws_, state.x[Q], state.x[V], state.x[A], dtau_dq_,
                               dtau_dv_);
    if (constrained)
      contact_dynamics_derivatives<double>(model_, ws_, state.x[Q], state.x[V], state.x[Tau],
                                           dqdd_dq_, dqdd_dv_, dqdd_dtau_, dlambda_dq_,
                                           dlambda_dv_, dlambda_dtau_);
    else if (with_tau)
      aba_derivatives<double>(model_, ws_, state.x[Q], state.x[V], state.x[Tau], dqdd_dq_,
                              dqdd_dv_, Minv_);
    // "Minv" is minv's with or without tau: aba_derivatives' own, from M's factors, can
    // differ from it in the last bits
    minv<double>(model_, ws_, state.x[Q], Minv_);
  }
  Y_.assign(options_.regressor && with_a ? n_ * parameters_per_body * model_.nbodies : 0, 0.0);
  if (!Y_.empty()) regressor<double>(model_, ws_, state.x[Q], state.x[V], state.x[A], Y_);
  if (options_.frames) {
    frame_placements<double>(model_, ws_, state.x[Q], R_, p_);
    frame_jacobians<double>(model_, ws_, state.x[Q], JacobianAxes::World, J_);
    if (state.has(V))
      frame_bias_accelerations<double>(model_, ws_, state.x[Q], state.x[V], JacobianAxes::World,
                                       Jdot_v_);
  }
}

/// Frame f's J, Jdot_v (with v), R and p.
std::vector<Output> ResultWriter::frame_outputs(std::size_t f, bool with_v) const {
  std::vector<Output> out{Output{"\"J\"", J_.data() + 6 * f * n_, 6 * n_, n_}};
  if (with_v) out.push_back(Output{"\"Jdot_v\"", Jdot_v_.data() + 6 * f, 6, 0});
  out.push_back(Output{"\"R\"", R_.data() + 9 * f, 9, 3});
  out.push_back(Output{"\"p\"", p_.data() + 3 * f, 3, 0});
  return out;
}

void ResultWriter::check_finite(const Output& output, std::size_t s,
                                const std::string& frame) const {
  for (std::size_t k = 0; k < output.size; ++k) {
    if (std::isfinite(output.x[k])) continue;
    const std::string entry = output.columns == 0
                                  ? fmt::format("[{}]", k)
                                  : fmt::format("[{}][{}]", k / output.columns, k % output.columns);
    throw InputError(fmt::format("{}: state {}: {}{}{} is not finite ({}): the inputs overflow",
                                 name_, s, frame.empty() ? "" : "frame '" + frame + "': ",
                                 output.key, entry, output.x[k]));
  }
}

void ResultWriter::write(const State& state, std::size_t s) {
  compute(state);
  const auto matrix = [&](const char* key, const std::vector<double>& A) {
    return Output{key, A.data(), A.size(), n_};
  };
  std::vector<Output> matrices{matrix("\"M\"", M_)};
  if (options_.derivatives) matrices.push_back(matrix("\"Minv\"", Minv_));
  if (!Y_.empty())
    matrices.push_back({"\"Y\"", Y_.data(), Y_.size(),
                        static_cast<std::size_t>(parameters_per_body * model_.nbodies)});
  if (!dlambda_dq_.empty()) {
    matrices.push_back(matrix("\"dlambda_dq\"", dlambda_dq_));
    matrices.push_back(matrix("\"dlambda_dtau\"", dlambda_dtau_));
    matrices.push_back(matrix("\"dlambda_dv\"", dlambda_dv_));
  }
  if (options_.derivatives && state.has(Tau)) {
    matrices.push_back(matrix("\"dqdd_dq\"", dqdd_dq_));
    if (!dqdd_dtau_.empty()) matrices.push_back(matrix("\"dqdd_dtau\"", dqdd_dtau_));
    matrices.push_back(matrix("\"dqdd_dv\"", dqdd_dv_));
  }
  if (options_.derivatives && state.has(A)) {
    matrices.push_back(matrix("\"dtau_dq\"", dtau_dq_));
    matrices.push_back(matrix("\"dtau_dv\"", dtau_dv_));
  }
  std::vector<Output> vectors;
  const std::size_t nc = static_cast<std::size_t>(model_.nc);
  if (!impulse_.empty()) vectors.push_back({"\"impulse\"", impulse_.data(), nc, 0});
  if (!lambda_.empty()) vectors.push_back({"\"lambda\"", lambda_.data(), nc, 0});
  if (state.has(Tau)) vectors.push_back({"\"qdd\"", qdd_.data(), n_, 0});
  if (state.has(A)) vectors.push_back({"\"tau\"", tau_.data(), n_, 0});
  if (!v_plus_.empty()) vectors.push_back({"\"v_plus\"", v_plus_.data(), n_, 0});
  // every output is checked before any of the state's is written
  for (const Output& output : matrices) check_finite(output, s);
  for (const std::size_t f : frame_order_)
    for (const Output& output : frame_outputs(f, state.has(V)))
      check_finite(output, s, model_.frames[f].name);
  for (const Output& output : vectors) check_finite(output, s);

  if (!started_) start();
  put(s == 0 ? "\n    {" : ",\n    {");
  for (const Output& output : matrices) put_output(output, 6, &output == &matrices.front());
  if (options_.frames) {
    put_key("\"frames\"", 6, false);
    put(frame_order_.empty() ? "{}" : "{");
    for (const std::size_t f : frame_order_) {
      put_key(frame_keys_[f], 8, f == frame_order_.front());
      put("{");
      const std::vector<Output> outputs = frame_outputs(f, state.has(V));
      for (const Output& output : outputs) put_output(output, 10, &output == &outputs.front());
      put("\n        }");
    }
    if (!frame_order_.empty()) put("\n      }");
  }
  for (const Output& output : vectors) put_output(output, 6, false);
  put("\n    }");
}

void ResultWriter::start() {
  std::vector<std::string> joints;
  for (const std::string& name : velocity_names(model_)) joints.push_back(python_text(name));
  json fields{{"joints", joints}, {"nq", model_.nq}, {"nv", model_.nv}};
  if (model_.nc > 0) {
    std::vector<std::string> constraints;
    for (const Constraint<double>& c : model_.constraints)
      constraints.push_back(python_text(c.name));
    fields["constraints"] = constraints;
    fields["nc"] = model_.nc;
  }
  if (std::ranges::any_of(model_.armature, [](double a) { return a != 0; }))
    fields["armature"] = model_.armature;
  std::string head = fields.dump(2);
  head.resize(head.size() - 2);  // "\n}": the results follow
  put(head + ",\n  \"results\": [");
  started_ = true;
}

void ResultWriter::finish() {
  const bool empty = !started_;
  if (empty) start();
  put(empty ? "]\n}\n" : "\n  ]\n}\n");
  if (std::fflush(out_) != 0 || std::ferror(out_))
    throw FileError(fmt::format("cannot write the results to standard output: {}",
                                std::strerror(errno)));
}

/// Writes text, or throws FileError with the system's reason.
void ResultWriter::put(std::string_view text) {
  if (std::fwrite(text.data(), 1, text.size(), out_) != text.size())
    throw FileError(fmt::format("cannot write the results to standard output: {}",
                                std::strerror(errno)));
}

void ResultWriter::put_key(std::string_view key, int indent, bool first) {
  put(first ? "\n" : ",\n");
  put(std::string(static_cast<std::size_t>(indent), ' '));
  put(key);
  put(": ");
}

/// An output `indent` deep: an array, or a list of rows, each written as it is printed.
void ResultWriter::put_output(const Output& output, int indent, bool first) {
  put_key(output.key, indent, first);
  if (output.columns == 0) return put_array(output.x, output.size, indent);
  const std::size_t rows = output.size / output.columns;
  if (rows == 0) return put("[]");
  put("[");
  const std::string spaces(static_cast<std::size_t>(indent + 2), ' ');
  for (std::size_t i = 0; i < rows; ++i) {
    put(i == 0 ? "\n" : ",\n");
    put(spaces);
    put_array(&output.x[i * output.columns], output.columns, indent + 2);
  }
  put("\n");
  put(spaces.substr(2));
  put("]");
}

/// An array as dump(2) prints it `indent` deep: its lines after the first indented so much.
void ResultWriter::put_array(const double* x, std::size_t size, int indent) {
  row_.get_ref<json::array_t&>().assign(x, x + size);
  const std::string text = row_.dump(2);
  text_.clear();
  std::size_t from = 0;
  for (std::size_t at; (at = text.find('\n', from)) != std::string::npos; from = at + 1)
    text_.append(text, from, at + 1 - from).append(static_cast<std::size_t>(indent), ' ');
  put(text_.append(text, from));
}

}  // namespace

void evaluate(const Model<double>& model, std::istream& in, const std::string& name,
              std::FILE* out, const EvalOptions& options) {
  ResultWriter writer(model, name, out, options);
  StateReader reader(model, name, [&](const State& state, std::size_t s) {
    writer.write(state, s);
  });
  try {
    json::sax_parse(in, &reader);
  } catch (const std::ios_base::failure&) {  // libstdc++'s filebuf on a read error
    throw InputError(fmt::format("{}: cannot read: {}", name, std::strerror(errno)));
  }
  writer.finish();
}

void evaluate(const Model<double>& model, const std::string& path, std::FILE* out,
              const EvalOptions& options) {
  if (path == "-") return evaluate(model, std::cin, "<stdin>", out, options);
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(fmt::format("{}: cannot read the file: {}", path, std::strerror(errno)));
  evaluate(model, in, path, out, options);
}

}  // namespace dyngen::gen
