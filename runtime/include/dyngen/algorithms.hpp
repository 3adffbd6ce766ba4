// Every algorithm by name, with the arrays it reads and writes: one entry per algorithm. The
// generator traces and prints the entries it is asked for, the generated check calls the same
// entries on the runtime, and dyngen's other commands list them.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include "dyngen/aba.hpp"
#include "dyngen/aba_derivatives.hpp"
#include "dyngen/crba.hpp"
#include "dyngen/minv.hpp"
#include "dyngen/rnea.hpp"
#include "dyngen/rnea_derivatives.hpp"

namespace dyngen {

/// The length of an array for a model: nq, nv or nv * nv.
enum class Extent { Nq, Nv, NvNv };

inline std::size_t extent_size(Extent e, int nq, int nv) {
  const std::size_t n = static_cast<std::size_t>(nv);
  return e == Extent::Nq ? static_cast<std::size_t>(nq) : e == Extent::Nv ? n : n * n;
}

/// An array of an algorithm's signature: its name (the same name means the same quantity in
/// every algorithm), length and meaning, as the generated header documents it.
struct ArraySpec {
  std::string_view name;
  Extent extent;
  std::string_view meaning;
};

inline constexpr ArraySpec q_array{"q", Extent::Nq, "joint positions: rad (revolute), m (prismatic)"};
inline constexpr ArraySpec v_array{"v", Extent::Nv, "joint velocities"};
inline constexpr ArraySpec a_array{"a", Extent::Nv, "joint accelerations (input of rnea)"};
inline constexpr ArraySpec tau_array{"tau", Extent::Nv, "joint forces: N m (revolute), N (prismatic)"};
inline constexpr ArraySpec qdd_array{"qdd", Extent::Nv, "joint accelerations (output of aba)"};
inline constexpr ArraySpec M_array{"M", Extent::NvNv,
                                   "joint-space mass matrix, row-major, both triangles: M[i * nv + j]"};
inline constexpr ArraySpec g_array{"g", Extent::Nv, "generalised gravity: tau at v = 0, a = 0"};
inline constexpr ArraySpec dtau_dq_array{
    "dtau_dq", Extent::NvNv,
    "d tau / dq, row-major: dtau_dq[i * nv + j] = d tau_i / dq_j (free joints: tangent directions)"};
inline constexpr ArraySpec dtau_dv_array{"dtau_dv", Extent::NvNv,
                                         "d tau / dv, row-major: dtau_dv[i * nv + j] = d tau_i / dv_j"};
inline constexpr ArraySpec Minv_array{"Minv", Extent::NvNv,
                                      "inverse of the mass matrix, row-major, both triangles"};
inline constexpr ArraySpec dqdd_dq_array{
    "dqdd_dq", Extent::NvNv,
    "d qdd / dq, row-major: dqdd_dq[i * nv + j] = d qdd_i / dq_j (free joints: tangent directions)"};
inline constexpr ArraySpec dqdd_dv_array{"dqdd_dv", Extent::NvNv,
                                         "d qdd / dv, row-major: dqdd_dv[i * nv + j] = d qdd_i / dv_j"};
inline constexpr ArraySpec h_array{"h", Extent::Nv,
                                   "nonlinear effects (Coriolis, centrifugal, gravity): tau at a = 0"};

template <class S>
using AlgorithmInputs = std::span<const std::span<const S>>;
template <class S>
using AlgorithmOutputs = std::span<const std::span<S>>;

/// How an algorithm's work grows with the robot: linearly in the bodies; with the sum over
/// joints of nv times depth (carrying columns up the tree); or with nv^2 times the depth
/// (filling a dense nv x nv matrix).
enum class Growth { Linear, ColumnSteps, Dense };

/// One algorithm: call(model, ws, inputs, outputs) with the arrays in the order listed, each of
/// its extent's length. Every algorithm reads q first.
template <class S>
struct AlgorithmSpec {
  std::string_view name;     // of the runtime function and the generated one
  std::string_view summary;  // one sentence for the generated header
  std::vector<ArraySpec> inputs, outputs;
  Growth growth;
  bool divides_by_pivots;    // ABA's precondition: every joint moves some inertia
  void (*call)(const Model<S>&, Workspace<S>&, AlgorithmInputs<S>, AlgorithmOutputs<S>);
};

template <class S>
const std::vector<AlgorithmSpec<S>>& algorithm_table() {
  using In = AlgorithmInputs<S>;
  using Out = AlgorithmOutputs<S>;
  static const std::vector<AlgorithmSpec<S>> table{
      {"rnea", "Inverse dynamics (recursive Newton-Euler): tau = M(q) a + C(q, v) v + g(q).",
       {q_array, v_array, a_array}, {tau_array},
       Growth::Linear, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         rnea<S>(m, ws, in[0], in[1], in[2], out[0]);
       }},
      {"crba", "Mass matrix M(q) (composite rigid bodies).", {q_array}, {M_array},
       Growth::ColumnSteps, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) { crba<S>(m, ws, in[0], out[0]); }},
      {"aba",
       "Forward dynamics (articulated bodies): qdd = M(q)^-1 (tau - C(q, v) v - g(q)).",
       {q_array, v_array, tau_array}, {qdd_array},
       Growth::Linear, true,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         aba<S>(m, ws, in[0], in[1], in[2], out[0]);
       }},
      {"gravity", "Generalised gravity g(q): rnea at v = 0 and a = 0.", {q_array}, {g_array},
       Growth::Linear, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) { gravity<S>(m, ws, in[0], out[0]); }},
      {"nle", "Nonlinear effects h(q, v) = C(q, v) v + g(q): rnea at a = 0.", {q_array, v_array},
       {h_array},
       Growth::Linear, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         nle<S>(m, ws, in[0], in[1], out[0]);
       }},
      {"minv", "Inverse of the mass matrix M(q)^-1 (articulated-body recursion, no factorisation).",
       {q_array}, {Minv_array},
       Growth::Dense, true,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) { minv<S>(m, ws, in[0], out[0]); }},
      {"rnea_derivatives",
       "Derivatives of inverse dynamics: d tau / dq and d tau / dv at (q, v, a) (d tau / da is M).",
       {q_array, v_array, a_array}, {dtau_dq_array, dtau_dv_array},
       Growth::ColumnSteps, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         rnea_derivatives<S>(m, ws, in[0], in[1], in[2], out[0], out[1]);
       }},
      {"aba_derivatives",
       "Derivatives of forward dynamics: d qdd / dq, d qdd / dv and d qdd / d tau = M^-1 at "
       "(q, v, tau).",
       {q_array, v_array, tau_array}, {dqdd_dq_array, dqdd_dv_array, Minv_array},
       Growth::Dense, true,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         aba_derivatives<S>(m, ws, in[0], in[1], in[2], out[0], out[1], out[2]);
       }},
  };
  return table;
}

/// The entry named name, or nullptr.
template <class S>
const AlgorithmSpec<S>* find_algorithm(std::string_view name) {
  for (const AlgorithmSpec<S>& a : algorithm_table<S>())
    if (a.name == name) return &a;
  return nullptr;
}

}  // namespace dyngen
