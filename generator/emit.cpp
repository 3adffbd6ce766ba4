#include "emit.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <queue>
#include <set>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>

#include "footprint.hpp"
#include "names.hpp"

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
}

/// The operations of the nodes marked in counted.
template <class T>
OpCounts count_marked(const Program<T>& program, const std::vector<bool>& counted) {
  OpCounts c;
  for (std::size_t id = 0; id < program.graph.nodes.size(); ++id)
    if (counted[id]) count_node(c, program, program.graph.nodes[id]);
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
  return count_marked(program, live_only ? live_nodes(program)
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

/// Sections of limbs at the same depth that perform the same operations on other numbers (a
/// quadruped's four upper legs) run in one block of vector statements: lane l of each does
/// section l's operation on section l's operands, so each lane computes the bits of the
/// unrolled code. An operation stays scalar where its lanes would read one another (a sum
/// carried from limb to limb) or what the other lanes' results feed.
struct LaneBlock {
  std::vector<int> members;  // sections, one per lane
  std::vector<bool> in_lanes;  // by position in a member's ops
  int first = 0;             // the smallest node id of its lanes' operations
};

/// Where a node computed in lanes is: its block, lane and position.
struct LaneSlot {
  int block = -1, lane = 0, position = 0;
};

template <class T>
std::vector<LaneBlock> plan_lane_blocks(const Program<T>& program, const Model<double>& model,
                                        const std::vector<Section>& sections) {
  const auto& nodes = program.graph.nodes;
  const int n = static_cast<int>(nodes.size());
  std::vector<int> section_of(n, -1), local(n, -1);
  for (std::size_t s = 0; s < sections.size(); ++s)
    for (std::size_t k = 0; k < sections[s].ops.size(); ++k) {
      section_of[sections[s].ops[k]] = static_cast<int>(s);
      local[sections[s].ops[k]] = static_cast<int>(k);
    }
  std::vector<std::vector<int>> consumers(n);
  for (const Section& s : sections)
    for (const int id : s.ops) program.graph.for_each_operand(id, [&](int x) {
        consumers[x].push_back(id);
      });
  for (int id = 0; id < n; ++id)  // a kernel's results are read through its call
    if (nodes[id].op == Op::Result) consumers[nodes[id].a].push_back(id);

  // candidates: the same pass, depth and operations, operands inside the section by position
  // and the others (constants, inputs, other sections' values) alike
  std::vector<int> depth(static_cast<std::size_t>(model.nbodies), 0);
  for (int i = 0; i < model.nbodies; ++i)
    depth[i] = model.parent[i] < 0 ? 0 : depth[model.parent[i]] + 1;
  std::map<std::tuple<int, int, std::string>, std::vector<int>> candidates;
  for (std::size_t s = 0; s < sections.size(); ++s) {
    const Section& section = sections[s];
    if (section.body < 0 || section.ops.size() < min_lane_operations) continue;
    std::string shape;
    bool calls = false;
    for (const int id : section.ops) {
      calls = calls || nodes[id].op == Op::Call;
      shape += fmt::format("{}", static_cast<int>(nodes[id].op));
      program.graph.for_each_operand(id, [&](int x) {
        shape += section_of[x] == static_cast<int>(s) ? fmt::format(" t{}", local[x]) : " o";
      });
      shape += ";";
    }
    if (!calls)
      candidates[{static_cast<int>(section.pass), depth[section.body], shape}].push_back(
          static_cast<int>(s));
  }

  // the width of SSE2's and NEON's vector registers, which every x86-64 and AArch64 processor
  // has: 2 doubles or 4 floats (4 doubles in AVX's, emulated without it, ran slower than 2)
  const std::size_t width = 16 / sizeof(T);
  std::vector<LaneBlock> blocks;
  std::vector<char> reached(n, 0);
  for (auto& [key, members] : candidates) {
    // lanes in the order of the bodies, whatever the pass, so that blocks hand on whole vectors
    std::sort(members.begin(), members.end(),
              [&](int a, int b) { return sections[a].body < sections[b].body; });
    for (std::size_t begin = 0; members.size() - begin >= 2;) {
      std::size_t lanes = 2;
      while (lanes * 2 <= std::min(members.size() - begin, width)) lanes *= 2;
      LaneBlock block;
      block.members.assign(members.begin() + static_cast<long>(begin),
                           members.begin() + static_cast<long>(begin + lanes));
      begin += lanes;
      const std::size_t length = sections[block.members[0]].ops.size();
      auto member_of = [&](int x) {
        return std::find(block.members.begin(), block.members.end(), section_of[x]) !=
               block.members.end();
      };
      auto op_at = [&](std::size_t lane, std::size_t k) {
        return sections[block.members[lane]].ops[k];
      };
      // in lanes where each operand is the same position of every lane's section, or outside
      // every lane's section
      block.in_lanes.assign(length, false);
      for (std::size_t k = 0; k < length; ++k) {
        bool ok = true;
        for (int slot = 0; slot < 2 && ok; ++slot) {
          const int x0 = slot == 0 ? nodes[op_at(0, k)].a : nodes[op_at(0, k)].b;
          if (x0 < 0) continue;
          const bool inside = section_of[x0] == block.members[0];
          for (std::size_t l = 0; l < lanes && ok; ++l) {
            const int x = slot == 0 ? nodes[op_at(l, k)].a : nodes[op_at(l, k)].b;
            ok = inside ? section_of[x] == block.members[l] && local[x] == local[x0] &&
                              block.in_lanes[static_cast<std::size_t>(local[x0])]
                        : !member_of(x);
          }
        }
        block.in_lanes[k] = ok;
      }
      // nothing in lanes may read what the block's lanes feed
      std::fill(reached.begin(), reached.end(), 0);
      std::vector<int> stack;
      for (std::size_t k = 0; k < length; ++k)
        if (block.in_lanes[k])
          for (std::size_t l = 0; l < lanes; ++l) stack.push_back(op_at(l, k));
      while (!stack.empty()) {
        const int id = stack.back();
        stack.pop_back();
        for (const int c : consumers[id])
          if (!reached[c]) reached[c] = 1, stack.push_back(c);
      }
      for (std::size_t k = 0; k < length; ++k) {
        if (!block.in_lanes[k]) continue;
        for (std::size_t l = 0; l < lanes; ++l)
          program.graph.for_each_operand(op_at(l, k), [&](int x) {
            if (member_of(x) ? !block.in_lanes[static_cast<std::size_t>(local[x])] : reached[x])
              block.in_lanes[k] = false;
          });
      }
      const long count = std::count(block.in_lanes.begin(), block.in_lanes.end(), true);
      if (count < static_cast<long>(min_lane_operations)) continue;
      block.first = n;
      for (std::size_t k = 0; k < length; ++k)
        if (block.in_lanes[k]) block.first = std::min(block.first, op_at(0, k));
      blocks.push_back(std::move(block));
    }
  }
  std::sort(blocks.begin(), blocks.end(),
            [](const LaneBlock& a, const LaneBlock& b) { return a.first < b.first; });
  return blocks;
}

/// The order of emission with lane blocks: each block's vector statements as one unit (-1 -
/// block), every other operation as itself (its node id), in the trace's order as far as the
/// blocks allow. Drops the blocks that would wait on one another in a cycle.
template <class T>
std::vector<int> schedule_lane_blocks(const Program<T>& program,
                                      const std::vector<Section>& sections,
                                      std::vector<LaneBlock>& blocks,
                                      std::vector<LaneSlot>& slot) {
  const auto& nodes = program.graph.nodes;
  const int n = static_cast<int>(nodes.size());
  for (;;) {
    slot.assign(n, LaneSlot{});
    for (std::size_t b = 0; b < blocks.size(); ++b)
      for (std::size_t l = 0; l < blocks[b].members.size(); ++l)
        for (std::size_t k = 0; k < blocks[b].in_lanes.size(); ++k)
          if (blocks[b].in_lanes[k])
            slot[sections[blocks[b].members[l]].ops[k]] = {static_cast<int>(b),
                                                           static_cast<int>(l),
                                                           static_cast<int>(k)};
    // units: n + b for block b, the node id for an operation in place
    const int units = n + static_cast<int>(blocks.size());
    auto unit_of = [&](int id) {
      if (nodes[id].op == Op::Result) id = nodes[id].a;
      return slot[id].block >= 0 ? n + slot[id].block : id;
    };
    std::vector<std::vector<int>> after(units);
    std::vector<int> waiting(units, 0), priority(units, -1);
    std::vector<char> is_unit(units, 0);
    for (const Section& s : sections)
      for (const int id : s.ops) {
        const int u = unit_of(id);
        if (!is_unit[u]) is_unit[u] = 1, priority[u] = id;
        priority[u] = std::min(priority[u], id);
        program.graph.for_each_operand(id, [&](int x) {
          const Op op = nodes[x].op;
          if (op == Op::Const || op == Op::Input || op == Op::Sin || op == Op::Cos) return;
          const int v = unit_of(x);
          if (v != u) after[v].push_back(u), ++waiting[u];
        });
      }
    std::priority_queue<std::pair<int, int>, std::vector<std::pair<int, int>>,
                        std::greater<>>
        ready;
    for (int u = 0; u < units; ++u)
      if (is_unit[u] && waiting[u] == 0) ready.push({priority[u], u});
    std::vector<int> order;
    while (!ready.empty()) {
      const int u = ready.top().second;
      ready.pop();
      order.push_back(u >= n ? -1 - (u - n) : u);
      for (const int v : after[u])
        if (--waiting[v] == 0) ready.push({priority[v], v});
    }
    int stuck = -1;
    for (int b = static_cast<int>(blocks.size()) - 1; b >= 0 && stuck < 0; --b)
      if (waiting[n + b] > 0) stuck = b;
    if (stuck < 0) return order;
    blocks.erase(blocks.begin() + stuck);
  }
}

/// The first or second operand of the block's operation at position k, by lane.
template <class T>
std::vector<int> lane_operands(const Program<T>& program, const std::vector<Section>& sections,
                               const LaneBlock& block, std::size_t k, bool second) {
  std::vector<int> x;
  for (const int member : block.members) {
    const Node<T>& n = program.graph.nodes[sections[member].ops[k]];
    x.push_back(second ? n.b : n.a);
  }
  return x;
}

/// Whether operands x (by lane) are one vector of a block as wide, lane l from its lane l.
inline bool whole_vector(const std::vector<int>& x, const std::vector<LaneBlock>& blocks,
                         const std::vector<LaneSlot>& slot) {
  const LaneSlot& first = slot[x[0]];
  if (first.block < 0 || blocks[static_cast<std::size_t>(first.block)].members.size() != x.size())
    return false;
  for (std::size_t l = 0; l < x.size(); ++l)
    if (slot[x[l]].block != first.block || slot[x[l]].lane != static_cast<int>(l) ||
        slot[x[l]].position != first.position)
      return false;
  return true;
}

/// The vectors a block fills from separate values (its lanes reading values that are neither
/// constants nor the lanes of one vector), each counted once.
template <class T>
long lane_fills(const Program<T>& program, const std::vector<Section>& sections,
                const std::vector<LaneBlock>& blocks, const std::vector<LaneSlot>& slot,
                std::size_t b) {
  const LaneBlock& block = blocks[b];
  std::set<std::vector<int>> fills;
  for (std::size_t k = 0; k < block.in_lanes.size(); ++k) {
    if (!block.in_lanes[k]) continue;
    for (const bool second : {false, true}) {
      const std::vector<int> x = lane_operands(program, sections, block, k, second);
      if (x[0] < 0) continue;
      const bool constant = std::all_of(x.begin(), x.end(), [&](int id) {
        return program.graph.nodes[id].op == Op::Const;
      });
      if (!constant && !whole_vector(x, blocks, slot)) fills.insert(x);
    }
  }
  return static_cast<long>(fills.size());
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

/// What emit_code decides before it prints, as plain data: which nodes are statements, the
/// sections and how each is computed (in place, by a shared function, in vector lanes), and
/// the arrays that kernel calls write.
struct CodePlan {
  std::vector<bool> live;      // by node: reaches an output
  std::vector<bool> trig;      // by node: sin or cos of a joint angle, read from trig
  std::vector<bool> is_op;     // by node: a statement of the body
  std::vector<Section> sections;
  std::vector<std::vector<int>> groups;  // by shared function: the sections it computes
  int w_size = 0;                        // the outputs of the shared functions' sections
  bool lanes = false;                    // computed in lane blocks (Structure::Lanes)
  std::vector<LaneBlock> blocks;
  std::vector<LaneSlot> slot;
  std::vector<int> order;  // of emission in lanes: node ids, and -1 - b for block b
  // by kernel call and array it writes: the array's name, and whether it is an output written
  // in place; by output array: whether a kernel writes it in place
  std::vector<std::vector<std::string>> call_arrays;
  std::vector<std::vector<bool>> call_in_place;
  std::vector<bool> output_in_place;
};

/// sin and cos of joint angles come precomputed in trig (joint_trig), so that one call of
/// dyngen_sincos serves every function that takes the same q.
template <class T>
std::vector<bool> trig_nodes(const Program<T>& program, const std::vector<bool>& live) {
  const auto& nodes = program.graph.nodes;
  std::vector<bool> trig(nodes.size(), false);
  for (std::size_t id = 0; id < nodes.size(); ++id) {
    const Node<T>& n = nodes[id];
    if (!live[id] || (n.op != Op::Sin && n.op != Op::Cos)) continue;
    const Node<T>& x = nodes[n.a];
    if (x.op != Op::Input || program.graph.inputs[x.input].array != "q")
      throw std::logic_error("internal error: sin or cos of something other than a joint angle");
    trig[id] = true;
  }
  return trig;
}

/// Kernel calls: each array a call writes is named once, and an array of the function's outputs
/// that is exactly one of them is passed to the kernel to write in place (not in batch code,
/// whose outputs are stored from lanes).
template <class T>
void plan_kernel_arrays(const Program<T>& program, const Dialect& dialect, CodePlan& plan) {
  const std::vector<KernelRecord>& calls = program.graph.calls;
  if (!dialect.kernel_calls() && !calls.empty())
    throw std::logic_error(fmt::format("internal error: a kernel call in {} code", dialect.title()));
  plan.call_arrays.assign(calls.size(), {});
  plan.call_in_place.assign(calls.size(), {});
  plan.output_in_place.assign(program.outputs.size(), false);
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
        in_place = dialect.lanes() == 0 && size == call.outputs[j] && !plan.output_in_place[a];
        for (std::size_t k = 0; in_place && k < size; ++k)
          in_place = program.stored[offset + k] == first + static_cast<int>(k);
        if (in_place) {
          array = std::string(program.outputs[a].spec.name);
          plan.output_in_place[a] = true;
        }
        offset += size;
      }
      plan.call_in_place[c].push_back(in_place);
      plan.call_arrays[c].push_back(array);
      first += static_cast<int>(call.outputs[j]);
    }
  }
}

