#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace pavilion::cli {

// `pavilion bench hall --robots N [--runs 3] [--duration S] [--seed K]`: the
// hall benchmark (docs/benchmarks.md), the workload Stage and mvsim were
// measured on. Runs scenarios/hall_bench/hall_bench_<N>.yaml headless, one run
// at a time, and reports per run and best/median the real-time factor of the
// stepping loop (start-up apart), rays per second and peak memory.
struct BenchArgs {
  int robots = 10;               // 1, 10, 100 or 1000: the layouts the peers ran
  int runs = 3;                  // >= 1
  double duration_s = -1.0;      // simulated s; <= 0: the benchmark's (600/600/60/5 s)
  std::int64_t seed = -1;        // < 0: the scenario's
  std::vector<std::string> set;  // scenario overrides "key.path=value", as `pavilion run --set`
  std::string json;              // optional: the figures as JSON
  std::string out;               // optional: keep each run's outputs in out/run_<k>
  bool progress = false;         // a live progress line on stderr
  std::string laser_backend;     // planar | bullet; empty: the scenario's (planar)
  std::string wheel_model;       // articulated | raycast; empty: the scenario's (articulated)
  double physics_rate_hz = 0.0;  // > 0: replaces the scenario's physics.rate_hz (200)
  int threads = 0;               // RunOptions::threads (0: every hardware thread)
};

// Adds `bench` with its `hall` subcommand; returns `bench hall`.
CLI::App* AddBenchCommand(CLI::App* app, BenchArgs* args);
// Throws scenarios::InputError for bad files; returns the exit code.
int RunBenchCommand(const BenchArgs& args);

}  // namespace pavilion::cli
