// dyngen_call_counts (README.md, "Work counts and instruction counts"): the calls that
// scripts/callgrind.sh counts under valgrind --tool=callgrind, and the report it writes.
//
//   dyngen_call_counts --list
//       the packages of packages.cpp (the code dyngen_bench times), one per line: the name, then
//       the implementations it has: generated, snapped (the code of --snap 1e-9; robots),
//       unrolled (the code of --structure unrolled), runtime, hand-written (planar_reference.hpp;
//       planar chains)
//   dyngen_call_counts PACKAGE IMPLEMENTATION ALGORITHM CALLS
//       CALLS calls of one function on 16 seeded random states, each through
//       dyngen_measured_call, the one function whose instructions callgrind collects
//       (--toggle-collect); IMPLEMENTATION "none" calls an empty function instead, which
//       measures the harness's own instructions per call
//   dyngen_call_counts --report COUNTS OUTPUT_DIR
//       callgrind.md and callgrind.json from COUNTS, lines "PACKAGE IMPLEMENTATION ALGORITHM
//       CALLS IR I1MR" (the instructions and the level-1 instruction-cache misses collected over
//       the CALLS calls), with the operation
//       counts of each function (work_counts.cpp's: live operations of the simplified trace for
//       generated code, the unsimplified trace for the runtime, the counting scalar for the
//       hand-written chain)
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "dyngen/dyngen.hpp"
#include "dyngen/numerics/random.hpp"
#include "emit.hpp"
#include "package.hpp"
#include "planar_counts.hpp"
#include "robot.hpp"
#include "trace.hpp"

namespace dyngen::bench {

/// One call of one implementation on one state.
using Call = void (*)(void* implementation, const numerics::State& s, double* out);

}  // namespace dyngen::bench

// Out of line and out of reach of inlining and cloning, so that callgrind finds it by name and
// every implementation pays the same way in.
extern "C" __attribute__((noipa)) void dyngen_measured_call(dyngen::bench::Call call,
                                                            void* implementation,
                                                            const dyngen::numerics::State& s,
                                                            double* out) {
  call(implementation, s, out);
}

