// dyngen_work_counts (README.md, "Work counts and instruction counts"): deterministic operation
// counts of one call of RNEA, CRBA and ABA, for planar and spatial chains of 2 to 128 links
// (make_chain's, seed = links, as dyngen_bench's) and every URDF in tests/models with a fixed and
// a floating base:
//   generated:    the simplified trace's live operations, as dyngen's banner counts them;
//   runtime:      the unsimplified trace, every operation the runtime performs;
//   hand-written: the planar chains only, planar_reference.hpp run on op_counter.hpp's Counted;
//   seed:         the chapter's work counts, n link visits for RNEA and ABA and n(n+1)/2 joint
//                 pairs for CRBA, with n the degrees of freedom.
// Then forward dynamics both ways on the chains: generated ABA against generated CRBA, the bias
// h = RNEA(q, v, 0) and a dense LDL^T solve of M qdd = tau - h; and for ur5, iiwa14, solo12 and
// atlas, rnea_derivatives' operations by pass beside RNEA's and ABA's; and for the arms with
// rounded rotations, their functions as read, with the rotations cut to the joints' twists (the
// least any body frames leave) and snapped. Writes work_counts.md and
// work_counts.json into OUTPUT_DIR and prints the Markdown; progress goes to stderr.
//
// usage: dyngen_work_counts OUTPUT_DIR
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "dyngen/dyngen.hpp"
#include "emit.hpp"
#include "generate.hpp"
#include "op_counter.hpp"
#include "planar_counts.hpp"
#include "robot.hpp"
#include "test_support.hpp"
#include "trace.hpp"

