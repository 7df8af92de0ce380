// layerlab render-target TARGET.json --out DIR: renders a target scene
// (docs/target-format.md) into a light-field folder (docs/lightfield-format.md),
// color and depth. Progress goes to stderr (framework/progress.h).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/exit_status.h"
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
  cmd->add_option("--out", options->out_dir, "Light-field folder to write (created if needed)")->required();
  // The form before --out, refused naming it (before CLI11 finds --out missing).
  cmd->add_option_function<std::string>("out_dir",
                                        [](const std::string& folder) {
                                          throw UsageError("render-target: the output folder is given as --out " +
                                                           folder + " (as every command takes it)");
                                        })
      ->group("");
  cmd->callback([options] {
    TargetScene target = LoadTarget(options->target);
    StagedOutput stage(options->out_dir, "render-target", {"views", "depth", "lightfield.json"},
                       {{options->target, "the target scene"}});
    const LightFieldGeometry& g = target.geometry;
    char what[200];
    std::snprintf(what, sizeof what, "%d x %d pixels, %d samples per pixel; %s", g.cols, g.rows,
                  target.samples_per_pixel, target.description.c_str());
    RenderStats stats;
    Progress progress("render-target", size_t(g.rows));
    LightField lf = RenderTarget(target, &stats, [&](size_t done, size_t) {
      progress.Update(done, "pixel rows of every view, " + std::string(what));
    });
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
    CommandResult result("render-target");
    result["out"] = options->out_dir;
    result["views"] = {g.views_x, g.views_y};
    result["pixels_per_view"] = {g.cols, g.rows};
    result["rays"] = stats.rays;
    result["seconds"] = stats.seconds;
    result.Print();
  });
}

}  // namespace layerlab::app