namespace dyngen::bench {
namespace {


constexpr int state_count = 16;
constexpr std::uint64_t seed = 20261121;
constexpr const char* implementations[] = {"generated", "snapped", "unrolled", "runtime",
                                           "hand-written"};

const Package& package_named(const std::string& name) {
  for (const Package& p : packages())
    if (name == p.name) return p;
  throw std::runtime_error("no package " + name);
}

bool is_planar_chain(const Package& p) { return std::string(p.robot) == "planar_chain"; }

bool has(const Package& p, const std::string& implementation) {
  if (implementation == "snapped") return p.snapped.rnea != nullptr;
  if (implementation == "hand-written") return is_planar_chain(p);
  return implementation == "generated" || implementation == "unrolled" ||
         implementation == "runtime";
}

gen::Robot load(const Package& p, bool snapped) {
  return gen::load_robot(p.input, load_options(p, snapped));
}

// ---- the calls -----------------------------------------------------------------------------

struct Generated {
  Functions f;
  Algorithm a;
};

void call_generated(void* g, const numerics::State& s, double* out) {
  const Generated& x = *static_cast<Generated*>(g);
  call(x.f, x.a, s, out);
}

struct Runtime {
  const Model<double>& model;
  Workspace<double> ws;
  Algorithm a;
};

void call_runtime(void* r, const numerics::State& s, double* out) {
  Runtime& x = *static_cast<Runtime*>(r);
  const std::size_t nv = x.model.nv;
  switch (x.a) {
    case Computes::Other: break;
    case Computes::InverseDynamics: rnea<double>(x.model, x.ws, s.q, s.qd, s.qdd, {out, nv}); break;
    case Computes::MassMatrix: crba<double>(x.model, x.ws, s.q, {out, nv * nv}); break;
    case Computes::ForwardDynamics: aba<double>(x.model, x.ws, s.q, s.qd, s.tau, {out, nv}); break;
  }
}

struct HandWritten {
  PlanarChain<double> chain;
  Algorithm a;
};

void call_hand_written(void* h, const numerics::State& s, double* out) {
  HandWritten& x = *static_cast<HandWritten*>(h);
  switch (x.a) {
    case Computes::Other: break;
    case Computes::InverseDynamics: x.chain.rnea(s.q.data(), s.qd.data(), s.qdd.data(), out); break;
    case Computes::MassMatrix: x.chain.crba(s.q.data(), out); break;
    case Computes::ForwardDynamics: x.chain.aba(s.q.data(), s.qd.data(), s.tau.data(), out); break;
  }
}

void call_nothing(void*, const numerics::State&, double*) {}

int measure(const std::string& package, const std::string& implementation, Algorithm a,
            long calls) {
  const Package& p = package_named(package);
  if (implementation != "none" && !has(p, implementation))
    throw std::runtime_error(package + " has no " + implementation + " code");
  const gen::Robot robot = load(p, false);
  const Model<double>& model = robot.model;
  numerics::Random rng(seed);
  std::vector<numerics::State> states;
  for (int k = 0; k < state_count; ++k) states.push_back(numerics::random_state(model, rng));
  std::vector<double> out(model.nv * model.nv);

  Generated generated{implementation == "snapped"  ? p.snapped
                      : implementation == "unrolled" ? p.unrolled
                                                   : p.generated,
                      a};
  Runtime runtime{model, Workspace<double>(model), a};
  std::optional<HandWritten> hand_written;
  Call call = call_nothing;
  void* target = nullptr;
  if (implementation == "generated" || implementation == "snapped" || implementation == "unrolled") {
    call = call_generated, target = &generated;
  } else if (implementation == "runtime") {
    call = call_runtime, target = &runtime;
  } else if (implementation == "hand-written") {
    hand_written.emplace(HandWritten{PlanarChain<double>(model), a});
    call = call_hand_written, target = &*hand_written;
  }
  for (long k = 0; k < calls; ++k)
    dyngen_measured_call(call, target, states[k % state_count], out.data());
  return 0;
}

// ---- the report ----------------------------------------------------------------------------

/// Operations of one call of each implementation of one package's function.
std::map<std::string, long> operation_counts(const Package& p, Algorithm a) {
  std::map<std::string, long> ops;
  const gen::Robot robot = load(p, false);
  ops["generated"] = gen::count_ops(gen::trace<double>(algorithm_name(a), robot.model, true)).total();
  ops["runtime"] = gen::count_ops(gen::trace<double>(algorithm_name(a), robot.model, false), false).total();
  if (has(p, "snapped"))
    ops["snapped"] = gen::count_ops(gen::trace<double>(algorithm_name(a), load(p, true).model, true)).total();
  if (has(p, "hand-written")) ops["hand-written"] = count_planar_chain(robot.model, a).total();
  return ops;
}

int report(const std::string& counts_file, const std::filesystem::path& output) {
  // instructions and instruction-cache misses per call, by package, algorithm and implementation
  using PerCall = std::map<std::string, std::map<std::string, std::map<std::string, double>>>;
  PerCall ir, i1_misses;
  std::optional<double> overhead;
  std::ifstream in(counts_file);
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::string package, implementation, algorithm;
    long calls = 0;
    double total = 0, misses = 0;
    if (!(fields >> package >> implementation >> algorithm >> calls >> total >> misses) ||
        calls <= 0)
      throw std::runtime_error(counts_file + ": bad line '" + line + "'");
    if (implementation == "none") {
      overhead = total / calls;
    } else {
      ir[package][algorithm][implementation] = total / calls;
      i1_misses[package][algorithm][implementation] = misses / calls;
    }
  }

