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
#include "dyngen/configuration.hpp"
#include "dyngen/constrained.hpp"
#include "dyngen/contact_derivatives.hpp"
#include "dyngen/crba.hpp"
#include "dyngen/frames.hpp"
#include "dyngen/minv.hpp"
#include "dyngen/rnea.hpp"
#include "dyngen/regressor.hpp"
#include "dyngen/rnea_derivatives.hpp"

namespace dyngen {

/// The length of an array for a model: `count` times 1, nq, nv, nv * nv, nc (the constraints'
/// rows) or nc * nv, and times the number of frames for an array with an entry per frame (a frame's
/// Jacobian is 6 x nv).
struct Extent {
  enum Size { One, Nq, Nv, NvNv, Nc, NcNv };
  Size size = One;
  int count = 1;
  bool per_frame = false;
  bool per_body = false;

  friend bool operator==(const Extent&, const Extent&) = default;
};

inline std::size_t extent_size(const Extent& e, int nq, int nv, int nframes, int nbodies, int nc) {
  const std::size_t n = static_cast<std::size_t>(nv);
  const std::size_t size = e.size == Extent::One    ? 1
                           : e.size == Extent::Nq   ? static_cast<std::size_t>(nq)
                           : e.size == Extent::Nv   ? n
                           : e.size == Extent::NvNv ? n * n
                           : e.size == Extent::Nc   ? static_cast<std::size_t>(nc)
                                                    : static_cast<std::size_t>(nc) * n;
  return size * static_cast<std::size_t>(e.count) *
         (e.per_frame ? static_cast<std::size_t>(nframes) : 1) *
         (e.per_body ? static_cast<std::size_t>(nbodies) : 1);
}

template <class S>
std::size_t extent_size(const Extent& e, const Model<S>& model) {
  return extent_size(e, model.nq, model.nv, static_cast<int>(model.frames.size()), model.nbodies,
                     model.nc);
}

inline constexpr Extent length_nq{Extent::Nq}, length_nv{Extent::Nv}, length_nv_nv{Extent::NvNv},
    length_nc{Extent::Nc}, length_nc_nv{Extent::NcNv};

/// An array of an algorithm's signature: its name (the same name means the same quantity in
/// every algorithm), length and meaning, as the generated header documents it. Per frame f of
/// model.frames, in their order.
struct ArraySpec {
  std::string_view name;
  Extent extent;
  std::string_view meaning;
};

inline constexpr ArraySpec q_array{"q", length_nq, "joint positions: rad (revolute), m (prismatic)"};
inline constexpr ArraySpec v_array{"v", length_nv, "joint velocities"};
inline constexpr ArraySpec a_array{"a", length_nv, "joint accelerations (input of rnea)"};
inline constexpr ArraySpec tau_array{"tau", length_nv, "joint forces: N m (revolute), N (prismatic)"};
inline constexpr ArraySpec qdd_array{"qdd", length_nv, "joint accelerations (output of aba)"};
inline constexpr ArraySpec M_array{"M", length_nv_nv,
                                   "joint-space mass matrix, row-major, both triangles: M[i * nv + j]"};
inline constexpr ArraySpec g_array{"g", length_nv, "generalised gravity: tau at v = 0, a = 0"};
inline constexpr ArraySpec dtau_dq_array{
    "dtau_dq", length_nv_nv,
    "d tau / dq, row-major: dtau_dq[i * nv + j] = d tau_i / dq_j (free joints: tangent directions)"};
inline constexpr ArraySpec dtau_dv_array{"dtau_dv", length_nv_nv,
                                         "d tau / dv, row-major: dtau_dv[i * nv + j] = d tau_i / dv_j"};
inline constexpr ArraySpec Minv_array{"Minv", length_nv_nv,
                                      "inverse of the mass matrix, row-major, both triangles"};
inline constexpr ArraySpec dqdd_dq_array{
    "dqdd_dq", length_nv_nv,
    "d qdd / dq, row-major: dqdd_dq[i * nv + j] = d qdd_i / dq_j (free joints: tangent directions)"};
inline constexpr ArraySpec dqdd_dv_array{"dqdd_dv", length_nv_nv,
                                         "d qdd / dv, row-major: dqdd_dv[i * nv + j] = d qdd_i / dv_j"};
inline constexpr ArraySpec h_array{"h", length_nv,
                                   "nonlinear effects (Coriolis, centrifugal, gravity): tau at a = 0"};
inline constexpr ArraySpec R_array{
    "R", {Extent::One, 9, true},
    "each frame's rotation, row-major: R[9 f + 3 i + j]; its columns are the frame's axes in "
    "base coordinates"};
inline constexpr ArraySpec p_array{"p", {Extent::One, 3, true},
                                   "each frame's origin in base coordinates: p[3 f + i]"};
inline constexpr ArraySpec J_array{
    "J", {Extent::Nv, 6, true},
    "each frame's Jacobian in base axes at the frame's origin, 6 x nv row-major, linear rows "
    "first: J[(6 f + i) * nv + j]"};
inline constexpr ArraySpec J_local_array{
    "J_local", {Extent::Nv, 6, true},
    "each frame's Jacobian in its own axes, 6 x nv row-major, linear rows first"};
inline constexpr ArraySpec Jdot_v_array{
    "Jdot_v", {Extent::One, 6, true},
    "each frame's acceleration at qdd = 0 (of its origin, then angular), base axes: "
    "Jdot_v[6 f + i]; the frame accelerates by J qdd + Jdot_v"};
inline constexpr ArraySpec Jdot_v_local_array{
    "Jdot_v_local", {Extent::One, 6, true},
    "each frame's acceleration at qdd = 0 in its own axes: J_local qdd + Jdot_v_local"};
inline constexpr ArraySpec lambda_array{
    "lambda", length_nc,
    "constraint forces on frame A, per constraint: the force at its origin (3d), then the "
    "moment about it (6d), base axes, N and N m"};
inline constexpr ArraySpec anchors_array{
    "anchors", length_nc,
    "each contact's reference placement for Baumgarte's kp, in lambda's layout: its origin, then "
    "for a surface contact the rotation vector w of its axes (R = exp([w])), base coordinates; "
    "a loop's entries are not read"};
inline constexpr ArraySpec dqdd_dtau_array{
    "dqdd_dtau", length_nv_nv, "d qdd / d tau, row-major: dqdd_dtau[i * nv + j] = d qdd_i / d tau_j"};
inline constexpr ArraySpec dlambda_dq_array{
    "dlambda_dq", length_nc_nv,
    "d lambda / dq, nc x nv row-major: dlambda_dq[r * nv + j] = d lambda_r / dq_j (free joints: "
    "tangent directions)"};
inline constexpr ArraySpec dlambda_dv_array{"dlambda_dv", length_nc_nv,
                                            "d lambda / dv, nc x nv row-major"};
inline constexpr ArraySpec dlambda_dtau_array{"dlambda_dtau", length_nc_nv,
                                              "d lambda / d tau, nc x nv row-major"};
inline constexpr ArraySpec v_plus_array{"v_plus", length_nv, "joint velocities after the impact"};
inline constexpr ArraySpec impulse_array{
    "impulse", length_nc, "constraint impulses on frame A, as lambda's forces, N s and N m s"};
inline constexpr ArraySpec c_array{"c", {Extent::One, 3}, "centre of mass, base coordinates"};
inline constexpr ArraySpec Jc_array{"Jc", {Extent::Nv, 3},
                                    "Jacobian of the centre of mass, 3 x nv row-major"};
inline constexpr ArraySpec Ag_array{
    "Ag", {Extent::Nv, 6},
    "centroidal momentum matrix, 6 x nv row-major: linear momentum, then angular momentum "
    "about the centre of mass, base axes"};
inline constexpr ArraySpec hg_array{"hg", {Extent::One, 6},
                                    "centroidal momentum Ag v (linear, then angular)"};

inline constexpr ArraySpec Y_array{
    "Y", {Extent::Nv, 10, false, true},
    "inertial-parameter regressor, nv x 10 nbodies row-major: Y[k * 10 nbodies + 10 i + p], "
    "with tau = Y pi + armature a for pi the bodies' standard parameters (m, m c, Ixx, Ixy, Iyy, "
    "Ixz, Iyz, Izz about the body's origin) in body order"};

inline constexpr ArraySpec q_plus_array{
    "q_plus", length_nq,
    "q moved by the tangent vector v for unit time (free joints: the pose times exp(v) in its "
    "body frame; ball joints: the rotation times exp(v))"};
inline constexpr ArraySpec q_target_array{"q_target", length_nq, "joint positions to reach from q"};
inline constexpr ArraySpec delta_array{
    "delta", length_nv,
    "the tangent vector from q to q_target: integrate(q, delta) = q_target, rotations the "
    "shorter way round"};

inline constexpr ArraySpec dintegrate_dq_array{
    "dintegrate_dq", length_nv_nv,
    "d q_plus / dq in tangent coordinates, row-major, block diagonal (Pinocchio's dIntegrate, "
    "ARG0)"};
inline constexpr ArraySpec dintegrate_dv_array{
    "dintegrate_dv", length_nv_nv,
    "d q_plus / dv in tangent coordinates, row-major, block diagonal (Pinocchio's dIntegrate, "
    "ARG1)"};
inline constexpr ArraySpec ddifference_dq_array{
    "ddifference_dq", length_nv_nv,
    "d delta / dq in tangent coordinates, row-major, block diagonal (Pinocchio's dDifference, "
    "ARG0)"};
inline constexpr ArraySpec ddifference_dq_target_array{
    "ddifference_dq_target", length_nv_nv,
    "d delta / dq_target in tangent coordinates, row-major, block diagonal (Pinocchio's "
    "dDifference, ARG1)"};

template <class S>
using AlgorithmInputs = std::span<const std::span<const S>>;
template <class S>
using AlgorithmOutputs = std::span<const std::span<S>>;

/// How an algorithm's work grows with the robot: linearly in the bodies; with the sum over
/// joints of nv times depth (carrying columns up the tree); with nv^2 times the depth
/// (filling a dense nv x nv matrix); or with the frames' Jacobian columns, a column per degree
/// of freedom between each frame and the base, in an output of 6 nv entries per frame.
enum class Growth { Linear, ColumnSteps, Dense, FrameColumns };

/// What an algorithm needs of the model beyond its tree: frames (Model::frames) or constraints
/// (Model::constraints, --contacts); the generator leaves out an algorithm whose model lacks it.
enum class Needs { Tree, Constraints };

/// Which of the three quantities that every rigid-body dynamics library computes an algorithm
/// gives, so that dyngen can compare ways of computing them without naming algorithms: bench/
/// times each against the peers (MuJoCo, KDL) that compute it too, and dyngen report measures
/// forward dynamics also as qdd = M^-1 (tau - h) by LDL^T, with M from the MassMatrix entry and
/// h from the InverseDynamics entry at a = 0 (CRBA+LDLT). Each fixes the signature, which the
/// table's test checks: InverseDynamics (q, v, a) -> tau, MassMatrix (q) -> M and
/// ForwardDynamics (q, v, tau) -> qdd.
enum class Computes { Other, InverseDynamics, MassMatrix, ForwardDynamics };

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
  // the report's heading; empty: the name and the outputs, "minv (Minv)"
  std::string_view title = {};
  Computes computes = Computes::Other;
  bool in_default_set = false;  // generated when --algorithms is not given
  Needs needs = Needs::Tree;
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
       },
       "RNEA (inverse dynamics, tau)", Computes::InverseDynamics, true},
      {"crba", "Mass matrix M(q) (composite rigid bodies).", {q_array}, {M_array},
       Growth::ColumnSteps, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) { crba<S>(m, ws, in[0], out[0]); },
       "CRBA (mass matrix, M)", Computes::MassMatrix, true},
      {"aba",
       "Forward dynamics (articulated bodies): qdd = M(q)^-1 (tau - C(q, v) v - g(q)).",
       {q_array, v_array, tau_array}, {qdd_array},
       Growth::Linear, true,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         aba<S>(m, ws, in[0], in[1], in[2], out[0]);
       },
       "ABA (forward dynamics, qdd)", Computes::ForwardDynamics, true},
      {"gravity",
       "Generalised gravity g(q) = rnea(q, 0, 0), from each subtree's mass and first moment.",
       {q_array}, {g_array},
       Growth::Linear, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) { gravity<S>(m, ws, in[0], out[0]); }},
      {"nle", "Nonlinear effects h(q, v) = C(q, v) v + g(q): rnea at a = 0.", {q_array, v_array},
       {h_array},
       Growth::Linear, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         nle<S>(m, ws, in[0], in[1], out[0]);
       }},
      {"minv",
       "Inverse of the mass matrix M(q)^-1 (CRBA, then L^T D L along the tree's branches).",
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
      {"frame_placements",
       "Placements of the frames: rotation R and origin p in base coordinates.", {q_array},
       {R_array, p_array},
       Growth::Linear, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         frame_placements<S>(m, ws, in[0], out[0], out[1]);
       }},
      {"frame_jacobians", "Jacobians of the frames, in base axes at each frame's origin.",
       {q_array}, {J_array},
       Growth::FrameColumns, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         frame_jacobians<S>(m, ws, in[0], JacobianAxes::World, out[0]);
       }},
      {"frame_jacobians_local", "Jacobians of the frames, in each frame's own axes.",
       {q_array}, {J_local_array},
       Growth::FrameColumns, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         frame_jacobians<S>(m, ws, in[0], JacobianAxes::Local, out[0]);
       }},
      {"frame_accelerations",
       "Bias accelerations Jdot v of the frames at qdd = 0, in base axes.",
       {q_array, v_array}, {Jdot_v_array},
       Growth::Linear, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         frame_bias_accelerations<S>(m, ws, in[0], in[1], JacobianAxes::World, out[0]);
       }},
      {"frame_accelerations_local",
       "Bias accelerations Jdot v of the frames at qdd = 0, in each frame's own axes.",
       {q_array, v_array}, {Jdot_v_local_array},
       Growth::Linear, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         frame_bias_accelerations<S>(m, ws, in[0], in[1], JacobianAxes::Local, out[0]);
       }},
      {"com", "Centre of mass c(q) and its Jacobian.", {q_array}, {c_array, Jc_array},
       Growth::Linear, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         com<S>(m, ws, in[0], out[0], out[1]);
       }},
      {"centroidal",
       "Centroidal momentum matrix Ag(q) and momentum hg = Ag v (Orin, Goswami & Lee 2013).",
       {q_array, v_array}, {Ag_array, hg_array},
       Growth::Linear, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         centroidal<S>(m, ws, in[0], in[1], out[0], out[1]);
       }},
      {"regressor",
       "Inertial-parameter regressor Y(q, v, a): tau = Y pi + armature a, linear in the bodies' "
       "standard parameters pi.",
       {q_array, v_array, a_array}, {Y_array},
       Growth::ColumnSteps, false,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         regressor<S>(m, ws, in[0], in[1], in[2], out[0]);
       }},
      {"integrate",
       "The configuration reached from q along the tangent vector v in unit time: q (+) v "
       "(Pinocchio's integrate).",
       {q_array, v_array}, {q_plus_array},
       Growth::Linear, false,
       [](const Model<S>& m, Workspace<S>&, In in, Out out) {
         integrate<S>(m, in[0], in[1], out[0]);
       }},
      {"difference",
       "The tangent vector from q to q_target, with integrate(q, delta) = q_target (Pinocchio's "
       "difference).",
       {q_array, q_target_array}, {delta_array},
       Growth::Linear, false,
       [](const Model<S>& m, Workspace<S>&, In in, Out out) {
         difference<S>(m, in[0], in[1], out[0]);
       }},
      {"integrate_derivatives",
       "Jacobians of integrate(q, v) by q and by v, in tangent coordinates (Pinocchio's "
       "dIntegrate).",
       {q_array, v_array}, {dintegrate_dq_array, dintegrate_dv_array},
       Growth::Dense, false,
       [](const Model<S>& m, Workspace<S>&, In in, Out out) {
         integrate_derivatives<S>(m, in[0], in[1], out[0], out[1]);
       }},
      {"difference_derivatives",
       "Jacobians of difference(q, q_target) by q and by q_target, in tangent coordinates "
       "(Pinocchio's dDifference).",
       {q_array, q_target_array}, {ddifference_dq_array, ddifference_dq_target_array},
       Growth::Dense, false,
       [](const Model<S>& m, Workspace<S>&, In in, Out out) {
         difference_derivatives<S>(m, in[0], in[1], out[0], out[1]);
       }},
      {"contact_dynamics",
       "Forward dynamics under the constraints (--contacts): M qdd + h = tau + J^T lambda with "
       "J qdd + Jdot v = -kd J v - kp e (Baumgarte).",
       {q_array, v_array, tau_array}, {qdd_array, lambda_array},
       Growth::Dense, true,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         contact_dynamics<S>(m, ws, in[0], in[1], in[2], out[0], out[1]);
       },
       {}, Computes::Other, false, Needs::Constraints},
      {"contact_dynamics_anchored",
       "contact_dynamics with Baumgarte's kp acting on the contacts too: e is each contact "
       "frame's placement from its anchor (frame_placements where it touched down).",
       {q_array, v_array, tau_array, anchors_array}, {qdd_array, lambda_array},
       Growth::Dense, true,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         contact_dynamics<S>(m, ws, in[0], in[1], in[2], out[0], out[1], in[3]);
       },
       {}, Computes::Other, false, Needs::Constraints},
      {"contact_dynamics_derivatives",
       "Derivatives of contact_dynamics: d qdd and d lambda by dq, dv and d tau at (q, v, tau).",
       {q_array, v_array, tau_array},
       {dqdd_dq_array, dqdd_dv_array, dqdd_dtau_array, dlambda_dq_array, dlambda_dv_array,
        dlambda_dtau_array},
       Growth::Dense, true,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         contact_dynamics_derivatives<S>(m, ws, in[0], in[1], in[2], out[0], out[1], out[2],
                                         out[3], out[4], out[5]);
       },
       {}, Computes::Other, false, Needs::Constraints},
      {"contact_dynamics_anchored_derivatives",
       "Derivatives of contact_dynamics_anchored by q, v and tau (the anchors held fixed).",
       {q_array, v_array, tau_array, anchors_array},
       {dqdd_dq_array, dqdd_dv_array, dqdd_dtau_array, dlambda_dq_array, dlambda_dv_array,
        dlambda_dtau_array},
       Growth::Dense, true,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         contact_dynamics_derivatives<S>(m, ws, in[0], in[1], in[2], out[0], out[1], out[2],
                                         out[3], out[4], out[5], in[3]);
       },
       {}, Computes::Other, false, Needs::Constraints},
      {"impulse_dynamics",
       "The impulse of the constraints at impact (--contacts), from the velocities v before it: "
       "M (v_plus - v) = J^T impulse with J v_plus = -e J v (e: --restitution).",
       {q_array, v_array}, {v_plus_array, impulse_array},
       Growth::Dense, true,
       [](const Model<S>& m, Workspace<S>& ws, In in, Out out) {
         impulse_dynamics<S>(m, ws, in[0], in[1], out[0], out[1]);
       },
       {}, Computes::Other, false, Needs::Constraints},
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

/// The entry that computes c, or nullptr (for Other too).
template <class S>
const AlgorithmSpec<S>* find_algorithm(Computes c) {
  for (const AlgorithmSpec<S>& a : algorithm_table<S>())
    if (a.computes == c && c != Computes::Other) return &a;
  return nullptr;
}

}  // namespace dyngen
