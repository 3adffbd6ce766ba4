// The operations of one call of an algorithm of the hand-written planar chain
// (planar_reference.hpp), counted with op_counter.hpp's Counted: for work_counts.cpp and
// call_counts.cpp.
#pragma once

#include <vector>

#include "dyngen/model.hpp"
#include "dyngen/numerics/random.hpp"
#include "op_counter.hpp"
#include "planar_reference.hpp"
#include "algorithm.hpp"
#include "trace.hpp"

namespace dyngen::bench {

/// The counts of algorithm a at one random state; the code has no branch on values, so any
/// state gives them.
inline OpTally count_planar_chain(const Model<double>& model, Algorithm a) {
  PlanarChain<Counted> chain(model);
  numerics::Random rng(1);
  const numerics::State s = numerics::random_state(model, rng);
  const std::vector<Counted> q(s.q.begin(), s.q.end()), qd(s.qd.begin(), s.qd.end()),
      qdd(s.qdd.begin(), s.qdd.end()), tau(s.tau.begin(), s.tau.end());
  std::vector<Counted> out(model.nv * model.nv);
  const CountScope scope;
  switch (a) {
    case Computes::Other: break;
    case Computes::InverseDynamics: chain.rnea(q.data(), qd.data(), qdd.data(), out.data()); break;
    case Computes::MassMatrix: chain.crba(q.data(), out.data()); break;
    case Computes::ForwardDynamics: chain.aba(q.data(), qd.data(), tau.data(), out.data()); break;
  }
  return scope.counts();
}

}  // namespace dyngen::bench
