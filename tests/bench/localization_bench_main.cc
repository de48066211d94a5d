// The localization_bench executable: the Monte Carlo localization baseline
// (mcl_bench.cc).
#include <benchmark/benchmark.h>

BENCHMARK_MAIN();
