#include "systems/compile.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <set>

#include "systems/optics.h"

namespace layerlab {
namespace {

// One optical action between the eye and a branch's front panel.
struct PathStep {
  const Element* element;
  size_t port;  // for combiners
};

class Walker {
 public:
  explicit Walker(const Scene& scene) : scene_(scene) {}

  DisplaySystem Run() {
    const SceneNode& eye_node = FindEye();
    system_.file = scene_.file;
    system_.name = scene_.name;
    system_.eye = static_cast<const EyeElement&>(*eye_node.element).model();
    visited_.insert(&eye_node);
    stack_.push_back(&eye_node);

    const SceneNode& lens_node = Follow(eye_node, 0, {ElementKind::kLens});
    const auto& lens = static_cast<const LensElement&>(*lens_node.element);
    stack_.push_back(&lens_node);
    system_.lens = lens.name();
    system_.focal_length = lens.focal_length();
    system_.clear_aperture = lens.clear_aperture();
    if (system_.eye.eye_relief >= system_.focal_length)
      Fail(lens_node.where.child("focal_length"),
           "the eye relief (" + Mm(system_.eye.eye_relief) + ") must be shorter than the focal length (" +
               Mm(system_.focal_length) + ") to float the panels in front of the eye");

    const SceneNode& first = Follow(lens_node, 0, kAfterLens);
    Walk(first, {}, false, false, "");

    for (const SceneNode& node : scene_.nodes)
      if (!visited_.count(&node))
        Fail(node.where, "element \"" + node.element->name() + "\" (" + node.element->type() +
                             ") is not on the optical path from the eye");
    Finish();
    return std::move(system_);
  }

 private:
  inline static const std::vector<ElementKind> kAfterLens = {ElementKind::kCombiner, ElementKind::kInlineOptic,
                                                             ElementKind::kPanel};

  [[noreturn]] static void Fail(const Location& at, const std::string& message) { throw Error(at, message); }

  static std::string Mm(double meters) { return FormatFixed(meters * 1e3, 2) + " mm"; }

  const SceneNode& FindEye() const {
    const SceneNode* eye = nullptr;
    for (const SceneNode& node : scene_.nodes) {
      if (node.element->kind() != ElementKind::kEye) continue;
      if (eye)
        Fail(node.where, "a second eye \"" + node.element->name() + "\"; the scene already has \"" +
                             eye->element->name() + "\" (one eye per scene)");
      eye = &node;
    }
    if (!eye) Fail({scene_.file, "/elements"}, "the scene has no eye; the optical path starts at an element of type \"eye\"");
    return *eye;
  }

  // The node that `from`'s port leads to, checked for existence, loops and kind.
  const SceneNode& Follow(const SceneNode& from, size_t port, const std::vector<ElementKind>& expected) {
    const std::string port_name = from.element->output_ports()[port];
    const std::string& target = from.outputs[port];
    Location at = from.where.child(port_name);
    const SceneNode* next = scene_.find(target);
    if (!next) {
      std::vector<std::string> names;
      for (const SceneNode& n : scene_.nodes) names.push_back(n.element->name());
      std::string msg = "dangling connection: no element is named \"" + target + "\"";
      if (auto near = ClosestWord(target, names)) msg += "; did you mean \"" + *near + "\"?";
      Fail(at, msg);
    }
    if (std::find(stack_.begin(), stack_.end(), next) != stack_.end() || next == &from)
      Fail(at, "cyclic connection: \"" + target + "\" is already on the path from the eye to \"" +
                   from.element->name() + "\"");
    if (visited_.count(next))
      Fail(at, "\"" + target + "\" is already reached by another connection; each element sits on one optical path");
    if (std::find(expected.begin(), expected.end(), next->element->kind()) == expected.end()) {
      std::vector<std::string> kinds;
      for (ElementKind k : expected) kinds.push_back(KindName(k));
      Fail(at, "\"" + target + "\" is " + next->element->type() + ", " + KindName(next->element->kind()) + "; " +
                   JoinWords(kinds) + " was expected here");
    }
    visited_.insert(next);
    return *next;
  }

  void Walk(const SceneNode& node, std::vector<PathStep> path, bool flip_x, bool flip_y, const std::string& label) {
    stack_.push_back(&node);
    const Element& e = *node.element;
    if (e.kind() == ElementKind::kCombiner) {
      const auto& combiner = static_cast<const CombinerElement&>(e);
      ++combiners_;
      for (size_t port = 0; port < e.output_ports().size(); ++port) {
        std::vector<PathStep> branch_path = path;
        branch_path.push_back({&e, port});
        const SceneNode& next = Follow(node, port, kAfterLens);
        std::string branch_label = (label.empty() ? "" : label + "/") + e.name() + "." + e.output_ports()[port];
        Walk(next, branch_path, flip_x != combiner.flips_x(port), flip_y != combiner.flips_y(port), branch_label);
      }
    } else if (e.kind() == ElementKind::kInlineOptic) {
      path.push_back({&e, 0});
      Walk(Follow(node, 0, kAfterLens), path, flip_x, flip_y, label);
    } else {
      Stack(node, path, flip_x, flip_y, label.empty() ? "main" : label);
    }
    stack_.pop_back();
  }

