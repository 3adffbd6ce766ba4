// Schedules a traced program and prints it as C++: live nodes in creation order (the
// algorithm's order), one operation per statement, grouped and labelled by body and pass.
#pragma once

#include <string>

#include "dyngen/model.hpp"
#include "trace.hpp"

namespace dyngen::gen {

/// Operations by kind.
struct OpCounts {
  long add = 0, mul = 0, div = 0, neg = 0, sin = 0, cos = 0;
  long total() const { return add + mul + div + neg + sin + cos; }
};

/// "add 12, mul 30, div 0, neg 2, sin 1, cos 1"
std::string to_string(const OpCounts& c);

/// Counts the operations that reach an output (all of them for an unsimplified graph, whose
/// nodes the runtime all computes).
template <class T>
OpCounts count_ops(const Program<T>& program, bool live_only = true);

/// A C++ literal that reads back to the same bits: shortest round trip, with a suffix for
/// float and parentheses when negative.
std::string literal(double value);
std::string literal(float value);

/// The body of the emitted function (statements and output stores), indented.
template <class T>
std::string emit_body(const Program<T>& program, const Model<double>& model);

/// The body of joint_trig(q, trig): dyngen::sincos of every revolute joint's angle.
std::string emit_joint_trig(const Model<double>& model);

/// "revolute +z", "prismatic axis (0.6, 0, 0.8)"
std::string joint_description(const Model<double>& model, int body);

}  // namespace dyngen::gen
