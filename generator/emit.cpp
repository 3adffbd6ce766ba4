#include "emit.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "names.hpp"

namespace dyngen::gen {

std::string to_string(const OpCounts& c) {
  return fmt::format("add {}, mul {}, div {}, neg {}, sin {}, cos {}", c.add, c.mul, c.div, c.neg,
                     c.sin, c.cos);
}

namespace {

template <class T>
std::vector<bool> live_nodes(const Program<T>& program) {
  const Graph<T>& g = program.graph;
  std::vector<bool> live(g.nodes.size(), false);
  for (const int id : program.stored) live[id] = true;
  for (int id = static_cast<int>(g.nodes.size()) - 1; id >= 0; --id)
    if (live[id]) g.for_each_operand(id, [&](int x) { live[x] = true; });
  return live;
}

void count(OpCounts& c, Op op, long times = 1) {
  switch (op) {
    case Op::Add:
    case Op::Sub: c.add += times; break;
    case Op::Mul: c.mul += times; break;
    case Op::Div: c.div += times; break;
    case Op::Neg: c.neg += times; break;
    case Op::Sin: c.sin += times; break;
    case Op::Cos: c.cos += times; break;
    case Op::Const:
    case Op::Input:
    case Op::Call:
    case Op::Result: break;
  }
}

/// "    f(a, b, ...);" (indent first) with the arguments wrapped before 100 columns under the
/// first.
std::string wrapped_call(const std::string& function, const std::vector<std::string>& arguments,
                         const std::string& indent = "    ") {
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

OpCounts count_ops_of(const KernelRecord& call) {
  OpCounts c;
  for (std::size_t op = 0; op < op_kinds; ++op) count(c, static_cast<Op>(op), call.ops[op]);
  return c;
}

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
  }
  return "?";
}

template <class T>
OpCounts count_ops(const Program<T>& program, bool live_only) {
  const std::vector<bool> live = live_nodes(program);
  OpCounts c;
  for (std::size_t id = 0; id < program.graph.nodes.size(); ++id) {
    if (!live[id] && live_only) continue;
    const Node<T>& n = program.graph.nodes[id];
    count(c, n.op);
    if (n.op == Op::Call) {
      const OpCounts k = count_ops_of(program.graph.calls[n.a]);
      c.add += k.add, c.mul += k.mul, c.div += k.div, c.neg += k.neg, c.sin += k.sin, c.cos += k.cos;
    }
  }
  return c;
}

namespace {

/// A maximal run of operations that the trace recorded for one body and pass.
struct Section {
  int body;
  Pass pass;
  std::vector<int> ops;        // node ids, in the trace's order
  std::vector<int> inputs;     // values computed elsewhere that ops read, by first use
  std::vector<int> constants;  // the constants that ops read, by first use
  std::vector<int> outputs;    // ops that other sections or the outputs read
  std::string shape;           // the operations with operands renamed; equal shape, equal code
  int group = -1;              // index of its shared function, -1 when emitted in place
  int instance = 0;            // its row in the shared function's constant table
  int w = 0;                   // where its outputs start in w
};

template <class T>
std::vector<Section> sections_of(const Program<T>& program, const std::vector<bool>& is_op) {
  const auto& nodes = program.graph.nodes;
  std::vector<Section> sections;
  std::vector<int> section_of(nodes.size(), -1), local(nodes.size(), -1);
  for (std::size_t id = 0; id < nodes.size(); ++id) {
    if (!is_op[id]) continue;
    const Node<T>& n = nodes[id];
    if (sections.empty() || sections.back().body != n.body || sections.back().pass != n.pass)
      sections.push_back({n.body, n.pass, {}, {}, {}, {}, {}});
    section_of[id] = static_cast<int>(sections.size()) - 1;
    local[id] = static_cast<int>(sections.back().ops.size());
    sections.back().ops.push_back(static_cast<int>(id));
  }
  std::vector<bool> read_outside(nodes.size(), false);
  for (const int id : program.stored) read_outside[id] = true;
  for (Section& s : sections) {
    const int self = section_of[s.ops.front()];
    std::map<int, int> slot, constant_slot;
    for (const int id : s.ops) {
      const Node<T>& n = nodes[id];
      s.shape += fmt::format("{}", static_cast<int>(n.op));
      if (n.op == Op::Call) s.shape += fmt::format(" call{}", n.a);  // never shared
      program.graph.for_each_operand(id, [&](int x) {
        if (nodes[x].op == Op::Const) {
          const auto [it, added] = constant_slot.emplace(x, static_cast<int>(s.constants.size()));
          if (added) s.constants.push_back(x);
          s.shape += fmt::format(" k{}", it->second);
        } else if (section_of[x] == self) {
          s.shape += fmt::format(" t{}", local[x]);
        } else {
          if (section_of[x] >= 0) read_outside[x] = true;
          const auto [it, added] = slot.emplace(x, static_cast<int>(s.inputs.size()));
          if (added) s.inputs.push_back(x);
          s.shape += fmt::format(" x{}", it->second);
        }
      });
      s.shape += ";";
    }
  }
  for (Section& s : sections) {
    for (const int id : s.ops)
      if (read_outside[id]) s.outputs.push_back(id);
    s.shape += "->";
    for (const int id : s.outputs) s.shape += fmt::format(" t{}", local[id]);
  }
  return sections;
}

std::string body_label(const Model<double>& model, int body) {
  return fmt::format("'{}' ({})", safe_text(model.body_name[body]), body);
}

}  // namespace

template <class T>
EmittedCode emit_code(const Program<T>& program, const Model<double>& model, Structure structure,
                      const Dialect& dialect) {
  const auto& nodes = program.graph.nodes;
  const std::vector<bool> live = live_nodes(program);
  const std::string scalar = std::is_same_v<T, float> ? "float" : "double";
  const std::string type = dialect.batch() ? "lane" : scalar;  // of each computed value
  const std::string& prefix = program.algorithm;

  // sin and cos of joint angles come precomputed in trig (joint_trig), so that one call of
  // dyngen_sincos serves every function that takes the same q
  auto is_trig = [&](const Node<T>& n) {
    if (n.op != Op::Sin && n.op != Op::Cos) return false;
    const Node<T>& x = nodes[n.a];
    if (x.op != Op::Input || program.graph.inputs[x.input].array != "q")
      throw std::logic_error("internal error: sin or cos of something other than a joint angle");
    return true;
  };
  std::vector<bool> is_op(nodes.size(), false);
  for (std::size_t id = 0; id < nodes.size(); ++id)
    is_op[id] = live[id] && nodes[id].op != Op::Const && nodes[id].op != Op::Input &&
                nodes[id].op != Op::Result && !is_trig(nodes[id]);

  // Kernel calls: each array a call writes is named once, and an array of the function's
  // outputs that is exactly one of them is passed to the kernel to write in place
  const std::vector<KernelRecord>& calls = program.graph.calls;
  if (dialect.c() && !calls.empty())
    throw std::logic_error("internal error: a kernel call in C code");
  std::vector<std::vector<std::string>> call_arrays(calls.size());
  std::vector<std::vector<bool>> call_in_place(calls.size());
  std::vector<bool> output_in_place(program.outputs.size(), false);
  for (std::size_t c = 0; c < calls.size(); ++c) {
    const KernelRecord& call = calls[c];
    int first = call.first_result;
    for (std::size_t j = 0; j < call.outputs.size(); ++j) {
      std::string array = fmt::format("{}_{}_{}", call.kernel, c,
                                      call.names[call.tables.size() + call.inputs.size() + j]);
      bool in_place = false;
      std::size_t offset = 0;
      for (std::size_t a = 0; a < program.outputs.size() && !in_place; ++a) {
        const std::size_t size = program.outputs[a].size;
        // batch outputs are stored from lanes
        in_place = !dialect.batch() && size == call.outputs[j] && !output_in_place[a];
        for (std::size_t k = 0; in_place && k < size; ++k)
          in_place = program.stored[offset + k] == first + static_cast<int>(k);
        if (in_place) {
          array = std::string(program.outputs[a].spec.name);
          output_in_place[a] = true;
        }
        offset += size;
      }
      call_in_place[c].push_back(in_place);
      call_arrays[c].push_back(array);
      first += static_cast<int>(call.outputs[j]);
    }
  }
  auto result_name = [&](const Node<T>& n) {
    const int c = nodes[n.a].a;
    std::size_t index = static_cast<std::size_t>(n.input);
    std::size_t j = 0;
    while (index >= calls[c].outputs[j]) index -= calls[c].outputs[j++];
    return fmt::format("{}[{}]", call_arrays[c][j], index);
  };

  // Shared structure: sections of the same shape (a right leg's and a left leg's, a chain's
  // links) run one function over a table of their constants; the operations and their order
  // are those of the unrolled code, so the bits are too.
  std::vector<Section> sections = sections_of(program, is_op);
  std::vector<std::vector<int>> groups;
  const long operations = std::count(is_op.begin(), is_op.end(), true);
  if (structure == Structure::Shared ||
      (structure == Structure::Auto && operations >= min_shared_function_operations)) {
    std::map<std::string, std::vector<int>> by_shape;
    for (std::size_t s = 0; s < sections.size(); ++s)
      if (sections[s].body >= 0) by_shape[sections[s].shape].push_back(static_cast<int>(s));
    std::map<int, std::vector<int>> by_first;  // numbered in the order the body calls them
    for (auto& [shape, members] : by_shape)
      if (members.size() > 1 && sections[members.front()].ops.size() >= min_shared_operations)
        by_first[members.front()] = members;
    for (auto& [first, members] : by_first) {
      for (std::size_t k = 0; k < members.size(); ++k) {
        sections[members[k]].group = static_cast<int>(groups.size());
        sections[members[k]].instance = static_cast<int>(k);
      }
      groups.push_back(members);
    }
  }
  EmittedCode code;
  code.angles.assign(static_cast<std::size_t>(model.nq), false);
  for (std::size_t id = 0; id < nodes.size(); ++id)
    if (live[id] && is_trig(nodes[id]))
      code.angles[static_cast<std::size_t>(program.graph.inputs[nodes[nodes[id].a].input].index)] =
          true;
  code.sections = static_cast<int>(sections.size());
  code.shared_functions = static_cast<int>(groups.size());
  int w_size = 0;
  std::vector<std::string> name(nodes.size());
  for (Section& s : sections) {
    if (s.group < 0) continue;
    ++code.shared_sections;
    s.w = w_size;
    for (std::size_t k = 0; k < s.outputs.size(); ++k)
      name[s.outputs[k]] = fmt::format("w[{}]", w_size + static_cast<int>(k));
    w_size += static_cast<int>(s.outputs.size());
  }

  auto operand = [&](int id) -> std::string {
    const Node<T>& n = nodes[id];
    if (n.op == Op::Const) return literal(n.value);
    if (n.op == Op::Input) {
      const InputRef& in = program.graph.inputs[n.input];
      return dialect.batch() ? fmt::format("{}{}", in.array, in.index)
                             : fmt::format("{}[{}]", in.array, in.index);
    }
    if (is_trig(n))
    {
      const char* function = n.op == Op::Sin ? "sin" : "cos";
      const int index = program.graph.inputs[nodes[n.a].input].index;
      return dialect.batch() ? fmt::format("{}_q{}", function, index)
                             : fmt::format("{}{}_q[{}]", dialect.trig_member(), function, index);
    }
    if (n.op == Op::Result) return result_name(n);
    return name[id];
  };
  // an element of an array of values: in batch code a constant fills every lane
  auto element = [&](int id) {
    if (!dialect.batch() || nodes[id].op != Op::Const) return operand(id);
    std::string copies = operand(id);
    for (int l = 1; l < dialect.lanes; ++l) copies += ", " + operand(id);
    return "lane{" + copies + "}";
  };
  auto expression = [&](const Node<T>& n, auto&& arg) {
    switch (n.op) {
      case Op::Neg: return "-" + arg(n.a);
      case Op::Add: return arg(n.a) + " + " + arg(n.b);
      case Op::Sub: return arg(n.a) + " - " + arg(n.b);
      case Op::Mul: return arg(n.a) + " * " + arg(n.b);
      case Op::Div: return arg(n.a) + " / " + arg(n.b);
      default: return std::string();
    }
  };

  // the shared functions, each with its constant table
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const Section& first = sections[groups[g].front()];
    const std::string fn = fmt::format("{}_shape_{}", prefix, g);
    std::string users;
    for (std::size_t k = 0; k < groups[g].size() && k < 6; ++k)
      users += (k ? ", " : "") + body_label(model, sections[groups[g][k]].body);
    if (groups[g].size() > 6) users += fmt::format(" and {} more", groups[g].size() - 6);
    code.helpers += fmt::format(
        "// {}: {} operations, {} inputs, {} outputs; {}, {} sections: {}\n", fn,
        first.ops.size(), first.inputs.size(), first.outputs.size(), pass_name(first.pass),
        groups[g].size(), users);
    const std::size_t nk = first.constants.size();
    if (nk > 0) {
      code.helpers += fmt::format("{} {} {}_k[{}][{}] = {{\n", dialect.table(), scalar, fn,
                                  groups[g].size(), nk);
      for (const int member : groups[g]) {
        std::string row;
        for (const int c : sections[member].constants)
          row += (row.empty() ? "" : ", ") + literal(nodes[c].value);
        code.helpers += fmt::format("    {{{}}},\n", row);
      }
      code.helpers += "};\n";
    }
    code.helpers += fmt::format("static void {}({}const {} x[{}], {} y[{}]){}\n{{\n", fn,
                                nk > 0 ? fmt::format("const {} k[{}], ", scalar, nk) : "", type,
                                first.inputs.size(), type, first.outputs.size(),
                                dialect.no_throw());
    std::map<int, std::string> local;
    for (std::size_t k = 0; k < first.inputs.size(); ++k)
      local[first.inputs[k]] = fmt::format("x[{}]", k);
    for (std::size_t k = 0; k < first.constants.size(); ++k)
      local[first.constants[k]] = fmt::format("k[{}]", k);
    for (std::size_t k = 0; k < first.ops.size(); ++k) {
      code.helpers += fmt::format("    const {} t{} = {};\n", type, k,
                                  expression(nodes[first.ops[k]], [&](int id) { return local.at(id); }));
      local[first.ops[k]] = fmt::format("t{}", k);
    }
    for (std::size_t k = 0; k < first.outputs.size(); ++k)
      code.helpers += fmt::format("    y[{}] = {};\n", k, local.at(first.outputs[k]));
    code.helpers += "}\n\n";
  }