  std::string md =
      "# Instruction counts\n\n"
      "Instructions executed per call (callgrind's Ir), counted by `scripts/callgrind.sh` "
      "(bench/README.md): each function called on 16 seeded random states under `valgrind "
      "--tool=callgrind`, with collection only inside the call. *generated*: the code dyngen "
      "emits (dyngen_bench's packages, built at -O3 with -ffp-contract=off); *snapped*: the same "
      "with `--snap 1e-9`; *unrolled*: the code of `--structure unrolled` (the same operations as "
      "*generated*, which is the default `--structure auto`: shared in functions of 1800 "
      "operations or more); *runtime*: `dyngen::rnea`, `crba`, `aba` on `Model<double>`; "
      "*hand-written*: bench/planar_reference.hpp (planar chains). *ops*: operations per call "
      "(add, mul, div, neg, sin and cos, as dyngen_work_counts counts them); *Ir/op*: "
      "instructions per operation, loads, stores, calls and sin/cos included; *I1 misses*: "
      "level-1 instruction-cache misses per call in callgrind's simulation of this machine's "
      "cache (32 KB, 8 ways, 64-byte lines), the harness's code between the calls included. A "
      "function whose code fits misses about once per 64 bytes of code over all the calls "
      "(under 10 per call here); one that does not fit misses about once per 64 bytes in every "
      "call, and runs slower by up to half for the same instructions (docs/performance.md, "
      "\"Code size and the instruction cache\").";
  if (overhead)
    md += fmt::format(
        " Each figure includes the harness's {:.0f} instructions per call (an "
        "empty call, measured the same way).",
        *overhead);
  md +=
      "\n\n| package | algorithm | Ir: generated | snapped | unrolled | runtime | hand-written | "
      "runtime / generated | unrolled / generated | hand-written / generated | ops: generated | "
      "runtime | hand-written | Ir/op: generated | runtime | hand-written | I1 misses: generated "
      "| snapped | unrolled | runtime |\n"
      "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
      "---:|---:|\n";
  nlohmann::json json = {
      {"description",
       "instructions per call (callgrind Ir), level-1 instruction-cache misses per call "
       "(callgrind I1mr; 32 KB, 8 ways, 64-byte lines) and operations per call"},
      {"harness_ir_per_call", overhead ? nlohmann::json(*overhead) : nullptr},
      {"functions", nlohmann::json::array()}};
  for (const Package& p : packages()) {
    if (!ir.count(p.name)) continue;
    std::fprintf(stderr, "  %s\n", p.name);
    for (const Algorithm a : compared_algorithms()) {
      const std::string name = algorithm_name(a);
      if (!ir[p.name].count(name)) continue;
      const std::map<std::string, double>& per_call = ir[p.name][name];
      const std::map<std::string, long> ops = operation_counts(p, a);
      auto cell = [](const std::map<std::string, double>& x, const std::string& key,
                     const char* format, double divisor = 1) {
        return x.count(key) ? fmt::format(fmt::runtime(format), x.at(key) / divisor)
                            : std::string("-");
      };
      std::string row = fmt::format("| {} | {} |", p.name, name);
      for (const char* x : {"generated", "snapped", "unrolled", "runtime", "hand-written"})
        row += fmt::format(" {} |", cell(per_call, x, "{:.0f}"));
      for (const char* x : {"runtime", "unrolled", "hand-written"})
        row += fmt::format(" {} |", cell(per_call, x, "{:.2f}", per_call.at("generated")));
      for (const char* x : {"generated", "runtime", "hand-written"})
        row += ops.count(x) ? fmt::format(" {} |", ops.at(x)) : " - |";
      for (const char* x : {"generated", "runtime", "hand-written"})
        row += fmt::format(" {} |", ops.count(x) ? cell(per_call, x, "{:.2f}", ops.at(x)) : "-");
      const std::map<std::string, double>& misses = i1_misses[p.name][name];
      for (const char* x : {"generated", "snapped", "unrolled", "runtime"})
        row += fmt::format(" {} |", cell(misses, x, "{:.1f}"));
      md += row + "\n";
      json["functions"].push_back({{"package", p.name},
                                   {"algorithm", name},
                                   {"ir_per_call", per_call},
                                   {"i1_misses_per_call", misses},
                                   {"ops_per_call", ops}});
    }
  }
  std::filesystem::create_directories(output);
  std::ofstream(output / "callgrind.md") << md;
  std::ofstream(output / "callgrind.json") << json.dump(1) << "\n";
  std::fputs(md.c_str(), stdout);
  return 0;
}

int run(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() == 1 && args[0] == "--list") {
    for (const Package& p : packages()) {
      std::string line = p.name;
      for (const char* implementation : implementations)
        if (has(p, implementation)) line += std::string(" ") + implementation;
      std::puts(line.c_str());
    }
    return 0;
  }
  if (args.size() == 3 && args[0] == "--report") return report(args[1], args[2]);
  if (args.size() == 4 && compared_algorithm(args[2]))
    return measure(args[0], args[1], *compared_algorithm(args[2]), std::atol(args[3].c_str()));
  std::vector<const char*> names;
  for (const Algorithm a : compared_algorithms()) names.push_back(algorithm_name(a));
  fmt::print(stderr,
             "usage: dyngen_call_counts --list\n"
             "       dyngen_call_counts PACKAGE generated|snapped|unrolled|runtime|hand-written|none "
             "{} CALLS\n"
             "       dyngen_call_counts --report COUNTS OUTPUT_DIR\n",
             fmt::join(names, "|"));
  return 2;
}

}  // namespace
}  // namespace dyngen::bench

int main(int argc, char** argv) {
  try {
    return dyngen::bench::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dyngen_call_counts: %s\n", e.what());
    return 1;
  }
}
