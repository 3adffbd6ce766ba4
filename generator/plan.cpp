#include "plan.hpp"

#include <algorithm>
#include <map>
#include <queue>
#include <set>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>

namespace dyngen::gen {

template <class T>
std::vector<bool> live_nodes(const Program<T>& program) {
  const Graph<T>& g = program.graph;
  std::vector<bool> live(g.nodes.size(), false);
  for (const int id : program.stored) live[id] = true;
  // sin and cos read their angle from the trig, which joint_trig fills (a mimic joint's own
  // angle too): the angle is computed there
  for (int id = static_cast<int>(g.nodes.size()) - 1; id >= 0; --id)
    if (live[id] && g.nodes[id].op != Op::Sin && g.nodes[id].op != Op::Cos)
      g.for_each_operand(id, [&](int x) { live[x] = true; });
  return live;
}

namespace {

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
      if (n.op == Op::Fn) s.shape += fmt::format(" fn{}", n.input);
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
      // vector statements have neither kernel calls nor lie.h's functions
      calls = calls || nodes[id].op == Op::Call || nodes[id].op == Op::Fn;
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

/// sin and cos of joint angles come precomputed in trig (joint_trig), so that one call of
/// dyngen_sincos serves every function that takes the same q: those of q's entries, and of the
/// mimic joints' own angles (Program::mimic_angles).
template <class T>
std::vector<bool> trig_nodes(const Program<T>& program, const std::vector<bool>& live) {
  const auto& nodes = program.graph.nodes;
  std::vector<bool> trig(nodes.size(), false);
  for (std::size_t id = 0; id < nodes.size(); ++id) {
    const Node<T>& n = nodes[id];
    if (!live[id] || (n.op != Op::Sin && n.op != Op::Cos)) continue;
    const Node<T>& x = nodes[n.a];
    const bool angle = x.op == Op::Input ? program.graph.inputs[x.input].array == "q"
                                         : std::ranges::count(program.mimic_angles, n.a) > 0;
    if (!angle)
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
                 count_ops(program, plan.live).total() < max_lane_function_operations));
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

}  // namespace

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

template std::vector<bool> live_nodes<double>(const Program<double>&);
template std::vector<bool> live_nodes<float>(const Program<float>&);
template CodePlan plan_code<double>(const Program<double>&, const Model<double>&, Structure,
                                    const Dialect&);
template CodePlan plan_code<float>(const Program<float>&, const Model<double>&, Structure,
                                   const Dialect&);

}  // namespace dyngen::gen