namespace dyngen::bench {
namespace {


constexpr int chain_links[] = {WORK_COUNT_LINKS};
const std::vector<Algorithm>& algorithms = compared_algorithms();

/// Operations by kind, as the counting scalar tallies them; traces have no sqrt, so theirs is 0.
using Kinds = OpTally;

Kinds kinds(const gen::OpCounts& c) { return {c.add, c.mul, c.div, c.neg, c.sin, c.cos, 0}; }

Kinds operator+(const Kinds& a, const Kinds& b) {
  return {a.add + b.add, a.mul + b.mul, a.div + b.div,  a.neg + b.neg,
          a.sin + b.sin, a.cos + b.cos, a.sqrt + b.sqrt};
}

/// One function of one model.
struct Row {
  std::string model;  // planar_chain8, ur5, ...
  std::string kind;   // planar_chain, spatial_chain or robot
  std::string base;   // fixed or floating
  int nv;
  Algorithm algorithm;
  long seed_work;
  Kinds generated, runtime;
  std::optional<Kinds> hand_written;
};

/// Forward dynamics of one chain, both ways.
struct DenseRow {
  std::string model;
  int nv;
  Kinds aba, crba, bias, crba_and_bias, solve;
};

/// Where rnea_derivatives' operations go, beside the value functions (generated code throughout).
struct DerivativeRow {
  std::string model, base;
  int nv;
  long rnea, aba, forward, backward, pairs, rnea_derivatives, aba_derivatives;
};

/// The robots of issue 13's targets.
constexpr const char* derivative_robots[] = {"ur5", "iiwa14", "solo12", "atlas"};

/// One function of an arm with rounded rotations, three ways.
struct FrameRow {
  std::string model, algorithm;
  long as_read, twists_only, snapped;
  double least_cos, most_cos;  // |cos alpha| of the twists within 1e-9 of a right angle
};

/// The arms whose URDFs write rounded rotations (issue 45), and the functions counted on them.
constexpr const char* rounded_arms[] = {"iiwa14", "panda"};
constexpr const char* frame_algorithms[] = {"rnea", "crba", "aba", "minv", "rnea_derivatives",
                                            "aba_derivatives"};

long seed_work(Algorithm a, long n) { return a == Computes::MassMatrix ? n * (n + 1) / 2 : n; }

/// Generated-code operations of the mass matrix and/or the bias h = RNEA(q, v, 0), traced into
/// one graph as one emitted function would compute them: with both, the sin, cos and joint
/// transforms of q are made once.
Kinds dense_trace_counts(const Model<double>& model, bool with_M, bool with_bias) {
  using Sym = gen::Sym<double>;
  gen::Program<double> program;
  program.graph = gen::Graph<double>(true);
  const gen::Recording<double> recording(program.graph);
  const Model<Sym> m = model.cast<Sym>();
  Workspace<Sym> ws(m);
  const int n = model.nv;
  std::vector<Sym> q, v;
  for (int i = 0; i < model.nq; ++i) q.push_back(Sym::node(program.graph.input("q", i)));
  for (int i = 0; i < n; ++i) v.push_back(Sym::node(program.graph.input("v", i)));
  if (with_M) {
    std::vector<Sym> M(n * n);
    crba<Sym>(m, ws, q, M);
    for (const Sym& x : M) program.stored.push_back(x.id);
  }
  if (with_bias) {
    std::vector<Sym> h(n);
    nle<Sym>(m, ws, q, v, h);
    for (const Sym& x : h) program.stored.push_back(x.id);
  }
  return kinds(gen::count_ops(program));
}

/// qdd = M^-1 (tau - h) by a dense LDL^T factorisation without pivoting (M symmetric positive
/// definite, row-major, its lower triangle read): one reciprocal per pivot, L_jk d_k formed once
/// per row.
template <class S>
std::vector<S> ldlt_solve(int n, std::vector<S> A, const std::vector<S>& tau,
                          const std::vector<S>& h) {
  std::vector<S> LD(n), inv_d(n), x(n);
  for (int j = 0; j < n; ++j) {
    S* Lj = &A[j * n];
    for (int k = 0; k < j; ++k) LD[k] = Lj[k] * A[k * n + k];
    S d = Lj[j];
    for (int k = 0; k < j; ++k) d = d - Lj[k] * LD[k];
    A[j * n + j] = d;
    inv_d[j] = S(1) / d;
    for (int i = j + 1; i < n; ++i) {
      S lij = A[i * n + j];
      for (int k = 0; k < j; ++k) lij = lij - A[i * n + k] * LD[k];
      A[i * n + j] = lij * inv_d[j];
    }
  }
  for (int i = 0; i < n; ++i) {
    x[i] = tau[i] - h[i];
    for (int k = 0; k < i; ++k) x[i] = x[i] - A[i * n + k] * x[k];
  }
  for (int i = 0; i < n; ++i) x[i] = x[i] * inv_d[i];
  for (int i = n - 2; i >= 0; --i)
    for (int k = i + 1; k < n; ++k) x[i] = x[i] - A[k * n + i] * x[k];
  return x;
}

/// The dense solve's operations, counted on the model's own M (the count does not depend on
/// the values; a wrong solve would, so it is checked against ABA).
Kinds dense_solve_counts(const Model<double>& model) {
  const int n = model.nv;
  numerics::Random rng(2);
  const numerics::State s = numerics::random_state(model, rng);
  Workspace<double> ws(model);
  std::vector<double> M(n * n), h(n), zero(n), qdd(n);
  crba<double>(model, ws, s.q, M);
  rnea<double>(model, ws, s.q, s.qd, zero, h);
  aba<double>(model, ws, s.q, s.qd, s.tau, qdd);
  const std::vector<Counted> Mc(M.begin(), M.end()), tau(s.tau.begin(), s.tau.end()),
      hc(h.begin(), h.end());
  const CountScope scope;
  const std::vector<Counted> x = ldlt_solve<Counted>(n, Mc, tau, hc);
  const Kinds counts = scope.counts();
  std::vector<double> solved;
  for (const Counted& xi : x) solved.push_back(xi.value);
  const double error = test::relative_error(test::to_eigen(solved), test::to_eigen(qdd));
  if (!(error < 1e-8))
    throw std::runtime_error(fmt::format("{}-DoF LDL^T solve differs from ABA by {}", n, error));
  return counts;
}

std::vector<Row> count_model(const std::string& name, const std::string& kind,
                             const std::string& base, const Model<double>& model) {
  std::fprintf(stderr, "  %s (%s base, %d DoF)\n", name.c_str(), base.c_str(), model.nv);
  std::vector<Row> rows;
  for (const Algorithm a : algorithms) {
    Row r{name, kind, base, model.nv, a, seed_work(a, model.nv), {}, {}, {}};
    r.generated = kinds(gen::count_ops(gen::trace<double>(algorithm_name(a), model, true)));
    r.runtime = kinds(gen::count_ops(gen::trace<double>(algorithm_name(a), model, false), false));
    if (kind == "planar_chain") r.hand_written = count_planar_chain(model, a);
    rows.push_back(r);
  }
  return rows;
}

/// add, mul, div and neg: sin and cos are the same few in every function of a robot.
long arithmetic(const gen::OpCounts& c) { return c.add + c.mul + c.div + c.neg; }

/// The generated code's arithmetic operations of one function of a model.
long arithmetic(const Model<double>& model, const char* algorithm) {
  return arithmetic(gen::count_ops(gen::trace<double>(algorithm, model)));
}

DerivativeRow count_derivatives(const std::string& name, const std::string& base,
                                const Model<double>& model) {
  auto total = [&](const char* algorithm) { return arithmetic(model, algorithm); };
  const auto by_pass = gen::count_ops_by_pass(gen::trace<double>("rnea_derivatives", model));
  auto pass = [&](Pass p) { return by_pass.count(p) ? arithmetic(by_pass.at(p)) : 0L; };
  DerivativeRow d{name, base, model.nv, total("rnea"), total("aba"), pass(Pass::Forward),
                  pass(Pass::Backward), pass(Pass::Pairs), 0, total("aba_derivatives")};
  for (const auto& [p, c] : by_pass) d.rnea_derivatives += arithmetic(c);
  return d;
}

/// The model with each joint rotation cut to what no choice of body frames removes: with every
/// 1-DoF joint's axis made z, a body's rotation becomes Rx(alpha), alpha the angle between its
/// joint's axis and its parent's (identity under the base or a joint without an axis). Offsets
/// and inertias are kept as read, so the count is a lower bound: real frames of the modified
/// Denavit-Hartenberg kind would add the common normals' offsets, the joint-angle offsets and
/// rotated inertias. Only the pattern of zeros and ones matters to the count.
Model<double> twists_only(Model<double> model, double& least_cos, double& most_cos) {
  const auto has_axis = [&](int i) {
    return i >= 0 && quaternion_offset(model.joint_type[i]) < 0;
  };
  const Model<double> read = model;
  for (int i = 0; i < model.nbodies; ++i) {
    if (!has_axis(i)) throw std::logic_error("twists_only: a joint without an axis");
    const int p = read.parent[i];
    const Vec3<double>& k = read.joint_axis[i];
    const double c = has_axis(p) ? dot(k, mul(read.X_tree[i].E, read.joint_axis[p])) : 1.0;
    const double s = std::sqrt(std::max(0.0, 1 - c * c));
    if (std::abs(c) <= 1e-9) {
      least_cos = std::min(least_cos, std::abs(c));
      most_cos = std::max(most_cos, std::abs(c));
    }
    model.X_tree[i].E = Mat3<double>{1, 0, 0, 0, c, s, 0, -s, c};
    model.joint_axis[i] = {0, 0, 1};
    if (is_revolute(model.joint_type[i])) model.joint_type[i] = JointType::RevoluteZ;
  }
  return model;
}

std::vector<FrameRow> count_frames(const std::string& name, const Model<double>& model) {
  std::fprintf(stderr, "  %s: rotations as read, twists only, snapped\n", name.c_str());
  Model<double> snapped = model;
  snap(snapped, gen::suggested_snap);
  double least_cos = 1, most_cos = 0;
  const Model<double> twists = twists_only(model, least_cos, most_cos);
  std::vector<FrameRow> rows;
  for (const char* a : frame_algorithms)
    rows.push_back({name, a, arithmetic(model, a), arithmetic(twists, a), arithmetic(snapped, a),
                    least_cos, most_cos});
  return rows;
}

// ---- output ------------------------------------------------------------------------------

std::string by_kind(const Kinds& k) {
  return fmt::format("{}/{}/{}/{}/{}/{}", k.add, k.mul, k.div, k.neg, k.sin, k.cos);
}

std::string per(long ops, long n) { return fmt::format("{:.1f}", double(ops) / double(n)); }

std::string ratio(long a, long b) { return fmt::format("{:.2f}", double(a) / double(b)); }

nlohmann::json to_json(const Kinds& k) {
  return {{"add", k.add}, {"mul", k.mul}, {"div", k.div},   {"neg", k.neg},
          {"sin", k.sin}, {"cos", k.cos}, {"sqrt", k.sqrt}, {"total", k.total()}};
}

const Row& find(const std::vector<Row>& rows, const std::string& model, Algorithm a) {
  for (const Row& r : rows)
    if (r.model == model && r.algorithm == a) return r;
  throw std::logic_error("no row for " + model);
}

std::string frames_markdown(const std::vector<FrameRow>& frames) {
  std::string md =
      "\n## Rounded rotations: what body frames could save\n\n"
      "Generated code, add, mul, div and neg, on the arms whose URDFs write rounded rotations "
      "(fixed base). *As read*: the file's model. *Twists only*: each joint rotation cut to "
      "Rx(alpha), alpha the angle between the joint's axis and its parent's, with offsets and "
      "inertias as read (`twists_only` in work_counts.cpp): a lower bound for any choice of body "
      "frames, modified Denavit-Hartenberg ones included, since a twist is the angle between two "
      "joint axes, which no frame changes, and the file's near right angles are not exact "
      "(*\\|cos alpha\\|*: the least and largest over the twists within 1e-9 of one). "
      "*Snapped*: `--snap 1e-9`, which changes the model.\n\n"
      "| robot | \\|cos alpha\\| | function | as read | twists only | snapped | "
      "twists only / as read | snapped / as read |\n|---|---|---|---:|---:|---:|---:|---:|\n";
  for (const FrameRow& f : frames)
    md += fmt::format("| {} | {:.1e} to {:.1e} | {} | {} | {} | {} | {} | {} |\n", f.model,
                      f.least_cos, f.most_cos, f.algorithm, f.as_read, f.twists_only, f.snapped,
                      ratio(f.twists_only, f.as_read), ratio(f.snapped, f.as_read));
  return md;
}

std::string markdown(const std::vector<Row>& rows, const std::vector<DenseRow>& dense,
                     const std::vector<DerivativeRow>& derivatives,
                     const std::vector<FrameRow>& frames) {
  std::string md = fmt::format(
      "# Work counts\n\n"
      "Operations of one call, counted, not timed (`dyngen_work_counts`, bench/README.md). "
      "*generated*: the live operations of dyngen's simplified trace, as its banner counts them; "
      "*runtime*: the unsimplified trace, every operation the runtime performs for the same "
      "call; *hand-written*: `bench/planar_reference.hpp`, a planar (3-vector) RNEA, CRBA and ABA "
      "written by hand for the planar chains, run on a counting scalar. By kind, "
      "`add/mul/div/neg/sin/cos`, where add counts additions and subtractions; none of them takes "
      "a square root (sqrt is 0 everywhere). *seed*: the rigid-body algorithms chapter's work "
      "counts, n for RNEA and ABA and n(n+1)/2 joint pairs for CRBA, with n the degrees of "
      "freedom; *per seed unit* is the generated total over it. Chains: `make_chain N N planar|"
      "spatial` (seed N), as dyngen_bench's.\n\n");

  md +=
      "## Planar chains: generated code against the hand-written planar chain\n\n"
      "Operations per degree of freedom, generated / hand-written:\n\n"
      "| links | RNEA | CRBA | ABA |\n|---:|---|---|---|\n";
  for (const int links : chain_links) {
    const std::string model = fmt::format("planar_chain{}", links);
    md += fmt::format("| {} |", links);
    for (const Algorithm a : algorithms) {
      const Row& r = find(rows, model, a);
      md += fmt::format(" {} / {} ({}) |", per(r.generated.total(), r.nv),
                        per(r.hand_written->total(), r.nv),
                        ratio(r.generated.total(), r.hand_written->total()));
    }
    md += "\n";
  }
  md +=
      "\n| links | algorithm | seed | generated | total | per DoF | per seed unit | "
      "hand-written | total | per DoF | generated / hand-written | runtime | total | per DoF |\n"
      "|---:|---|---:|---|---:|---:|---:|---|---:|---:|---:|---|---:|---:|\n";
  for (const Row& r : rows) {
    if (r.kind != "planar_chain") continue;
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                      r.nv, algorithm_name(r.algorithm), r.seed_work, by_kind(r.generated),
                      r.generated.total(), per(r.generated.total(), r.nv),
                      per(r.generated.total(), r.seed_work), by_kind(*r.hand_written),
                      r.hand_written->total(), per(r.hand_written->total(), r.nv),
                      ratio(r.generated.total(), r.hand_written->total()), by_kind(r.runtime),
                      r.runtime.total(), per(r.runtime.total(), r.nv));
  }

