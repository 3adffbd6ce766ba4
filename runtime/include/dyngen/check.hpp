// The bit-for-bit check of a function against the runtime's algorithm of the same name
// (GoogleTest): seeded random and extreme states, every output compared bit for bit (+0 and -0
// count as equal), the first difference reported with its inputs. Every generated package's
// check (templates/check.cpp.in) calls it with its functions; it is a header of the runtime so
// that the check is the same code for every package.
//
// This header declares the comparison, and includes its definitions (check_impl.hpp) unless
// DYNGEN_CHECK_EXTERN is defined: a build of many packages' checks compiles them once, for
// double and float, and links them (as dyngen's tests do in tests/support/check_instances.cpp),
// and each check then parses no more than GoogleTest and the model.
#pragma once

#include <vector>

#include "dyngen/model.hpp"

namespace dyngen::check {

/// The values of an algorithm's input or output arrays, in the table's order.
template <class S>
using Arrays = std::vector<std::vector<S>>;

/// y = f(x), the arrays in the order of the algorithm's table entry.
template <class S>
using Function = void (*)(const Arrays<S>& x, Arrays<S>& y);

/// y = f(count, x) over `count` states, each array holding one state after the other.
template <class S>
using ManyFunction = void (*)(long count, const Arrays<S>& x, Arrays<S>& y);

/// The states a check runs: `random` seeded random ones, then `extreme` ones (angles from 10 to
/// 1e6 rad, speeds up to 1e3 rad/s, forces up to 1e4).
struct States {
  int random, extreme;
  constexpr int all() const { return random + extreme; }
};

/// Runs the runtime's `name` and `generated` on every state and compares their outputs.
template <class S>
void bit_for_bit(const Model<S>& model, States states, const char* name, Function<S> generated);

/// Runs the runtime's `name` on every state and compares it with each lane of `batch` (`lanes`
/// states a call, entry i of state l at [i * lanes + l]), and, on 2 lanes + 1 states, with `many`
/// (the states one after the other; the last batch is a partial one).
template <class S>
void batch_bit_for_bit(const Model<S>& model, States states, int lanes, const char* name,
                       Function<S> batch, ManyFunction<S> many);

/// The model's sizes are nq and nv, and its velocity names the nv of `names`.
template <class S>
void model_matches(const Model<S>& model, int nq, int nv, const char* const* names);

}  // namespace dyngen::check

#ifndef DYNGEN_CHECK_EXTERN
#include "dyngen/check_impl.hpp"
#endif
