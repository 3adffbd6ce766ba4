// dyngen_derivatives_bench (bench/README.md): the generated derivatives beside the generated
// values they differentiate, finite differences of the generated ABA, the runtime's derivatives,
// minv beside CRBA followed by an LDL^T inverse, and rnea_derivatives followed by crba (what
// Pinocchio's computeRNEADerivatives returns: dtau/da = M too), for the packages of bench/CMakeLists.txt's
// derivative_package(). ns per call on seeded random states that change every call; each
// generated function is first checked against the runtime. First it prints each function's
// operations (add, mul, div, neg; sin and cos are in joint_trig), generated and runtime, as
// dyngen's banner counts them.
//
// usage: dyngen_derivatives_bench [Google Benchmark flags]
//        dyngen_derivatives_bench --list
//            the packages' names, one per line
//        dyngen_derivatives_bench --count PACKAGE FUNCTION CALLS
//            CALLS calls of one function (a benchmark's name after the slash, or "none": an
//            empty call, the harness's own instructions) of one package ("ur5 fixed"), each
//            through dyngen_measured_call, the one function whose instructions
//            scripts/callgrind_derivatives.sh collects under callgrind
#include <benchmark/benchmark.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "derivative_packages.hpp"
#include "dyngen/dyngen.hpp"
#include "dyngen/numerics/random.hpp"
#include "emit.hpp"
#include "robot.hpp"
#include "trace.hpp"

namespace dyngen::bench {
struct Fixture;
using Measure = void (*)(Fixture&, const numerics::State&);
}  // namespace dyngen::bench

// Out of line and out of reach of inlining and cloning, so that callgrind finds it by name and
// every function pays the same way in.
extern "C" __attribute__((noipa)) void dyngen_measured_call(dyngen::bench::Measure measure,
                                                            dyngen::bench::Fixture& f,
                                                            const dyngen::numerics::State& s) {
  measure(f, s);
}

namespace dyngen::bench {
namespace {

constexpr int state_count = 64;  // cycled through, so the inputs change every call

}  // namespace

struct Fixture {
  const DerivativePackage* p;
  Model<double> model;
  std::vector<numerics::State> states;
  Workspace<double> ws;
  std::vector<double> a, b, c;  // outputs, nv * nv each
  int n;

  explicit Fixture(const DerivativePackage& package)
      : p(&package), model(gen::load_robot(package.input, options(package)).model), ws(model) {
    n = model.nv;
    numerics::Random rng(20261125);
    for (int k = 0; k < state_count; ++k) states.push_back(numerics::random_state(model, rng));
    a.resize(n * n), b.resize(n * n), c.resize(n * n);
  }