  // A panel stack from its front panel back to the backlight.
  void Stack(const SceneNode& front, const std::vector<PathStep>& path, bool flip_x, bool flip_y,
             const std::string& label) {
    Branch branch;
    branch.name = label;
    int branch_index = static_cast<int>(system_.branches.size());
    const SceneNode* node = &front;
    std::optional<VirtualLayer> previous;
    Rgb panels_transmittance = {1, 1, 1};
    double polarization_angle = 0;
    while (node->element->kind() == ElementKind::kPanel) {
      const auto& panel = static_cast<const PanelElement&>(*node->element);
      VirtualLayer layer = Float(*node, panel.spec(), flip_x, flip_y);
      layer.branch = branch_index;
      layer.position_in_branch = static_cast<int>(branch.layers.size());
      if (previous) CheckOrder(*previous, layer, *node);
      if (branch.layers.empty()) polarization_angle = panel.spec().polarization_angle;
      for (int c = 0; c < 3; ++c) panels_transmittance[c] *= panel.spec().max_transmittance[c];
      branch.layers.push_back(static_cast<int>(system_.layers.size()));
      system_.layers.push_back(layer);
      previous = layer;
      stack_.push_back(node);
      node = &Follow(*node, 0, {ElementKind::kPanel, ElementKind::kBacklight});
    }
    stack_.resize(stack_.size() - branch.layers.size());
    const auto& backlight = static_cast<const BacklightElement&>(*node->element);
    branch.backlight = backlight.name();
    branch.backlight_luminance = backlight.luminance();
    branch.optics_efficiency = PathEfficiency(path, polarization_angle);
    for (int c = 0; c < 3; ++c) branch.efficiency[c] = branch.optics_efficiency[c] * panels_transmittance[c];
    system_.branches.push_back(branch);
  }

  VirtualLayer Float(const SceneNode& node, const PanelSpec& spec, bool flip_x, bool flip_y) {
    const double f = system_.focal_length, e = system_.eye.eye_relief;
    VirtualLayer layer;
    layer.name = node.element->name();
    layer.panel = spec;
    if (spec.virtual_depth) {
      double D = spec.virtual_depth->diopters;
      if (!(D < 1.0 / e))
        Fail(node.where.child("virtual_depth"),
             "a virtual image at " + FormatFixed(D, 3) + " D (" + Mm(1.0 / D) +
                 " from the eye) would not lie behind the lens, which is " + Mm(e) + " from the eye (below " +
                 FormatFixed(1.0 / e, 1) + " D)");
      layer.panel_distance = PanelDistanceForDiopters(D, f, e);
    } else {
      layer.panel_distance = *spec.distance;
      if (layer.panel_distance > f)
        Fail(node.where.child("distance"),
             "the panel is " + Mm(layer.panel_distance) + " from the lens, beyond the focal length " + Mm(f) +
                 ": the lens would form a real, inverted image, not a floating virtual one");
    }
    FloatedImage image = FloatPanel(layer.panel_distance, f, e);
    layer.diopters = image.diopters;
    layer.depth = image.depth;
    layer.magnification = image.magnification;
    layer.pitch_x = image.magnification * spec.pitch_x;
    layer.pitch_y = image.magnification * spec.pitch_y;
    layer.tan_pitch_x = image.tan_per_meter * spec.pitch_x;
    layer.tan_pitch_y = image.tan_per_meter * spec.pitch_y;
    layer.cols = static_cast<int>(spec.active_cols);
    layer.rows = static_cast<int>(spec.active_rows);
    layer.offset_x = image.tan_per_meter * spec.offset[0];
    layer.offset_y = image.tan_per_meter * spec.offset[1];
    layer.rotation = spec.rotation;
    layer.flip_x = flip_x != spec.reversed;
    layer.flip_y = flip_y;
    layer.fov_x = FieldOfView(layer.tan_pitch_x, layer.cols);
    layer.fov_y = FieldOfView(layer.tan_pitch_y, layer.rows);
    layer.max_cpd = std::max(NyquistCyclesPerDegree(layer.tan_pitch_x), NyquistCyclesPerDegree(layer.tan_pitch_y));
    if (spec.virtual_depth == std::nullopt && image.diopters == 0)
      system_.warnings.push_back("panel \"" + layer.name + "\" sits at the focal plane: its image is at infinity (0 D)");
    return layer;
  }