  // the arrays that the emitted statements and output stores read
  std::map<std::string, bool> used;
  std::set<int> loads;  // batch code: the input and trig nodes read, loaded into lanes first
  auto use = [&](int id) {
    const Node<T>& n = nodes[id];
    if (n.op == Op::Input)
      used[program.graph.inputs[n.input].array] = true;
    else if (is_trig(n))
      used["trig"] = true;
    else
      return;
    loads.insert(id);
  };
  for (std::size_t id = 0; id < nodes.size(); ++id)
    if (is_op[id]) program.graph.for_each_operand(static_cast<int>(id), use);
  for (const int id : program.stored) use(id);

  std::string& out = code.body;
  std::vector<std::string> arrays;
  for (const ProgramArray& a : program.inputs) arrays.emplace_back(a.spec.name);
  const auto q = std::find(arrays.begin(), arrays.end(), "q");
  arrays.insert(q == arrays.end() ? q : q + 1, "trig");
  for (const std::string& array : arrays)
    if (!used[array])
      out += fmt::format("    {};  // {}\n\n", dialect.discard(array),
                         array == "q" && used["trig"] ? "read only through trig"
                                                      : "no output of this robot depends on it");
  if (dialect.batch() && !loads.empty()) {
    out += "    // the inputs' lanes\n";
    for (const int id : loads) {
      const Node<T>& n = nodes[id];
      const InputRef& in = program.graph.inputs[n.op == Op::Input ? n.input : nodes[n.a].input];
      const std::string from =
          n.op == Op::Input ? in.array : fmt::format("trig.{}_q", n.op == Op::Sin ? "sin" : "cos");
      out += fmt::format("    lane {}; load({}, {} + {} * lanes);\n", operand(id), operand(id),
                         from, in.index);
    }
    out += "\n";
  }
  if (w_size > 0)
    out += fmt::format("    {} w[{}];  // the outputs of the sections that shared functions compute\n\n",
                       type, w_size);
  // a kernel call: its tables, the arrays it reads (an array another call wrote is passed as it
  // is, the same entries gathered once), the arrays it writes, and the call
  std::map<std::vector<int>, std::string> gathered;
  auto kernel_call = [&](int c) {
    const KernelRecord& call = calls[c];
    std::string text = fmt::format("    // dyngen::kernels::{}: {}\n", call.kernel,
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
          if (same) array = call_arrays[d][k];
          first += static_cast<int>(calls[d].outputs[k]);
        }
      }
      if (array.empty()) {
        const auto [it, added] =
            gathered.emplace(ids, fmt::format("{}_{}_{}", call.kernel, c,
                                              call.names[call.tables.size() + j]));
        if (added) {
          std::vector<std::string> items;
          for (const int id : ids) items.push_back(element(id));
          text += fmt::format("    const {} {}[{}] = {};\n", type, it->second, ids.size(),
                              braced_list(items));
        }
        array = it->second;
      }
      arguments.push_back(array);
    }
    for (std::size_t j = 0; j < call.outputs.size(); ++j) {
      const std::string& array = call_arrays[c][j];
      if (!call_in_place[c][j])
        text += fmt::format("    {} {}[{}];\n", type, array, call.outputs[j]);
      arguments.push_back(array);
    }
    const std::string kernel = fmt::format("dyngen::kernels::{}", call.kernel);
    if (!dialect.batch()) return text + wrapped_call(kernel, arguments);
    // lane by lane: each state's numbers copied out of the lanes, the scalar kernel, and its
    // results copied back
    const std::size_t first_array = call.ints.size() + call.tables.size();
    const std::size_t arrays = call.inputs.size() + call.outputs.size();
    std::string declare, copy_in, copy_out;
    for (std::size_t j = 0; j < arrays; ++j) {
      const bool input = j < call.inputs.size();
      const std::string& array = arguments[first_array + j];
      const std::size_t size = input ? call.inputs[j].size() : call.outputs[j - call.inputs.size()];
      declare += fmt::format("        {} {}_l[{}];\n", scalar, array, size);
      if (input)
        copy_in += fmt::format("        for (int k = 0; k < {1}; ++k) {0}_l[k] = {0}[k][l];\n",
                               array, size);
      else
        copy_out += fmt::format("        for (int k = 0; k < {1}; ++k) {0}[k][l] = {0}_l[k];\n",
                                array, size);
      arguments[first_array + j] = array + "_l";
    }
    return text + "    for (int l = 0; l < lanes; ++l) {\n" + declare + copy_in +
           wrapped_call(kernel, arguments, "        ") + copy_out + "    }\n";
  };
  std::vector<int> per_body(model.nbodies + 1, 0);
  const std::vector<std::string> prefixes = temporary_prefixes(model);
  for (const Section& s : sections) {
    out += section_header<T>(model, s.body, s.pass);
    if (s.group >= 0) {
      std::string x;
      for (const int id : s.inputs) x += (x.empty() ? "" : ", ") + element(id);
      const std::string k = s.constants.empty()
                                ? std::string()
                                : fmt::format("{}_shape_{}_k[{}], ", prefix, s.group, s.instance);
      out += fmt::format("    {{\n        const {} x[] = {{{}}};\n        {}_shape_{}({}x, w + {});\n    }}\n\n",
                         type, x, prefix, s.group, k, s.w);
      continue;
    }
    for (const int id : s.ops) {
      const Node<T>& n = nodes[id];
      if (n.op == Op::Call) {
        out += kernel_call(n.a);
        continue;
      }
      name[id] = fmt::format("{}_{}", prefixes[n.body + 1], per_body[n.body + 1]++);
      out += fmt::format("    const {} {} = {};\n", type, name[id], expression(n, operand));
    }
    out += "\n";
  }
  out += "    // ---- outputs\n";
  std::size_t stored = 0;
  for (std::size_t a = 0; a < program.outputs.size(); ++a) {
    const ProgramArray& array = program.outputs[a];
    if (output_in_place[a])
      out += fmt::format("    // {}: written by the kernel\n", array.spec.name);
    else {
      // an array with a block per frame says whose block begins
      const std::size_t frames = array.spec.extent.per_frame ? model.frames.size() : 0;
      for (std::size_t k = 0; k < array.size; ++k) {
        if (frames > 0 && k % (array.size / frames) == 0)
          out += fmt::format("    // frame '{}'\n",
                             safe_text(model.frames[k / (array.size / frames)].name));
        if (dialect.batch())
          out += fmt::format("    store({} + {} * lanes, {});\n", array.spec.name, k,
                             operand(program.stored[stored + k]));
        else
          out += fmt::format("    {}[{}] = {};\n", array.spec.name, k,
                             operand(program.stored[stored + k]));
      }
    }
    stored += array.size;
  }
  return code;
}