/// Lanes where the structure asks for them, or, under Auto, where limbs repeat in a function
/// of fewer than max_lane_function_operations (counted with the kernels' loops, as the banner
/// counts them). Filling a vector costs about an instruction a lane, as an operation does: a
/// block must save at least twice what it fills.
template <class T>
void plan_lanes(const Program<T>& program, const Model<double>& model, Structure structure,
                const Dialect& dialect, CodePlan& plan) {
  plan.lanes = dialect.lane_blocks() &&
               (structure == Structure::Lanes ||
                (structure == Structure::Auto &&
                 count_marked(program, plan.live).total() < max_lane_function_operations));
  if (!plan.lanes) return;
  plan.blocks = plan_lane_blocks(program, model, plan.sections);
  plan.order = schedule_lane_blocks(program, plan.sections, plan.blocks, plan.slot);
  std::vector<LaneBlock> paying;
  for (std::size_t b = 0; b < plan.blocks.size(); ++b)
    if (std::count(plan.blocks[b].in_lanes.begin(), plan.blocks[b].in_lanes.end(), true) >=
        2 * lane_fills(program, plan.sections, plan.blocks, plan.slot, b))
      paying.push_back(plan.blocks[b]);
  if (paying.size() < plan.blocks.size()) {
    plan.blocks = std::move(paying);
    plan.order = schedule_lane_blocks(program, plan.sections, plan.blocks, plan.slot);
  }
  plan.lanes = structure == Structure::Lanes || !plan.blocks.empty();
}

