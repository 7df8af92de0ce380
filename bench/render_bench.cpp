// The target's render (issue 49): examples/targets/dice.json, the README's
// main job's target, 169 views of 400 x 200 at 4 samples a pixel; 3 x 3 views
// of 40 x 20 in a smoke run. Reports rays per second and the seconds a render.
#include <benchmark/benchmark.h>

#include "bench_setup.h"
#include "layerlab/targets/target_renderer.h"
#include "layerlab/targets/target_scene.h"

namespace layerlab::bench {
namespace {

void BM_RenderDiceTarget(benchmark::State& state) {
  TargetScene target = LoadTarget(std::string(LAYERLAB_SOURCE_DIR) + "/examples/targets/dice.json");
  if (Settings().smoke) {
    LightFieldGeometry& g = target.geometry;
    g.window_width_m *= 0.1, g.window_height_m *= 0.1, g.window_left_m *= 0.1, g.window_top_m *= 0.1;
    g.cols = 40, g.rows = 20, g.views_x = g.views_y = 3;
  }
  RenderStats stats;
  for (auto _ : state) {
    LightField lf = RenderTarget(target, &stats);
    benchmark::DoNotOptimize(lf.rgb.data());
  }
  state.counters["Mrays_per_s"] = stats.rays / std::max(stats.seconds, 1e-9) / 1e6;
  state.SetLabel(std::to_string(target.geometry.view_count()) + " views of " + std::to_string(target.geometry.cols) +
                 " x " + std::to_string(target.geometry.rows) + ", " + std::to_string(target.samples_per_pixel) +
                 " samples a pixel");
}

}  // namespace

BENCHMARK(BM_RenderDiceTarget)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace layerlab::bench