namespace {

std::vector<bool> revolute_angles(const Model<double>& model) {
  std::vector<bool> revolute(model.nq, false);
  for (int i = 0; i < model.nbodies; ++i)
    if (is_revolute(model.joint_type[i])) revolute[model.q_index[i]] = true;
  return revolute;
}

/// dyngen_sincos calls for the marked q entries into `trig` (the trig's name and member access,
/// "trig." or "trig->"): one array call per run of consecutive ones, which the compiler can
/// vectorise. Batch code (`batch`) holds a run's lanes together too, so it is one call as well.
std::string sincos_calls(const std::vector<bool>& marked, bool single_precision,
                         const std::string& trig, bool batch = false) {
  const char* sincos = single_precision ? "dyngen_sincosf" : "dyngen_sincos";
  const int nq = static_cast<int>(marked.size());
  std::string out;
  for (int k = 0; k < nq;) {
    if (!marked[k]) {
      ++k;
      continue;
    }
    int end = k;
    while (end < nq && marked[end]) ++end;
    if (batch)
      out += fmt::format(
          "    {3}_array(q + {0} * lanes, {4}sin_q + {0} * lanes, {4}cos_q + {0} * lanes, {1} * "
          "lanes);  // q[{0}..{2}]\n",
          k, end - k, end - 1, sincos, trig);
    else if (end - k == 1)
      out += fmt::format("    {1}(q[{0}], &{2}sin_q[{0}], &{2}cos_q[{0}]);\n", k, sincos, trig);
    else
      out += fmt::format(
          "    {3}_array(q + {0}, {4}sin_q + {0}, {4}cos_q + {0}, {1});  // q[{0}..{2}]\n", k,
          end - k, end - 1, sincos, trig);
    k = end;
  }
  return out;
}

}  // namespace

