// dyngen_sincos_bench: time per angle of dyngen::sincos (sincos.hpp), double and float, beside
// std::sin + std::cos (which GCC merges into one call of sincos when both take the same value;
// std_sin_cos_separate keeps them apart) and glibc's ::sincos and ::sincosf, on arrays of 7
// angles (a robot's joints), 30 and 1024 uniform in [-pi, pi]; 1024 also in [-1e4, 1e4] and,
// for double, log-uniform in [2^21, 2^1000] (dyngen's Payne-Hanek path, taken from 2^21 on).
// dyngen_double_array times the array form, which the generated joint_trig calls.
// The second argument of each benchmark names the range: 0 [-pi, pi], 1 [-1e4, 1e4], 2 huge.
//
// The counter per_angle is the CPU time of one sine and cosine pair; the loop over the array is
// the caller's, as in the runtime, and the calls are independent of each other.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "dyngen/sincos.hpp"

namespace {

enum Range : std::int64_t { kPi = 0, k1e4 = 1, kHuge = 2 };

template <class F>
std::vector<F> angles(std::int64_t n, std::int64_t range) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<F> x(static_cast<std::size_t>(n));
  for (F& xi : x) {
    const double u = unit(rng);
    switch (range) {
      case kPi: xi = static_cast<F>(3.141592653589793 * u); break;
      case k1e4: xi = static_cast<F>(1e4 * u); break;
      default: xi = static_cast<F>(std::copysign(std::exp2(21 + 979 * std::fabs(u)), u)); break;
    }
  }
  return x;
}

/// Times all(x, s, c, n), one pass over the array; state.range(0) angles, state.range(1) the
/// Range.
template <class F, class All>
void run_array(benchmark::State& state, All all) {
  const std::int64_t n = state.range(0);
  const std::vector<F> x = angles<F>(n, state.range(1));
  std::vector<F> s(x.size()), c(x.size());
  for (auto _ : state) {
    all(x.data(), s.data(), c.data(), static_cast<int>(n));
    benchmark::DoNotOptimize(s.data());
    benchmark::DoNotOptimize(c.data());
    benchmark::ClobberMemory();
  }
  state.counters["per_angle"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
}

/// Times fn(x[i], s[i], c[i]) for each angle, the loop being the caller's.
template <class F, class Fn>
void run(benchmark::State& state, Fn fn) {
  run_array<F>(state, [fn](const F* x, F* s, F* c, int n) {
    for (int i = 0; i < n; ++i) fn(x[i], s[i], c[i]);
  });
}

void dyngen_double(benchmark::State& state) {
  run<double>(state, [](double x, double& s, double& c) { dyngen::sincos(x, s, c); });
}
/// The array form, as the generated joint_trig calls it: one call for the whole array.
void dyngen_double_array(benchmark::State& state) {
  run_array<double>(state, [](const double* x, double* s, double* c, int n) {
    dyngen::sincos(x, s, c, n);
  });
}

void dyngen_float(benchmark::State& state) {
  run<float>(state, [](float x, float& s, float& c) { dyngen::sincos(x, s, c); });
}
void std_sin_cos(benchmark::State& state) {
  run<double>(state, [](double x, double& s, double& c) {
    s = std::sin(x);
    c = std::cos(x);
  });
}
/// std::sin then std::cos, kept apart: above, GCC turns the pair into one call of sincos.
void std_sin_cos_separate(benchmark::State& state) {
  run<double>(state, [](double x, double& s, double& c) {
    s = std::sin(x);
    benchmark::DoNotOptimize(x);  // cos's argument is no longer known to be sin's
    c = std::cos(x);
  });
}
void std_sin_cos_float(benchmark::State& state) {
  run<float>(state, [](float x, float& s, float& c) {
    s = std::sin(x);
    c = std::cos(x);
  });
}
void glibc_sincos(benchmark::State& state) {
  run<double>(state, [](double x, double& s, double& c) { ::sincos(x, &s, &c); });
}
void glibc_sincosf(benchmark::State& state) {
  run<float>(state, [](float x, float& s, float& c) { ::sincosf(x, &s, &c); });
}

void sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"n", "range"});
  for (std::int64_t n : {7, 30, 1024}) b->Args({n, kPi});
  b->Args({1024, k1e4});
}

void sizes_and_huge(benchmark::internal::Benchmark* b) {
  sizes(b);
  b->Args({1024, kHuge});
}

}  // namespace

BENCHMARK(dyngen_double)->Apply(sizes_and_huge);
BENCHMARK(dyngen_double_array)->Apply(sizes_and_huge);
BENCHMARK(std_sin_cos)->Apply(sizes_and_huge);
BENCHMARK(std_sin_cos_separate)->Apply(sizes_and_huge);
BENCHMARK(glibc_sincos)->Apply(sizes_and_huge);
BENCHMARK(dyngen_float)->Apply(sizes);
BENCHMARK(std_sin_cos_float)->Apply(sizes);
BENCHMARK(glibc_sincosf)->Apply(sizes);

BENCHMARK_MAIN();