  auto generated_and_runtime = [&](const std::string& kind) {
    std::string table =
        "| model | base | DoF | algorithm | seed | generated | total | per DoF | per seed unit | "
        "runtime | total | per DoF | runtime / generated |\n"
        "|---|---|---:|---|---:|---|---:|---:|---:|---|---:|---:|---:|\n";
    for (const Row& r : rows) {
      if (r.kind != kind) continue;
      table +=
          fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                      r.model, r.base, r.nv, algorithm_name(r.algorithm), r.seed_work,
                      by_kind(r.generated), r.generated.total(), per(r.generated.total(), r.nv),
                      per(r.generated.total(), r.seed_work), by_kind(r.runtime), r.runtime.total(),
                      per(r.runtime.total(), r.nv), ratio(r.runtime.total(), r.generated.total()));
    }
    return table;
  };
  md += "\n## Spatial chains\n\n" + generated_and_runtime("spatial_chain");
  md += "\n## Robots (tests/models, mimic joints independent, romeo's massless joints locked)\n\n" +
        generated_and_runtime("robot");

  md +=
      "\n## Forward dynamics: ABA against CRBA, bias and a dense solve\n\n"
      "Generated code throughout. *CRBA + bias*: M and h = RNEA(q, v, 0) traced into one "
      "function, so that the sin, cos and transforms of q are made once (*CRBA* and *bias*: "
      "each traced alone). *LDLT solve*: qdd = M^-1 (tau - h) by a dense LDLᵀ factorisation "
      "without pivoting and two triangular solves, counted by running it on the counting scalar "
      "(`ldlt_solve` in work_counts.cpp; n subtractions for tau - h included).\n\n"
      "| chain | n | ABA | CRBA | bias | CRBA + bias | LDLT solve | CRBA + bias + solve | "
      "over ABA | ABA per DoF | CRBA + bias + solve per DoF |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const DenseRow& d : dense) {
    const long both_ways = (d.crba_and_bias + d.solve).total();
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", d.model, d.nv,
                      d.aba.total(), d.crba.total(), d.bias.total(), d.crba_and_bias.total(),
                      d.solve.total(), both_ways, ratio(both_ways, d.aba.total()),
                      per(d.aba.total(), d.nv), per(both_ways, d.nv));
  }
  md +=
      "\n## Derivatives: where rnea_derivatives' operations go\n\n"
      "Generated code, add, mul, div and neg (sin and cos, the same few in each function, left "
      "out as in docs/performance.md's derivative tables). rnea_derivatives by the pass that "
      "records them (`dyngen/rnea_derivatives.hpp`): the *forward* and *backward* passes do "
      "each body's work (its joint columns' terms, the composite inertia, variation and force "
      "of its subtree, and the four forces its columns pair with) in its own frame, the "
      "*pairs* carry each column's forces up its path and pair them with every joint on it; "
      "on robots past `max_carried_path_joints` (atlas floating here) all is in base "
      "coordinates, dense, and the pairs are a kernel's loops where the trace keeps the call. "
      "aba_derivatives counts the product M^-1 d tau's kernel loops where it is a call (every "
      "floating base here: atlas's for its size, the others' as vector lanes run it faster; "
      "README, \"Kernels\"). "
      "*Per-body work over RNEA* is "
      "forward + backward over rnea: what the derivatives cost before any pair is formed. Issue "
      "13's targets in time are at most 4 times RNEA and 3 times ABA (6 and 4 on atlas "
      "floating).\n\n"
      "| robot | base | DoF | rnea | forward | backward | pairs | rnea_derivatives | "
      "per-body work over rnea | over rnea | aba | aba_derivatives | over aba |\n"
      "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const DerivativeRow& d : derivatives)
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                      d.model, d.base, d.nv, d.rnea, d.forward, d.backward, d.pairs,
                      d.rnea_derivatives, ratio(d.forward + d.backward, d.rnea),
                      ratio(d.rnea_derivatives, d.rnea), d.aba, d.aba_derivatives,
                      ratio(d.aba_derivatives, d.aba));
  return md + frames_markdown(frames);
}