std::string Dialect::size(const std::string& local) const {
  if (!c()) return local;
  std::string macro = name + "_" + local;
  for (char& ch : macro) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return macro;
}

std::string emit_joint_trig(const Model<double>& model, bool single_precision,
                            const Dialect& dialect) {
  const std::string out = sincos_calls(revolute_angles(model), single_precision,
                                       dialect.trig_member(), dialect.batch());
  if (out.empty())
    return fmt::format("    {};  // no revolute joint\n    {};\n", dialect.discard("q"),
                       dialect.discard("trig"));
  return out;
}

std::string emit_trig_fill(const Model<double>& model, bool single_precision,
                           const std::vector<bool>& angles, const Dialect& dialect) {
  if (angles == revolute_angles(model) ||
      std::find(angles.begin(), angles.end(), true) == angles.end())
    return fmt::format("    {}(q, {}trig);\n",
                       dialect.external(dialect.batch() ? "joint_trig_batch" : "joint_trig"),
                       dialect.c() ? "&" : "");
  std::string out = "    // the angles this function reads\n";
  return out.append(sincos_calls(angles, single_precision, "trig.", dialect.batch()));
}

template OpCounts count_ops<double>(const Program<double>&, bool);
template OpCounts count_ops<float>(const Program<float>&, bool);
template EmittedCode emit_code<double>(const Program<double>&, const Model<double>&, Structure,
                                       const Dialect&);
template EmittedCode emit_code<float>(const Program<float>&, const Model<double>&, Structure,
                                      const Dialect&);

}  // namespace dyngen::gen
