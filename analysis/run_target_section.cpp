// The run's target: read from its folder, or rendered from its scene and kept
// in OUT/target, where the next run reuses it while the scene is unchanged.
#include <filesystem>
#include <utility>

#include "layerlab/analysis/report_sections.h"
#include "layerlab/analysis/run_steps.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

std::string RunTarget(RunState& s) {
  const RenderCache cache{(fs::path(s.request.out) / "target").string(), (s.out / "target").string(),
                          s.request.shared_renders};
#if LAYERLAB_WITH_EMBREE
  s.target = LoadOrRenderTarget(s.in.solve, "target", &cache, std::move(s.in.target_scene));
#else
  s.target = LoadOrRenderTarget(s.in.solve, "target", &cache);
#endif
  fs::create_directories(s.out / "target");
  const std::array<int, 2> size =
      WriteCenterView(s.target->light_field, (s.out / "target" / "center_view.png").string());
  std::vector<std::pair<std::string, std::string>> links;
  if (s.target->rendered)
    links = {{"light field", "target/lightfield/lightfield.json"}, {"render record", "target/render.json"}};
  ReportImage center = Picture("center view (sRGB, 1 = white)", "target/center_view.png", links);
  center.width = size[0], center.height = size[1];
  s.page.sections.push_back(
      {"target", "Target", {"target/center_view.png"}, TargetHtml(DescribeTarget(*s.target), center)});
  return s.target->reused     ? "read the target's earlier render"
         : s.target->rendered ? "render the target"
                              : "load the target";
}

}  // namespace

RunSection TargetRunSection() {
  return {"target", [](const RunInputs& in) { return in.has_target(); }, RunTarget};
}

}  // namespace layerlab
