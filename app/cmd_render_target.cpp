// layerlab render-target TARGET.json OUT_DIR: renders a target scene
// (docs/target-format.md) into a light-field folder (docs/lightfield-format.md),
// color and depth. Progress goes to stderr (framework/progress.h).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "layerlab/app/commands.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/targets/target_renderer.h"
#include "layerlab/targets/target_scene.h"

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
    char what[200];
    std::snprintf(what, sizeof what, "%d x %d pixels, %d samples per pixel; %s", g.cols, g.rows,
                  target.samples_per_pixel, target.description.c_str());
    RenderStats stats;
    Progress progress("render-target", g.view_count());
    LightField lf = RenderTarget(target, &stats,
                                 [&](size_t done, size_t) { progress.Update(done, "views, " + std::string(what)); });
    std::snprintf(what, sizeof what, "%llu rays (%.1f Mrays/s)", static_cast<unsigned long long>(stats.rays),
                  stats.rays / std::max(stats.seconds, 1e-9) / 1e6);
    progress.Finish(what);
    try {
      WriteLightField(lf, stage.staging());
    } catch (const Error& e) {
      throw stage.Explain(e);
    }
    stage.Commit();
    Note("render-target: wrote " + options->out_dir);
  });
}

}  // namespace layerlab::app