nlohmann::json json(const std::vector<Row>& rows, const std::vector<DenseRow>& dense,
                    const std::vector<DerivativeRow>& derivatives,
                    const std::vector<FrameRow>& frames) {
  nlohmann::json out = {
      {"description",
       "operations of one call: generated (live operations of the simplified trace), runtime "
       "(unsimplified trace), hand_written (bench/planar_reference.hpp on a counting scalar, "
       "planar chains), seed_work (n for RNEA and ABA, n(n+1)/2 for CRBA, n = DoF); add counts "
       "add and sub"},
      {"functions", nlohmann::json::array()},
      {"forward_dynamics", nlohmann::json::array()},
      {"derivatives", nlohmann::json::array()},
      {"rounded_rotations", nlohmann::json::array()}};
  for (const Row& r : rows) {
    nlohmann::json f = {{"model", r.model},
                        {"kind", r.kind},
                        {"base", r.base},
                        {"dof", r.nv},
                        {"algorithm", algorithm_name(r.algorithm)},
                        {"seed_work", r.seed_work},
                        {"generated", to_json(r.generated)},
                        {"runtime", to_json(r.runtime)}};
    if (r.hand_written) f["hand_written"] = to_json(*r.hand_written);
    out["functions"].push_back(f);
  }
  for (const DerivativeRow& d : derivatives)
    out["derivatives"].push_back({{"model", d.model},
                                  {"base", d.base},
                                  {"dof", d.nv},
                                  {"rnea", d.rnea},
                                  {"aba", d.aba},
                                  {"rnea_derivatives",
                                   {{"forward", d.forward},
                                    {"backward", d.backward},
                                    {"pairs", d.pairs},
                                    {"total", d.rnea_derivatives}}},
                                  {"aba_derivatives", d.aba_derivatives}});
  for (const FrameRow& f : frames)
    out["rounded_rotations"].push_back({{"model", f.model},
                                        {"algorithm", f.algorithm},
                                        {"as_read", f.as_read},
                                        {"twists_only", f.twists_only},
                                        {"snapped", f.snapped},
                                        {"least_abs_cos_twist", f.least_cos},
                                        {"largest_abs_cos_twist", f.most_cos}});
  for (const DenseRow& d : dense)
    out["forward_dynamics"].push_back({{"model", d.model},
                                       {"dof", d.nv},
                                       {"aba", to_json(d.aba)},
                                       {"crba", to_json(d.crba)},
                                       {"bias", to_json(d.bias)},
                                       {"crba_and_bias", to_json(d.crba_and_bias)},
                                       {"ldlt_solve", to_json(d.solve)}});
  return out;
}

