// layerlab render-target TARGET.json OUT_DIR: renders a target scene
// (docs/target-format.md) into a light-field folder (docs/lightfield-format.md),
// color and depth. Progress goes to stderr, one line per tenth of the views.
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>

#include "app/commands.h"
#include "framework/error.h"
#include "framework/lightfield_io.h"
#include "framework/staged_output.h"
#include "targets/target_renderer.h"
#include "targets/target_scene.h"

namespace layerlab::app {

void AddRenderTargetCommand(CLI::App& app) {
  struct Options {
    std::string target, out_dir;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd =
      app.add_subcommand("render-target", "Render a target scene (planes, meshes) into a light-field folder");
  cmd->add_option("target", options->target, "Target scene file (JSON)")->required();
  cmd->add_option("out_dir", options->out_dir, "Light-field folder to write (created if needed)")->required();
  cmd->callback([options] {
    TargetScene target = LoadTarget(options->target);
    StagedOutput stage(options->out_dir, "render-target", {"views", "depth", "lightfield.json"},
                       {{options->target, "the target scene"}});
    const LightFieldGeometry& g = target.geometry;
    std::fprintf(stderr, "render-target: %d x %d views of %d x %d pixels, %d samples per pixel; %s\n", g.views_x,
                 g.views_y, g.cols, g.rows, target.samples_per_pixel, target.description.c_str());
    std::mutex print_mutex;
    size_t printed_tenths = 0;
    RenderStats stats;
    LightField lf = RenderTarget(target, &stats, [&](size_t done, size_t total) {
      std::lock_guard<std::mutex> lock(print_mutex);
      size_t tenths = done * 10 / total;
      if (tenths <= printed_tenths && done != total) return;
      printed_tenths = tenths;
      std::fprintf(stderr, "render-target: %zu / %zu views rendered\n", done, total);
    });
    try {
      WriteLightField(lf, stage.staging());
    } catch (const Error& e) {
      throw stage.Explain(e);
    }
    stage.Commit();
    std::fprintf(stderr, "render-target: %.2f s, %llu rays (%.1f Mrays/s); wrote %s\n", stats.seconds,
                 static_cast<unsigned long long>(stats.rays), stats.rays / stats.seconds / 1e6,
                 options->out_dir.c_str());
  });
}

}  // namespace layerlab::app
