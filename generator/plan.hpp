// What emit_code decides before it prints, as plain data that a test can inspect: which nodes
// are statements, the sections of one body's operations in one pass, and how each is computed
// (in place, by a function shared with sections of the same shape, or in vector lanes with the
// same sections of other limbs), and the arrays that kernel calls write.
#pragma once

#include <string>
#include <vector>

#include "dyngen/model.hpp"
#include "emit.hpp"
#include "trace.hpp"

namespace dyngen::gen {

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

/// By node: whether it reaches an output.
template <class T>
std::vector<bool> live_nodes(const Program<T>& program);

/// The plan of program's code in dialect under structure.
template <class T>
CodePlan plan_code(const Program<T>& program, const Model<double>& model, Structure structure,
                   const Dialect& dialect);

/// The first or second operand of the block's operation at position k, by lane.
template <class T>
inline std::vector<int> lane_operands(const Program<T>& program, const std::vector<Section>& sections,
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

}  // namespace dyngen::gen