  void CheckOrder(const VirtualLayer& front, const VirtualLayer& back, const SceneNode& node) const {
    const char* key = back.panel.virtual_depth ? "virtual_depth" : "distance";
    if (back.panel_distance == front.panel_distance || back.diopters == front.diopters)
      Fail(node.where.child(key), "panels \"" + front.name + "\" and \"" + back.name + "\" of one stack are at the same depth (" +
                                      FormatFixed(back.diopters, 4) + " D); a stack needs distinct planes");
    if (back.panel_distance < front.panel_distance)
      Fail(node.where.child(key), "panel \"" + back.name + "\" is behind \"" + front.name + "\" in the stack but nearer the lens (" +
                                      Mm(back.panel_distance) + " < " + Mm(front.panel_distance) +
                                      "); list each stack from the eye outward");
  }

  Rgb PathEfficiency(const std::vector<PathStep>& path, double polarization_angle) {
    bool polarized = std::any_of(path.begin(), path.end(), [](const PathStep& s) { return s.element->polarizing(); });
    system_.polarization_tracked = system_.polarization_tracked || polarized;
    Light light;
    for (ChannelLight& channel : light) {
      channel.polarized = polarized;
      if (polarized) channel.field = LinearPolarization(polarization_angle);
    }
    for (auto step = path.rbegin(); step != path.rend(); ++step) {  // from the panel toward the eye
      if (step->element->kind() == ElementKind::kCombiner)
        static_cast<const CombinerElement*>(step->element)->transfer(step->port, light);
      else
        static_cast<const InlineOpticElement*>(step->element)->transfer(light);
    }
    return {light[0].power(), light[1].power(), light[2].power()};
  }

  void Finish();

  const Scene& scene_;
  DisplaySystem system_;
  std::set<const SceneNode*> visited_;
  std::vector<const SceneNode*> stack_;
  int combiners_ = 0;
};

void Walker::Finish() {
  auto& layers = system_.layers;
  // Farthest first, as the paper numbers its panels.
  std::vector<int> order(layers.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return layers[a].diopters < layers[b].diopters; });
  std::vector<int> new_index(layers.size());
  std::vector<VirtualLayer> sorted;
  for (size_t i = 0; i < order.size(); ++i) new_index[order[i]] = static_cast<int>(i), sorted.push_back(layers[order[i]]);
  layers = std::move(sorted);
  for (Branch& b : system_.branches)
    for (int& k : b.layers) k = new_index[k];

  system_.fov_x = system_.fov_y = INFINITY;
  for (const VirtualLayer& l : layers) {
    system_.fov_x = std::min(system_.fov_x, l.fov_x);
    system_.fov_y = std::min(system_.fov_y, l.fov_y);
    system_.max_cpd = std::max(system_.max_cpd, l.max_cpd);
  }

  double emitted = 0;
  for (const Branch& b : system_.branches) {
    emitted += b.backlight_luminance;
    for (int c = 0; c < 3; ++c) system_.peak_luminance[c] += b.backlight_luminance * b.efficiency[c];
  }
  for (int c = 0; c < 3; ++c) {
    system_.brightness_efficiency[c] = system_.peak_luminance[c] / emitted;
    system_.luminance_efficiency += kLuminanceWeights[c] * system_.brightness_efficiency[c];
  }

  const EyeModel& eye = system_.eye;
  if (system_.clear_aperture) {
    double radius = *system_.clear_aperture / 2;
    auto field = [&](double eyebox) { return 2 * std::atan(std::max(0.0, radius - eyebox / 2) / eye.eye_relief); };
    system_.vignetting_free_fov_x = field(eye.eyebox_width);
    system_.vignetting_free_fov_y = field(eye.eyebox_height);
    if (*system_.vignetting_free_fov_x < system_.fov_x || *system_.vignetting_free_fov_y < system_.fov_y)
      system_.warnings.push_back("the lens aperture vignettes the field of view from the edges of the eyebox");
  }

  auto& parts = system_.components;
  parts.push_back("thin-lens floating (" + std::to_string(layers.size()) + " virtual layers)");
  if (system_.branches.size() > 1)
    parts.push_back("additive combination of " + std::to_string(system_.branches.size()) + " branches (" +
                    std::to_string(combiners_) + " combiner" + (combiners_ > 1 ? "s" : "") + ")");
  int products = 0;
  for (const Branch& b : system_.branches) products += b.layers.size() > 1;
  if (products) parts.push_back("multiplicative stacks in " + std::to_string(products) + " branch" + (products > 1 ? "es" : ""));
  parts.push_back(system_.polarization_tracked ? "polarization (Jones vectors per channel)"
                                               : "no polarization model (no polarizing element)");
  if (std::any_of(layers.begin(), layers.end(), [](const VirtualLayer& l) { return l.flip_x || l.flip_y; }))
    parts.push_back("mirrored layers (reversed panels or reflected branches)");
  if (std::any_of(layers.begin(), layers.end(), [](const VirtualLayer& l) { return l.rotation != 0; }))
    parts.push_back("rotated layers (general projection path)");
}

}  // namespace

DisplaySystem Compile(const Scene& scene) { return Walker(scene).Run(); }

}  // namespace layerlab
