#include "emit.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "footprint.hpp"
#include "names.hpp"
#include "plan.hpp"

namespace dyngen::gen {

std::string wrapped_call(const std::string& function, const std::vector<std::string>& arguments,
                         const std::string& indent) {
  const std::string head = indent + function + "(";
  std::string text = head;
  std::size_t column = head.size();
  for (std::size_t k = 0; k < arguments.size(); ++k) {
    const std::string item = arguments[k] + (k + 1 < arguments.size() ? ", " : ");");
    if (column + item.size() > 100 && column > head.size()) {
      while (text.back() == ' ') text.pop_back();
      text.append("\n").append(head.size(), ' ');  // GCC 12's -Wrestrict misfires on "\n" + string
      column = head.size();
    }
    text += item;
    column += item.size();
  }
  return text + "\n";
}

std::string to_string(const OpCounts& c) {
  return fmt::format("add {}, mul {}, div {}, neg {}, sin {}, cos {}{}", c.add, c.mul, c.div, c.neg,
                     c.sin, c.cos, c.fn > 0 ? fmt::format(", fn {}", c.fn) : "");
}

namespace {

void count(OpCounts& c, Op op, long times = 1) {
  switch (op) {
    case Op::Add:
    case Op::Sub: c.add += times; break;
    case Op::Mul: c.mul += times; break;
    case Op::Div: c.div += times; break;
    case Op::Neg: c.neg += times; break;
    case Op::Sin: c.sin += times; break;
    case Op::Cos: c.cos += times; break;
    case Op::Fn: c.fn += times; break;
    case Op::Const:
    case Op::Input:
    case Op::Call:
    case Op::Result: break;
  }
}

OpCounts count_ops_of(const KernelRecord& call) {
  OpCounts c;
  for (std::size_t op = 0; op < op_kinds; ++op) count(c, static_cast<Op>(op), call.ops[op]);
  return c;
}

/// Adds node n's operations to c: a kernel call's are those of its loops.
template <class T>
void count_node(OpCounts& c, const Program<T>& program, const Node<T>& n) {
  count(c, n.op);
  if (n.op != Op::Call) return;
  const OpCounts k = count_ops_of(program.graph.calls[n.a]);
  c.add += k.add, c.mul += k.mul, c.div += k.div, c.neg += k.neg, c.sin += k.sin, c.cos += k.cos;
  c.fn += k.fn;
}

}  // namespace

template <class T>
OpCounts count_ops(const Program<T>& program, const std::vector<bool>& counted) {
  OpCounts c;
  for (std::size_t id = 0; id < program.graph.nodes.size(); ++id)
    if (counted[id]) count_node(c, program, program.graph.nodes[id]);
  return c;
}

namespace {

/// "{" then the items on lines of at most 100 columns indented by 8, then "}".
std::string braced_list(const std::vector<std::string>& items) {
  std::string text = "{", line;
  for (std::size_t k = 0; k < items.size(); ++k) {
    const std::string item = items[k] + (k + 1 < items.size() ? "," : "");
    if (line.empty() || line.size() + 1 + item.size() > 92) {
      text += line.empty() ? "" : line;
      text += "\n        ";
      line = item;
    } else {
      line += " " + item;
    }
  }
  return text + line + "}";
}


template <class T>
std::string shortest(T value) {
  if (!std::isfinite(value))
    throw std::runtime_error(fmt::format("internal error: non-finite constant {} in the trace", value));
  std::string s = fmt::format("{}", value);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

/// The prefix of each body's temporaries (`upper_arm` for upper_arm_7), "t" for those of no
/// body: identifiers of at most 32 characters, distinct for distinct bodies ("link-1" and
/// "link_1", "α" and "β"), so that no two temporaries share a name.
std::vector<std::string> temporary_prefixes(const Model<double>& model) {
  std::set<std::string> taken{"t"};
  std::vector<std::string> prefixes{"t"};
  for (int i = 0; i < model.nbodies; ++i) {
    std::string prefix;
    for (const char ch : model.body_name[i]) {
      const unsigned char c = static_cast<unsigned char>(ch);
      if (c < 0x80 && std::isalnum(c)) prefix += ch;
      else if (!prefix.empty() && prefix.back() != '_') prefix += '_';
    }
    while (!prefix.empty() && prefix.back() == '_') prefix.pop_back();
    if (prefix.size() > 32) prefix.resize(32);
    if (prefix.empty() || std::isdigit(static_cast<unsigned char>(prefix[0])))
      prefix = "link" + prefix;
    for (int k = 0; !taken.insert(prefix).second; ++k) prefix = fmt::format("link{}_{}", i, k);
    prefixes.push_back(prefix);
  }
  return prefixes;
}

template <class T>
std::string section_header(const Model<double>& model, int body, Pass pass) {
  if (body < 0) return fmt::format("    // ---- {}\n", pass_name(pass));
  const int p = model.parent[body];
  const std::string parent =
      p < 0 ? std::string("base") : fmt::format("'{}' ({})", safe_text(model.body_name[p]), p);
  return fmt::format("    // ---- link '{}' ({}) <- {}; joint '{}': {}; {}\n",
                     safe_text(model.body_name[body]), body, parent,
                     safe_text(model.joint_name[body]), joint_description(model, body),
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
    case JointType::Ball: return "ball (3 DoF)";
  }
  return "?";
}

template <class T>
OpCounts count_ops(const Program<T>& program, bool live_only) {
  return count_ops(program, live_only ? live_nodes(program)
                                         : std::vector<bool>(program.graph.nodes.size(), true));
}

template <class T>
std::map<Pass, OpCounts> count_ops_by_pass(const Program<T>& program) {
  const std::vector<bool> live = live_nodes(program);
  std::map<Pass, OpCounts> by_pass;
  for (std::size_t id = 0; id < program.graph.nodes.size(); ++id) {
    const Node<T>& n = program.graph.nodes[id];
    if (live[id]) count_node(by_pass[n.pass], program, n);
  }
  return by_pass;
}

namespace {

std::string body_label(const Model<double>& model, int body) {
  return fmt::format("'{}' ({})", safe_text(model.body_name[body]), body);
}

/// Runs of at least this many +0 entries of an output are stored by a loop (one line where the
/// stores would be as many).
inline constexpr std::size_t min_zero_run = 8;

/// The stores of the outputs that no kernel wrote in place (operand(id): a node's value as
/// code). Exact zeros are not stored one by one (a frame's Jacobian columns of the joints off
/// its path): an array at least half of whose entries are +0 is first zero-filled by one loop,
/// then gets its other entries; otherwise each run of min_zero_run or more is a loop. Compilers
/// make these loops vector stores (and call no memset under -ffreestanding).
template <class T>
std::string output_stores(const Program<T>& program, const Model<double>& model,
                          const Dialect& dialect, const std::vector<bool>& output_in_place,
                          const std::function<std::string(int)>& operand) {
  std::string out = "    // ---- outputs\n";
  std::size_t stored = 0;
  for (std::size_t a = 0; a < program.outputs.size(); ++a) {
    const ProgramArray& array = program.outputs[a];
    const std::string_view name = array.spec.name;
    const int* entry = program.stored.data() + stored;
    stored += array.size;
    if (output_in_place[a]) {
      out += fmt::format("    // {}: written by the kernel\n", name);
      continue;
    }
    auto is_zero = [&](std::size_t k) {
      const Node<T>& n = program.graph.nodes[entry[k]];
      return n.op == Op::Const && n.value == T(0) && !std::signbit(n.value);
    };
    // entries [begin, end) set to 0 (batch arrays hold `lanes` numbers per entry)
    auto zero_loop = [&](std::size_t begin, std::size_t end, const std::string& comment) {
      return fmt::format("    for (int k = {}; k < {}; ++k) {}[k] = {};{}\n", dialect.entry(begin),
                         dialect.entry(end), name, literal(T(0)), comment);
    };
    std::size_t zeros = 0;
    for (std::size_t k = 0; k < array.size; ++k) zeros += is_zero(k);
    const bool fill = 2 * zeros >= array.size && zeros >= min_zero_run;
    if (fill)
      out += zero_loop(0, array.size,
                       fmt::format("  // {} of its {} entries are 0", zeros, array.size));
    // an array with a block per frame says whose block begins; zero runs end there
    const std::size_t block = array.spec.extent.per_frame && !model.frames.empty()
                                  ? array.size / model.frames.size()
                                  : array.size;
    for (std::size_t k = 0; k < array.size;) {
      if (block < array.size && k % block == 0)
        out += fmt::format("    // frame '{}'\n", safe_text(model.frames[k / block].name));
      std::size_t end = k;
      while (!fill && end < array.size && is_zero(end) && (end == k || end % block != 0)) ++end;
      if (end - k >= min_zero_run) {
        out += zero_loop(k, end, "");
        k = end;
        continue;
      }
      if (!(fill && is_zero(k))) out += dialect.store(name, k, operand(entry[k]));
      ++k;
    }
  }
  return out;
}

/// Prints a planned program as the body of a function and the shared functions it calls: one
/// statement per operation, grouped and labelled by body and pass. Each computed value is named
/// once, when its statement is printed, and operands are read by those names.
template <class T>
class CodePrinter {
 public:
  CodePrinter(const Program<T>& program, const Model<double>& model, const Dialect& dialect,
              CodePlan plan)
      : program_(program),
        nodes_(program.graph.nodes),
        model_(model),
        dialect_(dialect),
        plan_(std::move(plan)),
        scalar_(std::is_same_v<T, float> ? "float" : "double"),
        type_(dialect.value_type(scalar_)),
        name_(nodes_.size()),
        per_body_(model.nbodies + 1, 0),
        prefixes_(temporary_prefixes(model)) {}

  EmittedCode print();

 private:
  std::string operand(int id) const;
  std::string element(int id) const;
  int trig_index(int id) const;
  template <class Arg>
  std::string expression(const Node<T>& n, Arg&& arg) const;
  std::string shared_function(std::size_t g) const;
  std::string prologue() const;
  std::string kernel_call(int c);
  std::string statement(int id);
  std::string lanes_body();
  std::string lane_block(const LaneBlock& block, std::vector<std::string>& vector_name);
  std::string sections_body();

  const Program<T>& program_;
  const std::vector<Node<T>>& nodes_;
  const Model<double>& model_;
  const Dialect& dialect_;
  CodePlan plan_;
  const std::string scalar_;
  const std::string type_;  // of each computed value: the scalar, or a batch's lane
  std::vector<std::string> name_;  // by node: its value as code, once printed
  std::vector<int> per_body_;      // temporaries named so far, by body + 1
  const std::vector<std::string> prefixes_;
  std::map<std::vector<int>, std::string> gathered_;  // kernel inputs gathered into arrays
  EmittedCode code_;
};

std::string apply(Op op, const std::string& a, const std::string& b) {
  switch (op) {
    case Op::Neg: return "-" + a;
    case Op::Add: return a + " + " + b;
    case Op::Sub: return a + " - " + b;
    case Op::Mul: return a + " * " + b;
    case Op::Div: return a + " / " + b;
    default: return std::string();
  }
}

template <class T>
template <class Arg>
std::string CodePrinter<T>::expression(const Node<T>& n, Arg&& arg) const {
  if (n.op == Op::Fn) {
    const std::string name = std::string(info(static_cast<Function>(n.input)).name) +
                             (std::is_same_v<T, float> ? "f" : "");
    std::vector<std::string> arguments{arg(n.a)};
    if (n.b >= 0) arguments.push_back(arg(n.b));
    return dialect_.function_call(name, arguments);
  }
  return apply(n.op, arg(n.a), n.b >= 0 ? arg(n.b) : std::string());
}

template <class T>
std::string CodePrinter<T>::operand(int id) const {
  const Node<T>& n = nodes_[id];
  if (n.op == Op::Const) return literal(n.value);
  if (n.op == Op::Input) {
    const InputRef& in = program_.graph.inputs[n.input];
    return dialect_.input(in.array, in.index);
  }
  if (plan_.trig[id]) return dialect_.trig_value(n.op == Op::Sin ? "sin" : "cos", trig_index(id));
  if (n.op == Op::Result) {  // entry n.input of the results of the call that node n.a made
    const int c = nodes_[n.a].a;
    std::size_t index = static_cast<std::size_t>(n.input);
    std::size_t j = 0;
    while (index >= program_.graph.calls[c].outputs[j])
      index -= program_.graph.calls[c].outputs[j++];
    return fmt::format("{}[{}]", plan_.call_arrays[c][j], index);
  }
  return name_[id];
}

/// An element of an array of values (in batch code a constant fills every lane).
template <class T>
std::string CodePrinter<T>::element(int id) const {
  return nodes_[id].op == Op::Const ? dialect_.element(operand(id)) : operand(id);
}

/// The trig's entry that trig node id reads: its angle's index in q, or nq + j for the j-th
/// mimic joint's own angle (Program::mimic_angles).
template <class T>
int CodePrinter<T>::trig_index(int id) const {
  const Node<T>& x = nodes_[nodes_[id].a];
  if (x.op == Op::Input) return program_.graph.inputs[x.input].index;
  const std::vector<int>& angles = program_.mimic_angles;
  return model_.nq +
         static_cast<int>(std::find(angles.begin(), angles.end(), nodes_[id].a) - angles.begin());
}

/// Shared function g, with its table of each section's constants.
template <class T>
std::string CodePrinter<T>::shared_function(std::size_t g) const {
  const std::vector<int>& members = plan_.groups[g];
  const Section& first = plan_.sections[members.front()];
  const std::string fn = fmt::format("{}_shape_{}", program_.algorithm, g);
  std::string users;
  for (std::size_t k = 0; k < members.size() && k < 6; ++k)
    users += (k ? ", " : "") + body_label(model_, plan_.sections[members[k]].body);
  if (members.size() > 6) users += fmt::format(" and {} more", members.size() - 6);
  std::string text =
      fmt::format("// {}: {} operations, {} inputs, {} outputs; {}, {} sections: {}\n", fn,
                  first.ops.size(), first.inputs.size(), first.outputs.size(),
                  pass_name(first.pass), members.size(), users);
  const std::size_t nk = first.constants.size();
  if (nk > 0) {
    text += fmt::format("{} {} {}_k[{}][{}] = {{\n", dialect_.table(), scalar_, fn, members.size(),
                        nk);
    for (const int member : members) {
      std::string row;
      for (const int c : plan_.sections[member].constants)
        row += (row.empty() ? "" : ", ") + literal(nodes_[c].value);
      text += fmt::format("    {{{}}},\n", row);
    }
    text += "};\n";
  }
  text += fmt::format("DYNGEN_DISPATCH\nstatic void {}({}const {} x[{}], {} y[{}]){}\n{{\n", fn,
                      nk > 0 ? fmt::format("const {} k[{}], ", scalar_, nk) : "", type_,
                      first.inputs.size(), type_, first.outputs.size(), dialect_.no_throw());
  std::map<int, std::string> local;
  for (std::size_t k = 0; k < first.inputs.size(); ++k)
    local[first.inputs[k]] = fmt::format("x[{}]", k);
  for (std::size_t k = 0; k < first.constants.size(); ++k)
    local[first.constants[k]] = fmt::format("k[{}]", k);
  for (std::size_t k = 0; k < first.ops.size(); ++k) {
    text += fmt::format("    const {} t{} = {};\n", type_, k,
                        expression(nodes_[first.ops[k]], [&](int id) { return local.at(id); }));
    local[first.ops[k]] = fmt::format("t{}", k);
  }
  for (std::size_t k = 0; k < first.outputs.size(); ++k)
    text += fmt::format("    y[{}] = {};\n", k, local.at(first.outputs[k]));
  return text + "}\n\n";
}

/// What the body does before its statements: discards the arrays that no output reads, reads
/// the inputs and trig in the dialect's way (batch code loads them into lanes), and declares
/// the shared functions' outputs.
template <class T>
std::string CodePrinter<T>::prologue() const {
  std::map<std::string, bool> used;
  std::set<int> reads;  // the input and trig nodes read
  auto use = [&](int id) {
    const Node<T>& n = nodes_[id];
    if (n.op == Op::Input)
      used[program_.graph.inputs[n.input].array] = true;
    else if (plan_.trig[id])
      used["trig"] = true;
    else
      return;
    reads.insert(id);
  };
  for (std::size_t id = 0; id < nodes_.size(); ++id)
    if (plan_.is_op[id]) program_.graph.for_each_operand(static_cast<int>(id), use);
  for (const int id : program_.stored) use(id);

  std::string out;
  std::vector<std::string> arrays;
  for (const ProgramArray& a : program_.inputs) arrays.emplace_back(a.spec.name);
  const auto q = std::find(arrays.begin(), arrays.end(), "q");
  arrays.insert(q == arrays.end() ? q : q + 1, "trig");
  for (const std::string& array : arrays)
    if (!used[array])
      out += fmt::format("    {};  // {}\n\n", dialect_.discard(array),
                         array == "q" && used["trig"] ? "read only through trig"
                                                      : "no output of this robot depends on it");
  std::vector<Dialect::Read> read;
  for (const int id : reads) {
    const Node<T>& n = nodes_[id];
    if (n.op == Op::Input) {
      const InputRef& in = program_.graph.inputs[n.input];
      read.push_back({operand(id), in.array, in.index});
    } else {
      read.push_back(
          {operand(id),
           fmt::format("{}{}_q", dialect_.trig_member(), n.op == Op::Sin ? "sin" : "cos"),
           trig_index(id)});
    }
  }
  out += dialect_.load(read);
  if (plan_.w_size > 0)
    out += fmt::format(
        "    {} w[{}];  // the outputs of the sections that shared functions compute\n\n", type_,
        plan_.w_size);
  return out;
}

/// A kernel call: its tables, the arrays it reads (an array another call wrote is passed as it
/// is, the same entries gathered once), the arrays it writes, and the call.
template <class T>
std::string CodePrinter<T>::kernel_call(int c) {
  const std::vector<KernelRecord>& calls = program_.graph.calls;
  const KernelRecord& call = calls[c];
  std::string text = fmt::format("    // dyngen_kernels::{}: {}\n", call.kernel,
                                 to_string(count_ops_of(call)));
  std::vector<std::string> arguments;
  for (const int x : call.ints) arguments.push_back(std::to_string(x));
  for (std::size_t t = 0; t < call.tables.size(); ++t) {
    std::vector<std::string> items;
    for (const int x : call.tables[t]) items.push_back(std::to_string(x));
    const std::string table = fmt::format("{}_{}_{}", call.kernel, c, call.names[t]);
    text += fmt::format("    static constexpr int {}[] = {};\n", table, braced_list(items));
    arguments.push_back(table);
  }
  for (std::size_t j = 0; j < call.inputs.size(); ++j) {
    const std::vector<int>& ids = call.inputs[j];
    std::string array;
    for (std::size_t d = 0; d < calls.size() && array.empty(); ++d) {
      int first = calls[d].first_result;
      for (std::size_t k = 0; k < calls[d].outputs.size(); ++k) {
        bool same = calls[d].outputs[k] == ids.size();
        for (std::size_t e = 0; same && e < ids.size(); ++e)
          same = ids[e] == first + static_cast<int>(e);
        if (same) array = plan_.call_arrays[d][k];
        first += static_cast<int>(calls[d].outputs[k]);
      }
    }
    if (array.empty()) {
      const auto [it, added] = gathered_.emplace(
          ids, fmt::format("{}_{}_{}", call.kernel, c, call.names[call.tables.size() + j]));
      if (added) {
        std::vector<std::string> items;
        for (const int id : ids) items.push_back(element(id));
        text += fmt::format("    const {} {}[{}] = {};\n", type_, it->second, ids.size(),
                            braced_list(items));
      }
      array = it->second;
    }
    arguments.push_back(array);
  }
  for (std::size_t j = 0; j < call.outputs.size(); ++j) {
    const std::string& array = plan_.call_arrays[c][j];
    if (!plan_.call_in_place[c][j])
      text += fmt::format("    {} {}[{}];\n", type_, array, call.outputs[j]);
    arguments.push_back(array);
  }
  return text + dialect_.kernel_call(call, std::move(arguments),
                                     fmt::format("dyngen_kernels::{}", call.kernel), scalar_);
}

/// The statement of node id, which names its value.
template <class T>
std::string CodePrinter<T>::statement(int id) {
  const Node<T>& n = nodes_[id];
  if (n.op == Op::Call) return kernel_call(n.a);
  name_[id] = fmt::format("{}_{}", prefixes_[n.body + 1], per_body_[n.body + 1]++);
  return fmt::format("    const {} {} = {};\n", type_, name_[id],
                     expression(n, [this](int x) { return operand(x); }));
}

/// A lane block: a vector statement for each operation its lanes share (vector_name: by node,
/// the vector statement that computed it).
template <class T>
std::string CodePrinter<T>::lane_block(const LaneBlock& block,
                                       std::vector<std::string>& vector_name) {
  const std::vector<Section>& sections = plan_.sections;
  const std::size_t width = block.members.size();
  const std::string vector = fmt::format("lanes{}", width);
  std::string out = fmt::format("    // ---- {} lanes; {}:\n", width,
                                pass_name(sections[block.members[0]].pass));
  for (const int member : block.members) {
    const int body = sections[member].body;
    out += fmt::format("    //      link {}, joint '{}': {}\n", body_label(model_, body),
                       safe_text(model_.joint_name[body]), joint_description(model_, body));
  }
  const int body = sections[block.members[0]].body;
  for (std::size_t k = 0; k < block.in_lanes.size(); ++k) {
    if (!block.in_lanes[k]) continue;
    auto at = [&](std::size_t l) { return sections[block.members[l]].ops[k]; };
    // an operand: a block's vector where lane l reads lane l of it, else its lanes filled
    auto lanes_of = [&](bool second) {
      const std::vector<int> x = lane_operands(program_, sections, block, k, second);
      if (whole_vector(x, plan_.blocks, plan_.slot)) return vector_name[x[0]];
      std::string items;
      for (std::size_t l = 0; l < width; ++l) items += (l ? ", " : "") + operand(x[l]);
      return vector + "{" + items + "}";
    };
    const Node<T>& n = nodes_[at(0)];
    const std::string v = fmt::format("{}_l{}", prefixes_[body + 1], per_body_[body + 1]++);
    out += fmt::format("    const {} {} = {};\n", vector, v,
                       apply(n.op, lanes_of(false), n.b >= 0 ? lanes_of(true) : std::string()));
    for (std::size_t l = 0; l < width; ++l) {
      vector_name[at(l)] = v;
      name_[at(l)] = fmt::format("{}[{}]", v, l);
    }
    code_.lane_operations += static_cast<long>(width);
  }
  ++code_.lane_blocks;
  return out;
}

/// The statements in lanes: the vector types, then sections and lane blocks in their scheduled
/// order.
template <class T>
std::string CodePrinter<T>::lanes_body() {
  const std::vector<Section>& sections = plan_.sections;
  std::string out;
  std::vector<int> section_of(nodes_.size(), -1);
  for (std::size_t s = 0; s < sections.size(); ++s)
    for (const int id : sections[s].ops) section_of[id] = static_cast<int>(s);
  std::vector<std::string> vector_name(nodes_.size());
  std::set<std::size_t> widths;
  for (const LaneBlock& block : plan_.blocks) widths.insert(block.members.size());
  for (const std::size_t width : widths)
    out += fmt::format(
        "    typedef {0} lanes{1} __attribute__((vector_size({1} * sizeof({0}))));\n", scalar_,
        width);
  if (!widths.empty()) out += "\n";
  int current = -1;  // the section whose header was printed last; -2 a block
  for (const int unit : plan_.order) {
    if (unit >= 0) {
      const int s = section_of[unit];
      if (s != current) {
        if (current != -1) out += "\n";
        out += section_header<T>(model_, sections[s].body, sections[s].pass);
      }
      current = s;
      out += statement(unit);
      continue;
    }
    if (current != -1) out += "\n";
    current = -2;
    out += lane_block(plan_.blocks[static_cast<std::size_t>(-1 - unit)], vector_name);
  }
  return out + "\n";
}

/// The statements section by section, each in place or as a call of its shared function.
template <class T>
std::string CodePrinter<T>::sections_body() {
  std::string out;
  for (const Section& s : plan_.sections) {
    out += section_header<T>(model_, s.body, s.pass);
    if (s.group >= 0) {
      std::string x;
      for (const int id : s.inputs) x += (x.empty() ? "" : ", ") + element(id);
      const std::string k =
          s.constants.empty()
              ? std::string()
              : fmt::format("{}_shape_{}_k[{}], ", program_.algorithm, s.group, s.instance);
      out += fmt::format("    {{\n        const {} x[] = {{{}}};\n", type_, x);
      out += fmt::format("        {}_shape_{}({}x, w + {});\n    }}\n\n", program_.algorithm,
                         s.group, k, s.w);
      continue;
    }
    for (const int id : s.ops) out += statement(id);
    out += "\n";
  }
  return out;
}

template <class T>
EmittedCode CodePrinter<T>::print() {
  code_.angles.assign(static_cast<std::size_t>(trig_entries(model_)), false);
  for (std::size_t id = 0; id < nodes_.size(); ++id)
    if (plan_.trig[id])
      code_.angles[static_cast<std::size_t>(trig_index(static_cast<int>(id)))] = true;
  code_.sections = static_cast<int>(plan_.sections.size());
  code_.shared_functions = static_cast<int>(plan_.groups.size());
  for (const Section& s : plan_.sections) {
    if (s.group < 0) continue;
    ++code_.shared_sections;
    for (std::size_t k = 0; k < s.outputs.size(); ++k)
      name_[s.outputs[k]] = fmt::format("w[{}]", s.w + static_cast<int>(k));
  }
  for (std::size_t g = 0; g < plan_.groups.size(); ++g) code_.helpers += shared_function(g);
  code_.body = prologue();
  code_.body += plan_.lanes ? lanes_body() : sections_body();
  code_.body += output_stores(program_, model_, dialect_, plan_.output_in_place,
                              [this](int id) { return operand(id); });
  return std::move(code_);
}

}  // namespace

template <class T>
EmittedCode emit_code(const Program<T>& program, const Model<double>& model, Structure structure,
                      const Dialect& dialect) {
  return CodePrinter<T>(program, model, dialect, plan_code(program, model, structure, dialect))
      .print();
}

int trig_entries(const Model<double>& model) {
  return model.nq + static_cast<int>(own_angle_mimics(model).size());
}

namespace {

/// The trig's entries that joint_trig fills: the revolute joints' angles in q, and the mimic
/// joints' own angles after them.
std::vector<bool> revolute_angles(const Model<double>& model) {
  std::vector<bool> revolute(static_cast<std::size_t>(trig_entries(model)), false);
  for (int i = 0; i < model.nbodies; ++i)
    if (is_revolute(model.joint_type[i]) && !has_own_angle(model, i))
      revolute[model.q_index[i]] = true;
  std::fill(revolute.begin() + model.nq, revolute.end(), true);
  return revolute;
}

/// Mimic joint i's own angle as the runtime computes it in T (joint_position), traced as the
/// functions are, with the same simplifications, and printed with q_entry(k) for q[k].
template <class T>
std::string mimic_angle_text(const Model<double>& model, int i,
                             const std::function<std::string(int)>& q_entry) {
  Graph<T> g(true);
  const Recording<T> recording(g);
  const Model<Sym<T>> m = model.cast<T>().template cast<Sym<T>>();
  const int angle = joint_position(m, i, Sym<T>::node(g.input("q", m.q_index[i]))).id;
  const std::function<std::string(int)> print = [&](int id) -> std::string {
    const Node<T>& n = g.nodes[id];
    switch (n.op) {
      case Op::Const: return literal(n.value);
      case Op::Input: return q_entry(g.inputs[n.input].index);
      case Op::Neg: return "-" + print(n.a);
      case Op::Add: return "(" + print(n.a) + " + " + print(n.b) + ")";
      case Op::Sub: return "(" + print(n.a) + " - " + print(n.b) + ")";
      case Op::Mul: return "(" + print(n.a) + " * " + print(n.b) + ")";
      default: throw std::logic_error("internal error: a mimic angle of other operations");
    }
  };
  const std::string text = print(angle);
  const Op top = g.nodes[angle].op;
  return top == Op::Add || top == Op::Sub || top == Op::Mul ? text.substr(1, text.size() - 2)
                                                            : text;  // without the outer (...)
}

/// dyngen_sincos calls for the marked trig entries into `trig` (the trig's name and member
/// access, "trig." or "trig->"): one array call per run of consecutive angles of q, which the
/// compiler can vectorise, and one call per mimic joint's own angle.
std::string sincos_calls(const Model<double>& model, const std::vector<bool>& marked,
                         bool single_precision, const std::string& trig, const Dialect& dialect) {
  const char* sincos = single_precision ? "dyngen_sincosf" : "dyngen_sincos";
  const int nq = model.nq;
  std::string out;
  for (int k = 0; k < nq;) {
    if (!marked[k]) {
      ++k;
      continue;
    }
    int end = k;
    while (end < nq && marked[end]) ++end;
    out += dialect.sincos_run(k, end - k, sincos, trig);
    k = end;
  }
  const std::vector<int> mimics = own_angle_mimics(model);
  const auto q_entry = [&](int k) { return dialect.q_entry(k); };
  for (std::size_t j = 0; j < mimics.size(); ++j) {
    if (!marked[nq + j]) continue;
    const int i = mimics[j];
    const std::string angle = single_precision ? mimic_angle_text<float>(model, i, q_entry)
                                               : mimic_angle_text<double>(model, i, q_entry);
    out += dialect.sincos_angle(nq + static_cast<int>(j), angle, sincos, trig,
                                "mimic joint " + safe_text(model.joint_name[i]));
  }
  return out;
}

}  // namespace

std::string Dialect::trig_value(const char* function, int index) const {
  return fmt::format("{}{}_q[{}]", trig_member(), function, index);
}

std::string Dialect::store(std::string_view array, std::size_t k, const std::string& value) const {
  return fmt::format("    {}[{}] = {};\n", array, k, value);
}

std::string Dialect::kernel_call(const KernelRecord& /*call*/, std::vector<std::string> arguments,
                                 const std::string& kernel, const std::string& /*scalar*/) const {
  return wrapped_call(kernel, arguments);
}

std::string Dialect::sincos_angle(int k, const std::string& angle, const char* sincos,
                                  const std::string& trig, const std::string& what) const {
  return fmt::format("    {}({}, &{}sin_q[{}], &{}cos_q[{}]);  // {}\n", sincos, angle, trig, k,
                     trig, k, what);
}

std::string Dialect::sincos_run(int first, int count, const char* sincos,
                                const std::string& trig) const {
  if (count == 1) return fmt::format("    {1}(q[{0}], &{2}sin_q[{0}], &{2}cos_q[{0}]);\n", first, sincos, trig);
  return fmt::format("    {3}_array(q + {0}, {4}sin_q + {0}, {4}cos_q + {0}, {1});  // q[{0}..{2}]\n",
                     first, count, first + count - 1, sincos, trig);
}

const std::vector<std::string>& Dialect::compiler(const Toolchain& toolchain) const {
  return toolchain.cxx;
}

std::string emit_joint_trig(const Model<double>& model, bool single_precision,
                            const Dialect& dialect) {
  const std::string out =
      sincos_calls(model, revolute_angles(model), single_precision, dialect.trig_member(), dialect);
  if (out.empty())
    return fmt::format("    {};  // no revolute joint\n    {};\n", dialect.discard("q"),
                       dialect.discard("trig"));
  return out;
}

std::string emit_trig_fill(const Model<double>& model, bool single_precision,
                           const std::vector<bool>& angles, const Dialect& dialect) {
  if (std::find(angles.begin(), angles.end(), true) == angles.end())
    return fmt::format("    {}  // no angle is read\n", dialect.zero_trig());
  const std::string declared = fmt::format("    {} trig;\n", dialect.trig_type());
  if (angles == revolute_angles(model))
    return fmt::format("{}    {}(q, {});\n", declared, dialect.joint_trig(),
                       dialect.trig_argument());
  std::string out = declared + "    // the angles this function reads\n";
  return out.append(sincos_calls(model, angles, single_precision, "trig.", dialect));
}

template OpCounts count_ops<double>(const Program<double>&, bool);
template OpCounts count_ops<double>(const Program<double>&, const std::vector<bool>&);
template OpCounts count_ops<float>(const Program<float>&, const std::vector<bool>&);
template OpCounts count_ops<float>(const Program<float>&, bool);
template std::map<Pass, OpCounts> count_ops_by_pass<double>(const Program<double>&);
template std::map<Pass, OpCounts> count_ops_by_pass<float>(const Program<float>&);
template EmittedCode emit_code<double>(const Program<double>&, const Model<double>&, Structure,
                                       const Dialect&);
template EmittedCode emit_code<float>(const Program<float>&, const Model<double>&, Structure,
                                      const Dialect&);

}  // namespace dyngen::gen