/// Shared structure: sections of the same shape (a right leg's and a left leg's, a chain's
/// links) run one function over a table of their constants, under Shared, or under Auto from
/// min_shared_function_operations statements; the operations and their order are those of the
/// unrolled code, so the bits are too.
void plan_shared_functions(Structure structure, long operations, CodePlan& plan) {
  std::vector<Section>& sections = plan.sections;
  const bool big = operations >= min_shared_function_operations;
  if (plan.lanes || !(structure == Structure::Shared || (structure == Structure::Auto && big)))
    return;
  std::map<std::string, std::vector<int>> by_shape;
  for (std::size_t s = 0; s < sections.size(); ++s)
    if (sections[s].body >= 0) by_shape[sections[s].shape].push_back(static_cast<int>(s));
  std::map<int, std::vector<int>> by_first;  // numbered in the order the body calls them
  for (auto& [shape, members] : by_shape)
    if (members.size() > 1 && sections[members.front()].ops.size() >= min_shared_operations)
      by_first[members.front()] = members;
  for (auto& [first, members] : by_first) {
    for (std::size_t k = 0; k < members.size(); ++k) {
      sections[members[k]].group = static_cast<int>(plan.groups.size());
      sections[members[k]].instance = static_cast<int>(k);
    }
    plan.groups.push_back(members);
  }
  for (Section& s : sections) {
    if (s.group < 0) continue;
    s.w = plan.w_size;
    plan.w_size += static_cast<int>(s.outputs.size());
  }
}

