// The load-time dispatch side by side (scripts/dispatch_bench.sh): each robot's rnea, crba, aba,
// minv, rnea_derivatives and aba_derivatives compiled for the baseline alone
// (DYNGEN_NO_DISPATCH) and as a user's build compiles them (DYNGEN_DISPATCH: the loader runs the
// AVX2 clone where the processor has AVX2), timed in one binary after both have been checked to
// return the same bits at one state. packages.hpp (written by the script) includes the packages
// and lists them as ROBOT(name, baseline, dispatch), their namespaces.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "packages.hpp"

namespace {

template <int nq, int nv>
struct State {
  double q[nq], v[nv], a[nv];
  State() {
    for (int i = 0; i < nq; ++i) q[i] = 0.3 * std::sin(1.0 + i);
    for (int i = 0; i < nv; ++i) v[i] = 0.5 * std::cos(2.0 + i), a[i] = 0.2 * std::sin(3.0 * i);
  }
};

// The six functions of one package, each writing into out (3 nv * nv at least).
#define CALLS(ns)                                                                         \
  [](const double* q, const double* v, const double* a, double* out, int f) {            \
    constexpr int nn = ns::nv * ns::nv;                                                   \
    switch (f) {                                                                          \
      case 0: ns::rnea(q, v, a, out); break;                                              \
      case 1: ns::crba(q, out); break;                                                    \
      case 2: ns::aba(q, v, a, out); break;                                               \
      case 3: ns::minv(q, out); break;                                                    \
      case 4: ns::rnea_derivatives(q, v, a, out, out + nn); break;                        \
      default: ns::aba_derivatives(q, v, a, out, out + nn, out + 2 * nn); break;          \
    }                                                                                     \
  }

using Call = void (*)(const double*, const double*, const double*, double*, int);
const char* const functions[] = {"rnea", "crba", "aba", "minv", "rnea_derivatives",
                                 "aba_derivatives"};
const char* const builds[] = {"baseline", "dispatch"};

template <int nq, int nv>
void add_robot(const char* robot, const Call (&calls)[2]) {
  static State<nq, nv> state;
  constexpr int size = 3 * nv * nv;
  for (int f = 0; f < 6; ++f) {
    static double out[2][size];
    for (int b = 0; b < 2; ++b) calls[b](state.q, state.v, state.a, out[b], f);
    if (std::memcmp(out[0], out[1], sizeof out[0]) != 0) {
      std::fprintf(stderr, "%s %s: the builds' bits differ\n", robot, functions[f]);
      std::exit(1);
    }
    for (int b = 0; b < 2; ++b) {
      const std::string name = std::string(robot) + "/" + functions[f] + "/" + builds[b];
      benchmark::RegisterBenchmark(name.c_str(), [call = calls[b], f](benchmark::State& st) {
        static double result[size];
        for (auto _ : st) {
          call(state.q, state.v, state.a, result, f);
          benchmark::DoNotOptimize(result);
          benchmark::ClobberMemory();
        }
      });
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
#define ROBOT(name, b, d) add_robot<b::nq, b::nv>(name, {CALLS(b), CALLS(d)});
  ROBOTS
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