  static gen::LoadOptions options(const DerivativePackage& p) {
    gen::LoadOptions o;
    o.floating_base = p.floating_base;
    o.mimic_independent = true;
    return o;
  }
};

namespace {

double max_difference(const std::vector<double>& x, const std::vector<double>& y) {
  double m = 0, scale = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    m = std::max(m, std::abs(x[k] - y[k]));
    scale = std::max(scale, std::abs(y[k]));
  }
  return m / std::max(scale, 1.0);
}

/// The generated derivatives against the runtime's at one state, so that every timed function
/// computes what it says.
void check(Fixture& f) {
  const numerics::State& s = f.states[0];
  Workspace<double> ws(f.model);
  const std::size_t nn = static_cast<std::size_t>(f.n) * f.n;
  std::vector<double> x(nn), y(nn), z(nn), X(nn), Y(nn), Z(nn);
  f.p->rnea_derivatives(s.q.data(), s.qd.data(), s.qdd.data(), x.data(), y.data());
  rnea_derivatives<double>(f.model, ws, s.q, s.qd, s.qdd, X, Y);
  f.p->aba_derivatives(s.q.data(), s.qd.data(), s.tau.data(), x.data(), y.data(), z.data());
  aba_derivatives<double>(f.model, ws, s.q, s.qd, s.tau, X, Y, Z);
  if (max_difference(x, X) > 1e-9 || max_difference(y, Y) > 1e-9 || max_difference(z, Z) > 1e-9)
    throw std::runtime_error(std::string(f.p->name) + ": generated derivatives differ");
}

/// Forward differences of the generated ABA in q (along integrate) and v: 2n + 1 calls.
void finite_differences(Fixture& f, const numerics::State& s) {
  const int n = f.n;
  std::vector<double> qdd0(n), qdd(n), q(s.q.size()), v = s.qd, d(n, 0.0);
  const double h = 1e-7;
  f.p->aba(s.q.data(), s.qd.data(), s.tau.data(), qdd0.data());
  for (int j = 0; j < n; ++j) {
    d[j] = h;
    integrate<double>(f.model, s.q, d, q);
    d[j] = 0;
    f.p->aba(q.data(), s.qd.data(), s.tau.data(), qdd.data());
    for (int i = 0; i < n; ++i) f.a[i * n + j] = (qdd[i] - qdd0[i]) / h;
    v[j] += h;
    f.p->aba(s.q.data(), v.data(), s.tau.data(), qdd.data());
    v[j] = s.qd[j];
    for (int i = 0; i < n; ++i) f.b[i * n + j] = (qdd[i] - qdd0[i]) / h;
  }
}

/// CRBA, then M^-1 from an LDL^T factorisation (Eigen's, dense).
void crba_ldlt_inverse(Fixture& f, const numerics::State& s) {
  f.p->crba(s.q.data(), f.a.data());
  const Eigen::Map<const Eigen::MatrixXd> M(f.a.data(), f.n, f.n);
  Eigen::Map<Eigen::MatrixXd>(f.b.data(), f.n, f.n) =
      M.ldlt().solve(Eigen::MatrixXd::Identity(f.n, f.n));
}

/// The operation counts of the generated functions and of the runtime's, as a Markdown table.
void print_operation_counts(const std::vector<std::unique_ptr<Fixture>>& fixtures) {
  const char* functions[] = {"rnea", "crba", "aba", "gravity", "nle", "minv", "rnea_derivatives",
                             "aba_derivatives"};
  std::printf("operations per call, generated / runtime (add, mul, div, neg):\n\n| robot |");
  for (const char* a : functions) std::printf(" %s |", a);
  std::printf("\n|---|");
  for (std::size_t k = 0; k < std::size(functions); ++k) std::printf("---:|");
  std::printf("\n");
  for (const auto& f : fixtures) {
    std::printf("| %s |", f->p->name);
    for (const char* a : functions) {
      const auto arithmetic = [](const gen::OpCounts& c) { return c.add + c.mul + c.div + c.neg; };
      std::printf(" %ld / %ld |", arithmetic(gen::count_ops(gen::trace<double>(a, f->model))),
                  arithmetic(gen::count_ops(gen::trace<double>(a, f->model, false), false)));
    }
    std::printf("\n");
  }
  std::printf("\n");
  std::fflush(stdout);
}

const std::map<std::string, Measure>& measures() {
  static const std::map<std::string, Measure> all{
      {"rnea", [](Fixture& f, const numerics::State& s) {
         f.p->rnea(s.q.data(), s.qd.data(), s.qdd.data(), f.a.data());
       }},
      {"aba", [](Fixture& f, const numerics::State& s) {
         f.p->aba(s.q.data(), s.qd.data(), s.tau.data(), f.a.data());
       }},
      {"crba", [](Fixture& f, const numerics::State& s) { f.p->crba(s.q.data(), f.a.data()); }},
      {"gravity", [](Fixture& f, const numerics::State& s) { f.p->gravity(s.q.data(), f.a.data()); }},
      {"nle", [](Fixture& f, const numerics::State& s) {
         f.p->nle(s.q.data(), s.qd.data(), f.a.data());
       }},
      {"minv", [](Fixture& f, const numerics::State& s) { f.p->minv(s.q.data(), f.a.data()); }},
      {"crba_ldlt_inverse", crba_ldlt_inverse},
      {"rnea_derivatives", [](Fixture& f, const numerics::State& s) {
         f.p->rnea_derivatives(s.q.data(), s.qd.data(), s.qdd.data(), f.a.data(), f.b.data());
       }},
      {"rnea_derivatives_with_M", [](Fixture& f, const numerics::State& s) {
         f.p->rnea_derivatives(s.q.data(), s.qd.data(), s.qdd.data(), f.a.data(), f.b.data());
         f.p->crba(s.q.data(), f.c.data());
       }},
      {"aba_derivatives", [](Fixture& f, const numerics::State& s) {
         f.p->aba_derivatives(s.q.data(), s.qd.data(), s.tau.data(), f.a.data(), f.b.data(),
                              f.c.data());
       }},
      {"aba_finite_differences", finite_differences},
      {"runtime_gravity", [](Fixture& f, const numerics::State& s) {
         gravity<double>(f.model, f.ws, s.q, f.a);
       }},
      {"runtime_nle", [](Fixture& f, const numerics::State& s) {
         nle<double>(f.model, f.ws, s.q, s.qd, f.a);
       }},
      {"runtime_minv", [](Fixture& f, const numerics::State& s) {
         minv<double>(f.model, f.ws, s.q, f.a);
       }},
      {"runtime_rnea_derivatives", [](Fixture& f, const numerics::State& s) {
         rnea_derivatives<double>(f.model, f.ws, s.q, s.qd, s.qdd, f.a, f.b);
       }},
      {"runtime_aba_derivatives", [](Fixture& f, const numerics::State& s) {
         aba_derivatives<double>(f.model, f.ws, s.q, s.qd, s.tau, f.a, f.b, f.c);
       }},
  };
  return all;
}

/// --count: calls of one function through dyngen_measured_call, for callgrind.
int count_calls(const std::string& package, const std::string& function, long calls) {
  for (const DerivativePackage& p : derivative_packages()) {
    if (package != p.name) continue;
    const auto found = measures().find(function);
    if (function != "none" && found == measures().end()) {
      std::fprintf(stderr, "dyngen_derivatives_bench: no function %s\n", function.c_str());
      return 2;
    }
    const Measure measure =
        found == measures().end() ? [](Fixture&, const numerics::State&) {} : found->second;
    Fixture f(p);
    check(f);
    for (long k = 0; k < calls; ++k)
      dyngen_measured_call(measure, f, f.states[static_cast<std::size_t>(k) % f.states.size()]);
    return 0;
  }
  std::fprintf(stderr, "dyngen_derivatives_bench: no package %s\n", package.c_str());
  return 2;
}

}  // namespace
}  // namespace dyngen::bench

int main(int argc, char** argv) {
  using namespace dyngen::bench;
  if (argc == 2 && std::string(argv[1]) == "--list") {
    for (const DerivativePackage& p : derivative_packages()) std::printf("%s\n", p.name);
    return 0;
  }
  if (argc == 5 && std::string(argv[1]) == "--count")
    return count_calls(argv[2], argv[3], std::atol(argv[4]));
  benchmark::Initialize(&argc, argv);
  std::vector<std::unique_ptr<Fixture>> fixtures;
  for (const DerivativePackage& p : derivative_packages()) {
    fixtures.push_back(std::make_unique<Fixture>(p));
    check(*fixtures.back());
    Fixture* f = fixtures.back().get();
    for (const auto& [name, measure] : measures()) {
      const std::string id = std::string(p.name) + "/" + name;
      benchmark::RegisterBenchmark(id.c_str(), [f, m = measure, id](benchmark::State& st) {
        std::size_t k = 0;
        for (auto _ : st) {
          m(*f, f->states[k]);
          benchmark::DoNotOptimize(f->a.data());
          benchmark::ClobberMemory();
          k = (k + 1) % f->states.size();
        }
      });
    }
  }
  print_operation_counts(fixtures);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