template <class T>
CodePlan plan_code(const Program<T>& program, const Model<double>& model, Structure structure,
                   const Dialect& dialect) {
  const auto& nodes = program.graph.nodes;
  CodePlan plan;
  plan.live = live_nodes(program);
  plan.trig = trig_nodes(program, plan.live);
  plan.is_op.assign(nodes.size(), false);
  for (std::size_t id = 0; id < nodes.size(); ++id)
    plan.is_op[id] = plan.live[id] && nodes[id].op != Op::Const && nodes[id].op != Op::Input &&
                     nodes[id].op != Op::Result && !plan.trig[id];
  plan_kernel_arrays(program, dialect, plan);
  plan.sections = sections_of(program, plan.is_op);
  plan_lanes(program, model, structure, dialect, plan);
  plan_shared_functions(structure, std::count(plan.is_op.begin(), plan.is_op.end(), true), plan);
  return plan;
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
  if (plan_.trig[id]) {
    const char* function = n.op == Op::Sin ? "sin" : "cos";
    const int index = program_.graph.inputs[nodes_[n.a].input].index;
    return dialect_.trig_value(function, index);
  }
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
  text += fmt::format("static void {}({}const {} x[{}], {} y[{}]){}\n{{\n", fn,
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
    const InputRef& in = program_.graph.inputs[n.op == Op::Input ? n.input : nodes_[n.a].input];
    read.push_back({operand(id),
                    n.op == Op::Input ? in.array
                                      : fmt::format("{}{}_q", dialect_.trig_member(),
                                                    n.op == Op::Sin ? "sin" : "cos"),
                    in.index});
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
                                     fmt::format("dyngen::kernels::{}", call.kernel), scalar_);
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
  code_.angles.assign(static_cast<std::size_t>(model_.nq), false);
  for (std::size_t id = 0; id < nodes_.size(); ++id)
    if (plan_.trig[id])
      code_.angles[static_cast<std::size_t>(
          program_.graph.inputs[nodes_[nodes_[id].a].input].index)] = true;
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

namespace {

std::vector<bool> revolute_angles(const Model<double>& model) {
  std::vector<bool> revolute(model.nq, false);
  for (int i = 0; i < model.nbodies; ++i)
    if (is_revolute(model.joint_type[i])) revolute[model.q_index[i]] = true;
  return revolute;
}

/// dyngen_sincos calls for the marked q entries into `trig` (the trig's name and member access,
/// "trig." or "trig->"): one array call per run of consecutive ones, which the compiler can
/// vectorise.
std::string sincos_calls(const std::vector<bool>& marked, bool single_precision,
                         const std::string& trig, const Dialect& dialect) {
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
    out += dialect.sincos_run(k, end - k, sincos, trig);
    k = end;
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
      sincos_calls(revolute_angles(model), single_precision, dialect.trig_member(), dialect);
  if (out.empty())
    return fmt::format("    {};  // no revolute joint\n    {};\n", dialect.discard("q"),
                       dialect.discard("trig"));
  return out;
}

std::string emit_trig_fill(const Model<double>& model, bool single_precision,
                           const std::vector<bool>& angles, const Dialect& dialect) {
  if (angles == revolute_angles(model) ||
      std::find(angles.begin(), angles.end(), true) == angles.end())
    return fmt::format("    {}(q, {});\n", dialect.joint_trig(), dialect.trig_argument());
  std::string out = "    // the angles this function reads\n";
  return out.append(sincos_calls(angles, single_precision, "trig.", dialect));
}

template OpCounts count_ops<double>(const Program<double>&, bool);
template OpCounts count_ops<float>(const Program<float>&, bool);
template std::map<Pass, OpCounts> count_ops_by_pass<double>(const Program<double>&);
template std::map<Pass, OpCounts> count_ops_by_pass<float>(const Program<float>&);
template EmittedCode emit_code<double>(const Program<double>&, const Model<double>&, Structure,
                                       const Dialect&);
template EmittedCode emit_code<float>(const Program<float>&, const Model<double>&, Structure,
                                      const Dialect&);

}  // namespace dyngen::gen
