// One evaluation of `layerlab optimize` (design/design_evaluator.h) on the
// reduced example's design problem (examples/optimize/hybrid_small_depths.json):
// the scene written with a new design, its target's cached render read back,
// the hybrid solve and its records, as an optimization runs each one. The
// counter evaluations_per_minute is what a budget buys on this machine.
#if LAYERLAB_WITH_EMBREE
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <chrono>

#include <filesystem>
#include <string>

#include "layerlab/design/design_evaluator.h"
#include "layerlab/framework/progress.h"

namespace layerlab::bench {
namespace {

void BM_OptimizeEvaluation(benchmark::State& state) {
  const DesignSpec spec =
      ReadDesignSpec(std::string(LAYERLAB_SOURCE_DIR) + "/examples/optimize/hybrid_small_depths.json");
  const std::string out =
      (std::filesystem::temp_directory_path() / ("layerlab_bench_optimize_" + std::to_string(::getpid()))).string();
  std::filesystem::remove_all(out);
  SetVerbosity(Verbosity::kQuiet);
  DesignEvaluator evaluator(spec, out);
  std::vector<double> x;
  for (const DesignVariable& v : spec.variables) x.push_back(v.start);
  evaluator.Evaluate(x);  // renders the target once, as the first evaluation of a run does
  double seconds = 0, total = 0;
  for (auto _ : state) {
    x[0] += 1e-3;  // a design not evaluated yet
    const auto start = std::chrono::steady_clock::now();
    const DesignEvaluation& e = evaluator.Evaluate(x);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.SetIterationTime(seconds);
    total += seconds;
    if (e.failed) state.SkipWithError(e.error.c_str());
  }
  state.counters["evaluations_per_minute"] = 60.0 * static_cast<double>(state.iterations()) / total;
  SetVerbosity(Verbosity::kNormal);
  std::filesystem::remove_all(out);
}

}  // namespace

BENCHMARK(BM_OptimizeEvaluation)->Unit(benchmark::kMillisecond)->UseManualTime();

}  // namespace layerlab::bench
#endif