int run(const std::filesystem::path& output) {
  std::vector<Row> rows;
  std::vector<DenseRow> dense;
  for (const char* kind : {"planar", "spatial"}) {
    for (const int links : chain_links) {
      const std::string name = fmt::format("{}_chain{}", kind, links);
      const Model<double> model =
          gen::load_robot(fmt::format("{}/{}.yaml", WORK_COUNT_CHAINS, name)).model;
      const std::vector<Row> counted =
          count_model(name, std::string(kind) + "_chain", "fixed", model);
      rows.insert(rows.end(), counted.begin(), counted.end());
      DenseRow d{name, model.nv, {}, {}, {}, {}, {}};
      d.aba = find(counted, name, Computes::ForwardDynamics).generated;
      d.crba = find(counted, name, Computes::MassMatrix).generated;
      d.bias = dense_trace_counts(model, false, true);
      d.crba_and_bias = dense_trace_counts(model, true, true);
      d.solve = dense_solve_counts(model);
      dense.push_back(d);
    }
  }
  for (const test::RobotFile& robot : test::robot_files())
    for (const bool floating : {false, true}) {
      gen::LoadOptions options = robot.aba_options;
      options.floating_base = floating;
      const Model<double> model = gen::load_robot(robot.path, options).model;
      const std::vector<Row> counted =
          count_model(robot.name, "robot", floating ? "floating" : "fixed", model);
      rows.insert(rows.end(), counted.begin(), counted.end());
    }

  std::vector<DerivativeRow> derivatives;
  for (const test::RobotFile& robot : test::robot_files()) {
    if (std::find(std::begin(derivative_robots), std::end(derivative_robots), robot.name) ==
        std::end(derivative_robots))
      continue;
    for (const bool floating : {false, true}) {
      const char* base = floating ? "floating" : "fixed";
      std::fprintf(stderr, "  %s (%s base): derivatives\n", robot.name.c_str(), base);
      derivatives.push_back(
          count_derivatives(robot.name, base, test::load_for_aba(robot, floating)));
    }
  }

  std::vector<FrameRow> frames;
  for (const test::RobotFile& robot : test::robot_files())
    if (std::find(std::begin(rounded_arms), std::end(rounded_arms), robot.name) !=
        std::end(rounded_arms)) {
      const std::vector<FrameRow> counted = count_frames(robot.name, test::load_for_aba(robot));
      frames.insert(frames.end(), counted.begin(), counted.end());
    }

  std::filesystem::create_directories(output);
  const std::string md = markdown(rows, dense, derivatives, frames);
  std::ofstream(output / "work_counts.md") << md;
  std::ofstream(output / "work_counts.json")
      << json(rows, dense, derivatives, frames).dump(1) << "\n";
  std::fputs(md.c_str(), stdout);
  std::fprintf(stderr, "wrote %s and %s\n", (output / "work_counts.md").c_str(),
               (output / "work_counts.json").c_str());
  return 0;
}

}  // namespace
}  // namespace dyngen::bench

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: dyngen_work_counts OUTPUT_DIR\n");
    return 2;
  }
  try {
    return dyngen::bench::run(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dyngen_work_counts: %s\n", e.what());
    return 1;
  }
}
