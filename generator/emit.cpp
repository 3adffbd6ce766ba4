#include "emit.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

namespace dyngen::gen {

std::string to_string(const OpCounts& c) {
  return fmt::format("add {}, mul {}, div {}, neg {}, sin {}, cos {}", c.add, c.mul, c.div, c.neg,
                     c.sin, c.cos);
}

namespace {

template <class T>
std::vector<bool> live_nodes(const Program<T>& program) {
  const auto& nodes = program.graph.nodes;
  std::vector<bool> live(nodes.size(), false);
  for (const int id : program.outputs) live[id] = true;
  for (int id = static_cast<int>(nodes.size()) - 1; id >= 0; --id) {
    if (!live[id]) continue;
    if (nodes[id].a >= 0) live[nodes[id].a] = true;
    if (nodes[id].b >= 0) live[nodes[id].b] = true;
  }
  return live;
}

void count(OpCounts& c, Op op) {
  switch (op) {
    case Op::Add:
    case Op::Sub: ++c.add; break;
    case Op::Mul: ++c.mul; break;
    case Op::Div: ++c.div; break;
    case Op::Neg: ++c.neg; break;
    case Op::Sin: ++c.sin; break;
    case Op::Cos: ++c.cos; break;
    case Op::Const:
    case Op::Input: break;
  }
}

template <class T>
std::string shortest(T value) {
  if (!std::isfinite(value))
    throw std::runtime_error(fmt::format("internal error: non-finite constant {} in the trace", value));
  std::string s = fmt::format("{}", value);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string sanitize(const std::string& name) {
  std::string s;
  for (const char ch : name) s += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) s = "b_" + s;
  return s;
}

template <class T>
std::string section_header(const Model<double>& model, int body, Pass pass) {
  if (body < 0) return fmt::format("    // ---- {}\n", pass_name(pass));
  const int p = model.parent[body];
  const std::string parent =
      p < 0 ? std::string("base") : fmt::format("'{}' ({})", model.body_name[p], p);
  return fmt::format("    // ---- link '{}' ({}) <- {}; joint '{}': {}; {}\n", model.body_name[body],
                     body, parent, model.joint_name[body], joint_description(model, body),
                     pass_name(pass));
}

}  // namespace

std::string literal(double value) {
  const std::string s = shortest(value);
  return std::signbit(value) ? "(" + s + ")" : s;
}

std::string literal(float value) {
  const std::string s = shortest(value) + "f";
  return std::signbit(value) ? "(" + s + ")" : s;
}

std::string joint_description(const Model<double>& model, int body) {
  const Vec3<double>& k = model.joint_axis[body];
  switch (model.joint_type[body]) {
    case JointType::RevoluteX: return k.x > 0 ? "revolute +x" : "revolute -x";
    case JointType::RevoluteY: return k.y > 0 ? "revolute +y" : "revolute -y";
    case JointType::RevoluteZ: return k.z > 0 ? "revolute +z" : "revolute -z";
    case JointType::Revolute: return fmt::format("revolute axis ({}, {}, {})", k.x, k.y, k.z);
    case JointType::Prismatic: return fmt::format("prismatic axis ({}, {}, {})", k.x, k.y, k.z);
    case JointType::Free: return "free (6 DoF)";
  }
  return "?";
}

template <class T>
OpCounts count_ops(const Program<T>& program, bool live_only) {
  const std::vector<bool> live = live_nodes(program);
  OpCounts c;
  for (std::size_t id = 0; id < program.graph.nodes.size(); ++id)
    if (live[id] || !live_only) count(c, program.graph.nodes[id].op);
  return c;
}

template <class T>
std::string emit_body(const Program<T>& program, const Model<double>& model) {
  const auto& nodes = program.graph.nodes;
  const std::vector<bool> live = live_nodes(program);
  const char* type = std::is_same_v<T, float> ? "float" : "double";

  // sin and cos of joint angles come precomputed in trig (joint_trig), so that one call of
  // dyngen::sincos serves every function that takes the same q
  auto is_trig = [&](const Node<T>& n) {
    if (n.op != Op::Sin && n.op != Op::Cos) return false;
    const Node<T>& x = nodes[n.a];
    if (x.op != Op::Input || program.graph.inputs[x.input].array != "q")
      throw std::logic_error("internal error: sin or cos of something other than a joint angle");
    return true;
  };
  std::vector<std::string> name(nodes.size());
  std::vector<int> per_body(model.nbodies + 1, 0);
  auto operand = [&](int id) -> std::string {
    const Node<T>& n = nodes[id];
    if (n.op == Op::Const) return literal(n.value);
    if (n.op == Op::Input) {
      const InputRef& in = program.graph.inputs[n.input];
      return fmt::format("{}[{}]", in.array, in.index);
    }
    if (is_trig(n))
      return fmt::format("trig.{}_q[{}]", n.op == Op::Sin ? "sin" : "cos",
                         program.graph.inputs[nodes[n.a].input].index);
    return name[id];
  };

  // the arrays that the emitted statements and output stores read
  std::map<std::string, bool> used;
  auto use = [&](int id) {
    const Node<T>& n = nodes[id];
    if (n.op == Op::Input)
      used[program.graph.inputs[n.input].array] = true;
    else if (is_trig(n))
      used["trig"] = true;
  };
  for (std::size_t id = 0; id < nodes.size(); ++id) {
    const Node<T>& n = nodes[id];
    if (!live[id] || n.op == Op::Const || n.op == Op::Input || is_trig(n)) continue;
    if (n.a >= 0) use(n.a);
    if (n.b >= 0) use(n.b);
  }
  for (const int id : program.outputs) use(id);

  std::string out;
  std::vector<std::string> arrays = program.input_arrays;
  const auto q = std::find(arrays.begin(), arrays.end(), "q");
  arrays.insert(q == arrays.end() ? q : q + 1, "trig");
  for (const std::string& array : arrays)
    if (!used[array])
      out += fmt::format("    static_cast<void>({});  // {}\n\n", array,
                         array == "q" && used["trig"] ? "read only through trig"
                                                      : "no output of this robot depends on it");
  int section_body = -2;
  Pass section_pass = Pass::Forward;
  for (std::size_t id = 0; id < nodes.size(); ++id) {
    const Node<T>& n = nodes[id];
    if (!live[id] || n.op == Op::Const || n.op == Op::Input || is_trig(n)) continue;
    if (n.body != section_body || n.pass != section_pass) {
      if (section_body != -2) out += "\n";
      out += section_header<T>(model, n.body, n.pass);
      section_body = n.body;
      section_pass = n.pass;
    }
    const std::string prefix = n.body < 0 ? std::string("t") : sanitize(model.body_name[n.body]);
    name[id] = fmt::format("{}_{}", prefix, per_body[n.body + 1]++);
    std::string expr;
    switch (n.op) {
      case Op::Neg: expr = "-" + operand(n.a); break;
      case Op::Add: expr = operand(n.a) + " + " + operand(n.b); break;
      case Op::Sub: expr = operand(n.a) + " - " + operand(n.b); break;
      case Op::Mul: expr = operand(n.a) + " * " + operand(n.b); break;
      case Op::Div: expr = operand(n.a) + " / " + operand(n.b); break;
      case Op::Sin:
      case Op::Cos:
      case Op::Const:
      case Op::Input: break;
    }
    out += fmt::format("    const {} {} = {};\n", type, name[id], expr);
  }
  if (section_body != -2) out += "\n";
  out += "    // ---- outputs\n";
  for (int k = 0; k < program.output_size; ++k)
    out += fmt::format("    {}[{}] = {};\n", program.output_array, k, operand(program.outputs[k]));
  return out;
}

std::string emit_joint_trig(const Model<double>& model) {
  std::vector<bool> revolute(model.nq, false);
  for (int i = 0; i < model.nbodies; ++i)
    if (is_revolute(model.joint_type[i])) revolute[model.q_index[i]] = true;
  // one array call per run of consecutive revolute entries, which the compiler can vectorise
  std::string out;
  for (int k = 0; k < model.nq;) {
    if (!revolute[k]) {
      ++k;
      continue;
    }
    int end = k;
    while (end < model.nq && revolute[end]) ++end;
    if (end - k == 1)
      out += fmt::format("    dyngen::sincos(q[{0}], trig.sin_q[{0}], trig.cos_q[{0}]);\n", k);
    else
      out += fmt::format(
          "    dyngen::sincos(q + {0}, trig.sin_q + {0}, trig.cos_q + {0}, {1});  // q[{0}..{2}]\n",
          k, end - k, end - 1);
    k = end;
  }
  if (out.empty())
    out = "    static_cast<void>(q);  // no revolute joint\n    static_cast<void>(trig);\n";
  return out;
}

template OpCounts count_ops<double>(const Program<double>&, bool);
template OpCounts count_ops<float>(const Program<float>&, bool);
template std::string emit_body<double>(const Program<double>&, const Model<double>&);
template std::string emit_body<float>(const Program<float>&, const Model<double>&);

}  // namespace dyngen::gen
