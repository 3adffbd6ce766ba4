// The plan that emit_code prints (plan.hpp), checked against the traced program it plans: the
// sections partition the statements, shared functions serve sections of one shape, and lane
// blocks hold the same operations of limbs at one depth.
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "plan.hpp"
#include "robot.hpp"
#include "trace.hpp"

namespace {

using namespace dyngen;
using namespace dyngen::gen;

Robot load(const char* file, bool floating_base = false) {
  LoadOptions options;
  options.floating_base = floating_base;
  return load_robot(std::string(DYNGEN_TEST_MODELS) + "/" + file, options);
}

int depth(const Model<double>& model, int body) {
  int d = 0;
  for (int i = model.parent[body]; i >= 0; i = model.parent[i]) ++d;
  return d;
}

// Each statement is in one section, and a section is a maximal run of one body's and one pass's
// statements in the trace's order.
TEST(Plan, SectionsAreTheRunsOfOneBodysAndPasssStatements) {
  const Robot robot = load("atlas.urdf", true);
  const Program<double> program = trace<double>("aba", robot.model);
  const CodePlan plan = plan_code(program, robot.model, Structure::Unrolled, Dialect());
  std::vector<int> statements;
  for (std::size_t id = 0; id < plan.is_op.size(); ++id) {
    const Node<double>& n = program.graph.nodes[id];
    EXPECT_EQ(plan.is_op[id], plan.live[id] && n.op != Op::Const && n.op != Op::Input &&
                                  n.op != Op::Result && n.op != Op::Sin && n.op != Op::Cos)
        << id;
    if (plan.is_op[id]) statements.push_back(static_cast<int>(id));
  }
  std::vector<int> in_sections;
  for (std::size_t s = 0; s < plan.sections.size(); ++s) {
    const Section& section = plan.sections[s];
    ASSERT_FALSE(section.ops.empty());
    for (const int id : section.ops) {
      EXPECT_EQ(program.graph.nodes[id].body, section.body);
      EXPECT_EQ(program.graph.nodes[id].pass, section.pass);
      in_sections.push_back(id);
    }
    if (s > 0) {
      EXPECT_TRUE(plan.sections[s - 1].body != section.body ||
                  plan.sections[s - 1].pass != section.pass);
    }
  }
  EXPECT_EQ(in_sections, statements);
  EXPECT_GT(plan.sections.size(), static_cast<std::size_t>(2 * robot.model.nbodies));
  EXPECT_TRUE(plan.groups.empty());
  EXPECT_FALSE(plan.lanes);
}

// A shared function computes sections of one shape, each with its row of constants and its
// own outputs in w.
TEST(Plan, SharedFunctionsServeSectionsOfOneShape) {
  const Robot robot = load("atlas.urdf", true);
  const Program<double> program = trace<double>("crba", robot.model);
  const CodePlan plan = plan_code(program, robot.model, Structure::Shared, Dialect());
  ASSERT_FALSE(plan.groups.empty());
  std::vector<bool> w_used(static_cast<std::size_t>(plan.w_size), false);
  for (std::size_t g = 0; g < plan.groups.size(); ++g) {
    const std::vector<int>& members = plan.groups[g];
    ASSERT_GE(members.size(), 2u);
    const Section& first = plan.sections[members.front()];
    EXPECT_GE(first.ops.size(), min_shared_operations);
    for (std::size_t k = 0; k < members.size(); ++k) {
      const Section& s = plan.sections[members[k]];
      EXPECT_EQ(s.group, static_cast<int>(g));
      EXPECT_EQ(s.instance, static_cast<int>(k));
      EXPECT_EQ(s.shape, first.shape);
      EXPECT_EQ(s.constants.size(), first.constants.size());
      for (std::size_t j = 0; j < s.ops.size(); ++j)
        EXPECT_EQ(program.graph.nodes[s.ops[j]].op, program.graph.nodes[first.ops[j]].op);
      for (std::size_t o = 0; o < s.outputs.size(); ++o) {
        ASSERT_LT(s.w + o, w_used.size());
        EXPECT_FALSE(w_used[s.w + o]) << "w[" << s.w + o << "] twice";
        w_used[s.w + o] = true;
      }
    }
  }
  EXPECT_TRUE(std::all_of(w_used.begin(), w_used.end(), [](bool used) { return used; }));
}

// solo12's four legs: blocks of sections of one pass at one depth, lane by lane the same
// operation; every statement and block is emitted once.
TEST(Plan, LaneBlocksHoldTheSameOperationsOfLimbsAtOneDepth) {
  const Robot robot = load("solo12.urdf", true);
  const Program<double> program = trace<double>("rnea", robot.model);
  const CodePlan plan = plan_code(program, robot.model, Structure::Lanes, Dialect());
  ASSERT_TRUE(plan.lanes);
  ASSERT_FALSE(plan.blocks.empty());
  std::set<int> in_blocks;
  for (const LaneBlock& block : plan.blocks) {
    ASSERT_GE(block.members.size(), 2u);
    const Section& first = plan.sections[block.members.front()];
    std::set<int> bodies;
    for (const int member : block.members) {
      const Section& s = plan.sections[member];
      EXPECT_EQ(s.pass, first.pass);
      EXPECT_EQ(depth(robot.model, s.body), depth(robot.model, first.body));
      bodies.insert(s.body);
      ASSERT_EQ(s.ops.size(), block.in_lanes.size());
      for (std::size_t k = 0; k < s.ops.size(); ++k) {
        EXPECT_EQ(program.graph.nodes[s.ops[k]].op, program.graph.nodes[first.ops[k]].op);
        if (block.in_lanes[k]) in_blocks.insert(s.ops[k]);
      }
    }
    EXPECT_EQ(bodies.size(), block.members.size());
  }
  std::multiset<int> emitted, blocks;
  for (const int unit : plan.order) (unit >= 0 ? emitted : blocks).insert(unit);
  for (std::size_t id = 0; id < plan.is_op.size(); ++id) {
    if (!plan.is_op[id]) continue;
    const int node = static_cast<int>(id);
    EXPECT_EQ(emitted.count(node), in_blocks.count(node) ? 0u : 1u) << id;
  }
  EXPECT_EQ(blocks.size(), plan.blocks.size());
  EXPECT_EQ(std::set<int>(blocks.begin(), blocks.end()).size(), plan.blocks.size());
}

// Batches store their outputs from lanes, so no kernel writes an output in place there.
TEST(Plan, OnlyScalarCodeLetsKernelsWriteOutputsInPlace) {
  const Robot robot = load("ur5.urdf");
  // every loop a kernel call (symbolic_test: its dqdd_dq is written by the kernel)
  const Program<double> program = trace<double>("aba_derivatives", robot.model, true, 0);
  ASSERT_FALSE(program.graph.calls.empty());
  const CodePlan scalar = plan_code(program, robot.model, Structure::Auto, Dialect());
  EXPECT_TRUE(std::find(scalar.output_in_place.begin(), scalar.output_in_place.end(), true) !=
              scalar.output_in_place.end());
  struct Batch : Dialect {
    int lanes() const override { return 4; }
    bool lane_blocks() const override { return false; }
  } batch;
  const CodePlan lanes = plan_code(program, robot.model, Structure::Auto, batch);
  EXPECT_TRUE(std::none_of(lanes.output_in_place.begin(), lanes.output_in_place.end(),
                           [](bool in_place) { return in_place; }));
  ASSERT_EQ(lanes.call_arrays.size(), program.graph.calls.size());
}

}  // namespace
