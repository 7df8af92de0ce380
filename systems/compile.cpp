#include "layerlab/systems/compile.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "layerlab/elements/splitter_ports.h"
#include "layerlab/eye/pupil_size.h"
#include "layerlab/framework/units.h"
#include "layerlab/lenses/lens_system.h"
#include "layerlab/lenses/paraxial.h"
#include "layerlab/lenses/sequential_trace.h"
#include "layerlab/systems/eye_pose_limits.h"
#include "layerlab/systems/layer_order.h"
#include "layerlab/systems/layer_ray_map.h"
#include "layerlab/systems/lenslet_map.h"
#include "layerlab/systems/optics.h"
#include "layerlab/systems/route_light.h"

namespace layerlab {
namespace {

// What the walk knows at one point of one path from the eye.
struct PathState {
  std::vector<PathStep> steps;              // the elements passed, nearest the eye first
  std::vector<LightStep> light;             // those that act on light
  RayTransfer<double> transfer;             // pupil -> the last placed element
  double placed_at = 0;                     // that element's position (the pupil: 0)
  std::string placed_name;                  // and its name ("" for the pupil)
  std::optional<double> previous_position;  // of the element just before; none when it is flat and unplaced
  std::string previous_name;
  std::optional<size_t> last_power;  // index into steps of the nearest lens or curved mirror
  int powered = 0;                   // lenses and curved mirrors passed
  std::string tunable;               // a focus-tunable element passed, if any
  bool flip_x = false, flip_y = false;
  std::string label;
  size_t length = 0;                       // elements met so far
  int reversals = 0;                       // turns between away from and toward the eye (folded paths)
  std::map<const SceneNode*, int> passes;  // since the first turn: how often each element was met
};

// The farthest a pupil point lies from the pupil's centre (a square's corner).
double PupilReach(const EyeModel& eye) {
  return 0.5 * eye.pupil_diameter_m * (eye.pupil_shape == PupilShape::kSquare ? std::sqrt(2.0) : 1.0);
}

// Limits that keep the compile linear in the scene and the solvers' float products meaningful.
constexpr size_t kMaxPathElements = 256;  // from the eye to a backlight (each layer keeps its path)
constexpr size_t kMaxStackPanels = 32;    // 0.5^32 = 2.3e-10 of white at the solvers' start
constexpr size_t kMaxLayers = 1024;       // virtual layers, over every branch and subframe
// Folded paths (docs/optics.md, "Paths that pass an element more than once"): a route that has turned is
// followed while it can still pass kFaintestRoute of the light and meets no element more than kMaxPasses
// times since its first turn; a stack's other routes are its ghosts when they bring at least kGhostFloor
// of its brightest route's light.
constexpr double kFaintestRoute = 1e-4;
constexpr int kMaxPasses = 8;
constexpr double kGhostFloor = 1e-3;
constexpr size_t kMaxFoldedSteps = 100000;  // elements met on turned routes, over every subframe

std::string Mm(double meters) { return FormatFixed(meters * 1e3, 2) + " mm"; }
std::string Quoted(const std::string& name) { return "\"" + name + "\""; }

class Walker {
 public:
  explicit Walker(const Scene& scene) : scene_(scene) {}

  // pupil_diameter "auto": Watson and Yellott's pupil for the luminance at
  // the eye (default: half the display's peak white, the contrast gratings'
  // mean) over the adapting field (default: the display's field of view).
  void ResolvePupil() {
    EyeModel& eye = system_.eye;
    if (!eye.pupil_auto) {
      WarnWavefrontExtrapolated();
      return;
    }
    const PupilFromLuminance& a = *eye.pupil_auto;
    double white = 0;
    for (int c = 0; c < 3; ++c) white += kLuminanceWeights[c] * system_.peak_luminance_cd_m2[c];
    PupilAdaptation adaptation;
    adaptation.luminance_cd_m2 = a.luminance_cd_m2 ? *a.luminance_cd_m2 : 0.5 * white;
    const std::array<double, 2> field =
        a.field_rad ? *a.field_rad : std::array<double, 2>{system_.fov_x_rad, system_.fov_y_rad};
    adaptation.field_area_deg2 = field[0] * field[1] * kDegreesPerRadian * kDegreesPerRadian;
    adaptation.age_years = a.age_years;
    adaptation.eyes = a.eyes;
    const Location where = FindEye().where.child("pupil_diameter");
    if (!(adaptation.luminance_cd_m2 > 0))
      throw Error(where,
                  "\"auto\" needs a luminance at the eye, and the display's peak white is 0: give pupil_luminance");
    if (!(adaptation.field_area_deg2 > 0) || !std::isfinite(adaptation.field_area_deg2))
      throw Error(where, "\"auto\" needs an adapting field: give pupil_field");
    eye.pupil_diameter_m = WatsonYellottPupilDiameter(adaptation);
    eye.pupil_luminance_used_cd_m2 = adaptation.luminance_cd_m2;
    eye.pupil_field_area_used_deg2 = adaptation.field_area_deg2;
    if (eye.pupil_diameter_m > std::min(eye.eyebox_width_m, eye.eyebox_height_m))
      system_.warnings.push_back("the eye's pupil from luminance, " + FormatFixed(eye.pupil_diameter_m * 1e3, 2) +
                                 " mm, is wider than the eyebox: natural viewing reads the edge views beyond it");
    WarnWavefrontExtrapolated();
  }
  void WarnWavefrontExtrapolated() {
    const EyeModel& eye = system_.eye;
    const double reach = 2 * PupilReach(eye);
    if (!eye.wavefront.empty() && reach > eye.wavefront.pupil_diameter_m * (1 + 1e-9))
      system_.warnings.push_back("the eye's pupil reaches " + FormatFixed(reach * 1e3, 2) + " mm across, beyond the " +
                                 FormatFixed(eye.wavefront.pupil_diameter_m * 1e3, 2) +
                                 " mm its Zernike coefficients were measured at: the wavefront is extrapolated there");
  }

  DisplaySystem Run() {
    const SceneNode& eye_node = FindEye();
    system_.file = scene_.file;
    system_.name = scene_.name;
    system_.eye = static_cast<const EyeElement&>(*eye_node.element).model();
    system_.eye_name = eye_node.element->name();
    system_.subframes = scene_.subframes;
    system_.frame_rate_hz = scene_.frame_rate_hz;
    const int K = scene_.subframes;
    bool time_varying = false;
    for (const SceneNode& node : scene_.nodes) time_varying = time_varying || node.element->powers_given() > 0;

    // Each subframe is its own walk of the same path (a tunable lens takes its
    // power of that subframe); its layers and branches are kept apart.
    {
      std::vector<const SceneNode*> path;
      CheckConnections(eye_node, path);
    }
    for (subframe_ = 0; subframe_ < K; ++subframe_) {
      visited_ = {&eye_node};
      const size_t first_layer = system_.layers.size(), first_branch = system_.branches.size();
      const size_t first_ghost = system_.ghosts.size();
      PathState start;
      start.previous_position = 0.0;
      start.previous_name = eye_node.element->name();
      try {
        Walk(Follow(eye_node, 0), start);
        SettleStacks();
      } catch (const Error& e) {
        if (!time_varying) throw;
        throw Error(e.where(),
                    e.message() + " (in subframe " + std::to_string(subframe_ + 1) + " of " + std::to_string(K) + ")");
      }
      if (K == 1) continue;
      const std::string suffix = "@" + std::to_string(subframe_ + 1);
      for (size_t k = first_layer; k < system_.layers.size(); ++k) {
        system_.layers[k].name += suffix;
        system_.layers[k].subframe = subframe_;
      }
      for (size_t g = first_ghost; g < system_.ghosts.size(); ++g) {
        system_.ghosts[g].name += suffix;
        for (VirtualLayer& layer : system_.ghosts[g].layers) layer.name += suffix, layer.subframe = subframe_;
        for (int c = 0; c < 3; ++c) system_.ghosts[g].optics_efficiency[c] /= K, system_.ghosts[g].efficiency[c] /= K;
      }
      for (size_t b = first_branch; b < system_.branches.size(); ++b) {
        Branch& branch = system_.branches[b];
        branch.name += suffix;
        branch.subframe = subframe_;
        for (int c = 0; c < 3; ++c) {  // the eye sees the mean over subframes
          branch.optics_efficiency[c] /= K;
          branch.efficiency[c] /= K;
        }
      }
    }

    for (const SceneNode& node : scene_.nodes)
      if (!visited_.count(&node))
        Fail(node.where, "element \"" + node.element->name() + "\" (" + node.element->type() + ") " +
                             (predecessor_.count(&node)
                                  ? "is reached by no light: every route to it was left (below " +
                                        FormatFixed(kFaintestRoute * 100, 2) + " % of the light, or past " +
                                        std::to_string(kMaxPasses) + " passes of one element) or ends before it"
                                  : "is not on the optical path from the eye"));
    Finish();
    return std::move(system_);
  }

 private:
  inline static const std::vector<ElementKind> kOptics = {ElementKind::kLens,     ElementKind::kMirror,
                                                          ElementKind::kCombiner, ElementKind::kInlineOptic,
                                                          ElementKind::kPanel,    ElementKind::kWorld};

  [[noreturn]] static void Fail(const Location& at, const std::string& message) { throw Error(at, message); }

  // Real lenses' paraxial quantities (the layers' depths and pitches) are the
  // green channel's; each channel's own rays go through the layer's ray map.
  double DesignWavelength() const { return system_.eye.channel_wavelengths_m[1]; }

  const SceneNode& FindEye() const {
    const SceneNode* eye = nullptr;
    for (const SceneNode& node : scene_.nodes) {
      if (node.element->kind() != ElementKind::kEye) continue;
      if (eye)
        Fail(node.where, "a second eye \"" + node.element->name() + "\"; the scene already has \"" +
                             eye->element->name() + "\" (one eye per scene)");
      eye = &node;
    }
    if (!eye)
      Fail({scene_.file, "/elements"}, "the scene has no eye; the optical path starts at an element of type \"eye\"");
    return *eye;
  }

  // The connections from the eye, depth first: each names an element, none leads back onto its own path, and
  // no element is reached by two. Light that passes an element again does so by a reflection back toward the
  // eye, which the walk follows (Walk, WalkBack); the connections themselves form a tree.
  void CheckConnections(const SceneNode& node, std::vector<const SceneNode*>& path) {
    // A stack's panels have their own limit, kMaxStackPanels, which Stack says: the check stops at the panel past it.
    size_t panels = node.element->kind() == ElementKind::kPanel;
    for (auto n = path.rbegin(); panels && n != path.rend() && (*n)->element->kind() == ElementKind::kPanel; ++n)
      ++panels;
    if (panels > kMaxStackPanels) return;
    if (path.size() >= kMaxPathElements && !panels && node.element->kind() != ElementKind::kBacklight)
      Fail(node.where, "the path from the eye to " + Quoted(node.element->name()) + " passes more than " +
                           std::to_string(kMaxPathElements) + " elements; layerlab compiles paths of up to " +
                           std::to_string(kMaxPathElements));
    path.push_back(&node);
    if (node.element->kind() == ElementKind::kCombiner) RequireSplitterPorts(node);
    for (size_t port = 0; port < node.outputs.size(); ++port) {
      const std::string& target = node.outputs[port];
      if (target.empty()) continue;  // nothing there
      const Location at = node.where.child(node.element->output_ports()[port]);
      const SceneNode* next = scene_.find(target);
      if (!next) {
        std::vector<std::string> names;
        for (const SceneNode& n : scene_.nodes) names.push_back(n.element->name());
        std::string msg = "dangling connection: no element is named \"" + target + "\"";
        if (auto near = ClosestWord(target, names)) msg += "; did you mean \"" + *near + "\"?";
        Fail(at, msg);
      }
      if (std::find(path.begin(), path.end(), next) != path.end())
        Fail(at, "cyclic connection: \"" + target + "\" is already on the path from the eye to \"" +
                     node.element->name() +
                     "\"; light that passes an element again gets there by a reflection back toward the eye, "
                     "which layerlab follows itself: a half_mirror or pbs with \"fold\": \"back\" (at normal "
                     "incidence) or the \"reflected_from_behind\" port of one folded sideways (docs/optics.md, "
                     "\"Paths that pass an element more than once\")");
      if (!predecessor_.emplace(next, Predecessor{&node, port}).second)
        Fail(at, "\"" + target + "\" is already reached by another connection; each element sits on one optical path");
      const std::vector<ElementKind>& expected = ExpectedAfter(node);
      if (std::find(expected.begin(), expected.end(), next->element->kind()) == expected.end()) {
        std::vector<std::string> kinds;
        for (ElementKind k : expected) kinds.push_back(KindName(k));
        Fail(at, "\"" + target + "\" is " + next->element->type() + ", " + KindName(next->element->kind()) + "; " +
                     JoinWords(kinds) + " was expected here");
      }
      CheckConnections(*next, path);
    }
    path.pop_back();
  }

  // The walk reads a combiner's ports as a splitter's (elements/splitter_ports.h); a combiner of another layout
  // (a registered type of one's own) is refused rather than misread.
  void RequireSplitterPorts(const SceneNode& node) const {
    const auto& combiner = static_cast<const CombinerElement&>(*node.element);
    const std::vector<std::string> ports = combiner.output_ports();
    const std::vector<std::string> expected = {"transmitted", "reflected", "reflected_from_behind"};
    const size_t count = combiner.reflects_back() ? 1 : ports.size();
    bool splitter =
        !ports.empty() && ports.size() <= 3 && (combiner.reflects_back() ? ports.size() == 1 : ports.size() >= 2);
    for (size_t k = 0; splitter && k < count; ++k) splitter = ports[k] == expected[k];
    if (!splitter)
      Fail(node.where, "the combiner " + Quoted(node.element->name()) + " (" + node.element->type() + ") has ports " +
                           JoinWords(ports, ", ") +
                           "; layerlab walks a combiner's ports as a splitter's: transmitted, reflected and "
                           "optionally reflected_from_behind, or transmitted alone when it reflects back");
  }

  // The node that `from`'s port leads to (CheckConnections has checked it), marked as reached.
  const SceneNode& Follow(const SceneNode& from, size_t port) {
    const SceneNode* next = scene_.find(from.outputs[port]);
    visited_.insert(next);
    return *next;
  }

  // What may follow `from`: after a panel, the rest of its stack; elsewhere, optics.
  static const std::vector<ElementKind>& ExpectedAfter(const SceneNode& from) {
    static const std::vector<ElementKind> stack = {ElementKind::kPanel, ElementKind::kBacklight};
    return from.element->kind() == ElementKind::kPanel ? stack : kOptics;
  }

  // "gap" counts from the element before, which must have a place of its own.
  double AfterPrevious(const SceneNode& node, const PathState& state, double gap) const {
    if (!state.previous_position)
      Fail(node.where.child("gap"), "\"gap\" is measured from " + Quoted(state.previous_name) +
                                        ", which has no place of its own (a flat element without \"gap\"); give " +
                                        Quoted(state.previous_name) + " a \"gap\" as well");
    return *state.previous_position + gap;
  }

  // Moves the state's transfer to `position` (beyond the last placed element).
  static void Advance(PathState& state, double position, const std::string& name) {
    state.transfer = state.transfer.then_gap(position - state.placed_at);
    state.placed_at = position;
    state.placed_name = name;
  }

  // A lens, mirror, combiner or in-line optic: its place, power, flips and light. `action`: what a combiner does
  // (kTransmittedPort, kReflectedPort); `gap`: the path length from the element met before it; `front`: the
  // light meets a combiner's face toward the eye (its reflection's power is the opposite on the other face).
  PathStep Pass(const SceneNode& node, size_t action, PathState& state, std::optional<double> gap, bool front) {
    const Element& e = *node.element;
    if (e.powers_given() > 0 && e.powers_given() != scene_.subframes)
      Fail(node.where, Quoted(e.name()) + " gives " + std::to_string(e.powers_given()) +
                           " powers, one per subframe, but the scene shows " + std::to_string(scene_.subframes) +
                           " (\"subframes\": " + std::to_string(scene_.subframes) + " at the top of the scene)");
    double power = e.power_in_subframe(subframe_);
    if (e.kind() == ElementKind::kCombiner && action == kReflectedPort)
      power = static_cast<const CombinerElement&>(e).reflection_power() * (front ? 1 : -1);
    std::shared_ptr<const lenses::LensSystem> lens;
    lenses::VertexTransfer vertices;
    if (e.kind() == ElementKind::kLens) lens = static_cast<const LensElement&>(e).lens_system();
    if (lens) {
      vertices = lenses::TransferFromMatrices(lens->IsCentred() ? *lens : Centred(*lens), DesignWavelength());
      power = -vertices.c;
      if (!lens->IsCentred() && subframe_ == 0)
        system_.warnings.push_back(Quoted(e.name()) +
                                   " is tilted or decentred: the layers' depths, pitches and fields are the centred "
                                   "lens's (first-order optics needs a centred one); the rays are traced through it as "
                                   "mounted");
    }
    const bool powered = e.kind() == ElementKind::kLens || power != 0;
    if (e.powers_given() > 0) state.tunable = e.name();
    PathStep step{e.name(),     e.type(), e.kind(), "", std::nullopt, power, false, false,
                  std::nullopt, {},       nullptr,  0,  std::nullopt};
    if (lens) step.lens_system = lens, step.axial_length_m = lens->vertex_z_m(lens->size() - 1);
    const bool first_power = !state.last_power;
    if (gap) {
      step.position_m = AfterPrevious(node, state, *gap);
    } else if (powered && first_power) {
      step.position_m = system_.eye.eye_relief_m;  // the magnifier, as the paper places it
      if (!(*step.position_m > state.placed_at))
        Fail(node.where.child("gap"), Quoted(e.name()) + " would sit at the eye's eye_relief (" + Mm(*step.position_m) +
                                          " from the pupil), which is not behind " + Quoted(state.placed_name) + " (" +
                                          Mm(state.placed_at) + "); give it a \"gap\" from " +
                                          Quoted(state.previous_name));
    } else if (powered) {
      Fail(node.where.child("gap"), "missing placement: " + Quoted(e.name()) +
                                        " is not the first lens or curved mirror on its path, so the eye's "
                                        "eye_relief does not place it; give \"gap\" (the path length from " +
                                        Quoted(state.previous_name) + ")");
    }
    if (step.position_m) {
      Advance(state, *step.position_m, e.name());
      step.arrival = state.transfer;
      if (lens) {  // through the lens's vertex planes; the next gap counts from its last vertex
        state.transfer = state.transfer.then({vertices.a, vertices.b, vertices.c, vertices.d});
        state.placed_at += step.axial_length_m;
      } else {
        state.transfer = state.transfer.then_power(power);
      }
    }
    if (powered) {
      state.last_power = state.steps.size();
      ++state.powered;
    }
    if (e.kind() == ElementKind::kLens) {
      step.clear_aperture_m = static_cast<const LensElement&>(e).clear_aperture();
      if (const LensArraySpec* array = static_cast<const LensElement&>(e).lens_array()) step.lens_array = *array;
    }
    if (e.kind() == ElementKind::kMirror) {
      const auto& mirror = static_cast<const MirrorElement&>(e);
      step.flips_x = mirror.flips_x();
      step.flips_y = mirror.flips_y();
    }
    if (e.kind() == ElementKind::kCombiner) {
      const auto& combiner = static_cast<const CombinerElement&>(e);
      step.port = ActionName(action);
      step.flips_x = combiner.flips_x(action);
      step.flips_y = combiner.flips_y(action);
    }
    state.flip_x = state.flip_x != step.flips_x;
    state.flip_y = state.flip_y != step.flips_y;
    state.previous_position = step.position_m;
    if (step.position_m) *state.previous_position += step.axial_length_m;
    state.previous_name = e.name();
    state.light.push_back({&e, action});
    state.steps.push_back(step);
    return step;
  }

  static std::string ActionName(size_t action) { return action == kReflectedPort ? "reflected" : "transmitted"; }

  // Light met going away from the eye, from the element before it.
  void Walk(const SceneNode& node, PathState state) {
    if (!Follows(node, state)) return;
    const Element& e = *node.element;
    if (e.kind() == ElementKind::kCombiner) {
      if (state.reversals == 0) ++combiners_;
      const bool back = static_cast<const CombinerElement&>(e).reflects_back();
      Split(node, kTransmittedPort, true, state, e.gap(), [&](PathState s) { Forward(node, kTransmittedPort, s); });
      Split(node, kReflectedPort, true, state, e.gap(), [&](PathState s) {
        if (!back) return Forward(node, kReflectedPort, s);
        ++s.reversals;  // at normal incidence: back along the path toward the eye
        Back(node, s);
      });
    } else if (e.kind() == ElementKind::kPanel) {
      if (state.label.empty()) state.label = "main";
      arrivals_.emplace_back(&node, std::move(state));
    } else if (e.kind() == ElementKind::kWorld) {
      SeeThrough(node, state);
    } else {
      Pass(node, 0, state, e.gap(), true);
      Forward(node, 0, state);
    }
  }

  // Light met going toward the eye, returning from `node`'s port `port` after a reflection behind it; `gap`:
  // the path length to it from the element met before (that element's own "gap").
  void WalkBack(const SceneNode& node, size_t port, PathState state, std::optional<double> gap) {
    const Element& e = *node.element;
    if (e.kind() == ElementKind::kEye || IntoTheEye(node)) return;  // sent back into the eye: nothing seen there
    if (!Follows(node, state)) return;
    if (e.kind() != ElementKind::kCombiner) {
      Pass(node, 0, state, gap, true);
      return Back(node, state);
    }
    // Each action sends the light back toward the eye or, turning again, on into one of its ports.
    auto on = [&](size_t to) { return [&, to](PathState s) { ++s.reversals, Forward(node, to, s); }; };
    auto back = [&](PathState s) { Back(node, s); };
    if (static_cast<const CombinerElement&>(e).reflects_back()) {
      Split(node, kTransmittedPort, false, state, gap, back);
      Split(node, kReflectedPort, false, state, gap, on(kTransmittedPort));
    } else if (port == kTransmittedPort) {  // from behind: on toward the eye, or reflected to the fourth side
      Split(node, kTransmittedPort, false, state, gap, back);
      Split(node, kReflectedPort, false, state, gap, on(kBehindPort));
    } else if (port == kReflectedPort) {  // from its reflected branch: reflected toward the eye, or across
      Split(node, kReflectedPort, true, state, gap, back);
      Split(node, kTransmittedPort, true, state, gap, on(kBehindPort));
    } else {  // from the fourth side: across into the reflected branch, or reflected into the transmitted one
      Split(node, kTransmittedPort, false, state, gap, on(kReflectedPort));
      Split(node, kReflectedPort, false, state, gap, on(kTransmittedPort));
    }
  }

  // Whether light going back toward the eye from `node` can only reach the eye (no combiner lies between).
  bool IntoTheEye(const SceneNode& node) const {
    for (const SceneNode* n = &node; n->element->kind() != ElementKind::kEye; n = predecessor_.at(n).node)
      if (n->element->kind() == ElementKind::kCombiner) return false;
    return true;
  }

  // A combiner's action on a copy of the route, named in its label, then `go` on.
  template <typename Go>
  void Split(const SceneNode& node, size_t action, bool front, const PathState& state, std::optional<double> gap,
             Go go) {
    PathState branch = state;
    Pass(node, action, branch, gap, front);
    branch.label = (state.label.empty() ? "" : state.label + "/") + node.element->name() + "." + ActionName(action);
    go(std::move(branch));
  }

  // On from `node`'s port away from the eye; a side with nothing there ends the route in the dark.
  void Forward(const SceneNode& node, size_t port, PathState& state) {
    if (port >= node.outputs.size() || node.outputs[port].empty()) return;
    Walk(Follow(node, port), std::move(state));
  }

  // Back from `node` toward the eye, to the element that leads to it.
  void Back(const SceneNode& node, PathState& state) {
    const Predecessor& before = predecessor_.at(&node);
    if (before.node->element->kind() != ElementKind::kEye && !node.element->gap())
      Fail(node.where, "light reflected back toward the eye goes from " + Quoted(node.element->name()) + " back to " +
                           Quoted(before.node->element->name()) + ", a path length the scene does not give: give " +
                           Quoted(node.element->name()) + " a \"gap\" (from " + Quoted(before.node->element->name()) +
                           ")");
    WalkBack(*before.node, before.port, std::move(state), node.element->gap());
  }

  // Whether the route goes on to `node`: a route that has turned is followed while it may still bring
  // kFaintestRoute of the light, meeting each element at most kMaxPasses times since its first turn.
  bool Follows(const SceneNode& node, PathState& state) {
    if (++state.length > kMaxPathElements)
      Fail(node.where, "the path from the eye to " + Quoted(node.element->name()) + " passes more than " +
                           std::to_string(kMaxPathElements) + " elements; layerlab compiles paths of up to " +
                           std::to_string(kMaxPathElements));
    if (state.reversals == 0) return true;
    const Element& e = *node.element;
    if (e.kind() == ElementKind::kLens && static_cast<const LensElement&>(e).lens_system())
      Fail(node.where, "light reflected back toward the eye meets the lens " + Quoted(e.name()) +
                           " again; a lens of surfaces is traced from the eye outward only: describe it as a "
                           "thin_lens, or keep it off the folded part of the path");
    if (++folded_steps_ > kMaxFoldedSteps)
      Fail(node.where, "the light reflected back and forth through " + Quoted(e.name()) + " takes more than " +
                           std::to_string(kMaxFoldedSteps) + " steps to fall below " +
                           FormatFixed(kFaintestRoute * 100, 2) +
                           " % of its strength: its mirrors lose too little light for layerlab to follow");
    if (++state.passes[&node] > kMaxPasses) {
      ++routes_cut_;
      return false;
    }
    return BrightestThrough(state.light, system_.eye.channel_wavelengths_m) >= kFaintestRoute;
  }

  // The world behind a see-through path: its light at the eye, once (it is the same in every subframe).
  void SeeThrough(const SceneNode& node, const PathState& state) {
    const bool combined = std::any_of(state.steps.begin(), state.steps.end(),
                                      [](const PathStep& s) { return s.kind == ElementKind::kCombiner; });
    if (!combined)
      Fail(node.where, "the world " + Quoted(node.element->name()) +
                           " is reached without a combiner: a display seen against the world adds its light "
                           "through a combiner's port (a half mirror or a beam splitter), not in line with the eye");
    if (subframe_ > 0) return;
    WorldView w;
    w.element = node.element->name();
    w.name = state.label;
    const auto& world = static_cast<const WorldElement&>(*node.element);
    w.luminance_cd_m2 = world.luminance();
    w.scene_file = world.scene_file();
    w.flip_x = state.flip_x, w.flip_y = state.flip_y;
    w.path = state.steps;
    for (const PathStep& s : w.path)
      if (s.power_diopters != 0 && !w.scene_file.empty())
        Fail(node.where.child("scene"), "the world " + Quoted(w.element) + " is seen through " + Quoted(s.element) +
                                            ", which has optical power: its scene would be imaged, which is not "
                                            "modelled; a uniform world (no \"scene\") is the same through it");
    // Natural light: the mean of two orthogonal linear polarizations through the path.
    const Rgb x = PathEfficiency(state.light, 0), y = PathEfficiency(state.light, std::acos(-1.0) / 2);
    for (int c = 0; c < 3; ++c) w.efficiency[c] = 0.5 * (x[c] + y[c]);
    system_.worlds.push_back(std::move(w));
  }

  // A panel stack from its front panel back to the backlight, seen by `state`'s route: its branch (the index).
  int Stack(const SceneNode& front, PathState state) {
    Branch branch;
    branch.name = state.label;
    int branch_index = static_cast<int>(system_.branches.size());
    const SceneNode* node = &front;
    std::optional<VirtualLayer> previous;
    Rgb panels_transmittance = {1, 1, 1};
    double polarization_angle = 0;
    const std::vector<LightStep> light = state.light;
    while (node->element->kind() == ElementKind::kPanel) {
      if (branch.layers.size() == kMaxStackPanels)
        Fail(node->where, "a stack of more than " + std::to_string(kMaxStackPanels) + " panels: the product of " +
                              std::to_string(kMaxStackPanels + 1) + " transmittances (" +
                              FormatFixed(std::pow(0.5, kMaxStackPanels + 1) * 1e12, 3) +
                              "e-12 of white with every "
                              "panel at the solvers' start of 0.5) leaves the light field to float rounding and, with "
                              "hundreds of panels, underflows it to zero; layerlab takes at most " +
                              std::to_string(kMaxStackPanels) + " panels per stack");
      RequireLayerRoom(*node);
      const auto& panel = static_cast<const PanelElement&>(*node->element);
      VirtualLayer layer = Float(*node, panel.spec(), state, previous ? &*previous : nullptr);
      layer.branch = branch_index;
      layer.position_in_branch = static_cast<int>(branch.layers.size());
      if (branch.layers.empty()) polarization_angle = panel.spec().polarization_angle_rad;
      for (int c = 0; c < 3; ++c) panels_transmittance[c] *= panel.spec().max_transmittance[c];
      branch.layers.push_back(static_cast<int>(system_.layers.size()));
      system_.layers.push_back(layer);
      previous = layer;

      Advance(state, layer.position_m, layer.name);
      state.previous_position = layer.position_m;
      state.previous_name = layer.name;
      state.steps.push_back({layer.name, node->element->type(), ElementKind::kPanel, "", layer.position_m, 0, false,
                             false, std::nullopt, state.transfer, nullptr, 0, std::nullopt});
      node = &Follow(*node, 0);
    }
    const auto& backlight = static_cast<const BacklightElement&>(*node->element);
    if (backlight.emission()) {  // the stack's farthest layer, at its "gap" behind the panel in front
      RequireLayerRoom(*node);
      VirtualLayer layer = Float(*node, *backlight.emission(), state, &*previous);
      layer.branch = branch_index;
      layer.position_in_branch = static_cast<int>(branch.layers.size());
      branch.layers.push_back(static_cast<int>(system_.layers.size()));
      system_.layers.push_back(layer);
    }
    branch.backlight = backlight.name();
    branch.backlight_luminance_cd_m2 = backlight.luminance();
    branch.backlight_coherence_width_m = backlight.coherence_width_m();
    branch.optics_efficiency = PathEfficiency(light, polarization_angle);
    for (int c = 0; c < 3; ++c) branch.efficiency[c] = branch.optics_efficiency[c] * panels_transmittance[c];
    system_.branches.push_back(branch);
    return branch_index;
  }

  // Each stack reached in this subframe: its branch by the route that brings the most light, its ghosts by the
  // others that bring at least kGhostFloor of that (in the order the stacks were first reached).
  void SettleStacks() {
    std::vector<const SceneNode*> fronts;
    for (const auto& [front, route] : arrivals_)
      if (std::find(fronts.begin(), fronts.end(), front) == fronts.end()) fronts.push_back(front);
    for (const SceneNode* front : fronts) {
      const double angle = static_cast<const PanelElement&>(*front->element).spec().polarization_angle_rad;
      std::vector<const PathState*> routes;
      std::vector<double> light;  // Rec.709 luminance through each route's optics
      for (const auto& [f, route] : arrivals_) {
        if (f != front) continue;
        routes.push_back(&route);
        const Rgb e = PathEfficiency(route.light, angle);
        light.push_back(kLuminanceWeights[0] * e[0] + kLuminanceWeights[1] * e[1] + kLuminanceWeights[2] * e[2]);
      }
      const size_t brightest = std::max_element(light.begin(), light.end()) - light.begin();
      for (const PathState* route : routes) folded_ = folded_ || route->reversals > 0;
      const int branch = Stack(*front, *routes[brightest]);
      for (size_t r = 0; r < routes.size(); ++r)
        if (r != brightest && light[r] > 0 && light[r] >= kGhostFloor * light[brightest])
          AddGhost(*routes[r], *routes[brightest], branch, angle);
    }
    arrivals_.clear();
  }

  // A stack seen again by `route`, another than `main`'s (its branch): the same panels, each as far beyond the
  // route's last placed element as on the main route, imaged by the route's own optics.
  void AddGhost(const PathState& route, const PathState& main, int branch_index, double polarization_angle) {
    const Branch& branch = system_.branches[branch_index];
    auto leave_out = [&](const std::string& why) {
      if (subframe_ == 0)
        system_.warnings.push_back("the ghost of " + Quoted(branch.name) + " by " + Quoted(route.label) + " " + why +
                                   ": it is left out");
    };
    if (route.placed_name != main.placed_name)  // its panels' distance from that element is the main route's
      return leave_out("reaches the stack from " + Quoted(route.placed_name) + ", not from " +
                       Quoted(main.placed_name) + " as the stack's route does, so its panels cannot be placed");
    if (ghost_layers_ + branch.layers.size() + system_.layers.size() > kMaxLayers)
      return leave_out("would take the display past " + std::to_string(kMaxLayers) + " layers with its ghosts");
    Ghost ghost;
    ghost.name = route.label;
    ghost.branch = branch_index;
    Rgb panels_transmittance = {1, 1, 1};
    for (int k : branch.layers) {
      VirtualLayer layer = system_.layers[k];
      const double beyond = layer.position_m - main.placed_at;
      const RayTransfer<double> m = route.transfer.then_gap(beyond);
      // A real image behind the eye (D < 0) is seen as a blur, as any layer beyond the accommodation range.
      if (ZeroWithinRounding(m.b, std::abs(route.transfer.b) + std::abs(beyond * route.transfer.d)))
        return leave_out("is imaged into the pupil plane, where every pixel covers the whole field");
      layer.position_m = route.placed_at + beyond;
      layer.path = route.steps;
      layer.lenslets.reset();
      SetImage(layer.panel, route, m, &layer);
      SeeThroughLenslets(*scene_.find(layer.element), route, m, &layer);
      if (!layer.panel.emitter)
        for (int c = 0; c < 3; ++c) panels_transmittance[c] *= layer.panel.max_transmittance[c];
      ghost.layers.push_back(std::move(layer));
    }
    ghost.optics_efficiency = PathEfficiency(route.light, polarization_angle);
    for (int c = 0; c < 3; ++c) ghost.efficiency[c] = ghost.optics_efficiency[c] * panels_transmittance[c];
    ghost_layers_ += ghost.layers.size();
    system_.ghosts.push_back(std::move(ghost));
  }

  void RequireLayerRoom(const SceneNode& node) const {
    if (system_.layers.size() == kMaxLayers)
      Fail(node.where, "more than " + std::to_string(kMaxLayers) +
                           " virtual layers (over every branch and "
                           "subframe); layerlab compiles displays of up to " +
                           std::to_string(kMaxLayers));
  }

  // Where the panel (or a backlight's emission) sits on its path, and the image the optics in front of it form.
  VirtualLayer Float(const SceneNode& node, const PanelSpec& spec, const PathState& state, const VirtualLayer* front) {
    VirtualLayer layer;
    layer.name = layer.element = node.element->name();
    layer.subframe = subframe_;
    layer.panel = spec;
    if (spec.virtual_depth && !state.tunable.empty())
      Fail(node.where.child("virtual_depth"),
           "\"virtual_depth\" places a panel where its image should be, but behind "
           "the tunable " +
               Quoted(state.tunable) +
               " the image moves from subframe "
               "to subframe; place " +
               Quoted(layer.name) + " by \"distance\" or \"gap\"");
    layer.path = state.steps;
    const PathStep* last_power = state.last_power ? &state.steps[*state.last_power] : nullptr;
    const double lens_at = last_power ? *last_power->position_m + last_power->axial_length_m : 0.0;
    const char* key = spec.virtual_depth ? "virtual_depth" : spec.distance_m ? "distance" : "gap";
    layer.position_m = PlaceOnPath(node, spec, state, front, layer.name, key, lens_at);
    layer.panel_distance_m = layer.position_m - lens_at;
    if (front) CheckOrder(*front, layer, node, key, state.last_power.has_value());
    if (!(layer.position_m > state.placed_at))
      Fail(node.where.child(key), "panel " + Quoted(layer.name) + " would be " + Mm(layer.position_m) +
                                      " from the pupil, not behind " + Quoted(state.placed_name) + " (" +
                                      Mm(state.placed_at) + "), which comes before it on the path");
    const RayTransfer<double> m = PanelTransfer(node, spec, state, layer, key);
    const double D = m.a / m.b;
    if (D < 0) FailBehindTheEye(node, key, state, layer, D);
    SetImage(spec, state, m, &layer);
    SeeThroughLenslets(node, state, m, &layer);
    if (spec.tilted() && subframe_ == 0)
      system_.warnings.push_back("panel " + Quoted(layer.name) +
                                 " is tilted: its layer's depth, pitch and field are the untilted panel's "
                                 "(first-order optics needs it square to the axis); the rays meet it as mounted");
    if (spec.virtual_depth == std::nullopt && D == 0)
      system_.warnings.push_back("panel \"" + layer.name +
                                 "\" sits at the focal plane: its image is at infinity (0 D)");
    return layer;
  }

  // The panel's position on its path, by its "virtual_depth", "distance" or "gap" (`key`).
  double PlaceOnPath(const SceneNode& node, const PanelSpec& spec, const PathState& state, const VirtualLayer* front,
                     const std::string& name, const char* key, double lens_at) {
    if (spec.virtual_depth) {
      const double D = spec.virtual_depth->diopters;
      bool solvable = false;
      const double t = GapForDiopters(state.transfer, D, &solvable);
      if (!solvable && !state.last_power)
        Fail(node.where.child(key), FormatFixed(D, 3) + " D puts " + Quoted(name) +
                                        " infinitely far: nothing with optical power lies between the eye and it, so "
                                        "it is seen where it is (a virtual_depth of D puts it 1/D from the eye); give "
                                        "a virtual_depth above 0 D, or a lens in front of it");
      if (!solvable)
        Fail(node.where.child(key), "no place behind " + Quoted(state.placed_name) + " images the panel at " +
                                        FormatFixed(D, 3) +
                                        " D: the optics in front of it image every plane behind "
                                        "it at " +
                                        FormatFixed(state.transfer.c / state.transfer.d, 3) + " D");
      if (!front && !(t > 0)) FailUnreachableDepth(node, state, D);
      return state.placed_at + t;
    }
    if (spec.distance_m) {
      if (!state.last_power)
        Fail(node.where.child(key),
             "\"distance\" is measured from the nearest lens or curved mirror in front of the "
             "panel, and none lies between the eye and " +
                 Quoted(name) + "; give \"gap\" (from " + Quoted(state.previous_name) +
                 ") or \"virtual_depth\" (from the eye)");
      return lens_at + *spec.distance_m;
    }
    return AfterPrevious(node, state, *node.element->gap());
  }

  // Behind a lens array: which lenslet each ray passes (systems/lenslet_map.h), the field the array spans, and
  // the span of pupil points over which each lenslet shows only its own elemental image.
  void SeeThroughLenslets(const SceneNode& node, const PathState& state, const RayTransfer<double>& m,
                          VirtualLayer* layer) {
    const PathStep* array = nullptr;
    for (const PathStep& s : state.steps) {
      if (!s.lens_array) continue;
      if (array)
        Fail(node.where, "panel " + Quoted(layer->name) + " is seen through two lens arrays, " +
                             Quoted(array->element) + " and " + Quoted(s.element) + "; layerlab models one per path");
      array = &s;
    }
    if (!array) return;
    for (const PathStep& s : state.steps)
      if (s.lens_system)
        Fail(node.where, "panel " + Quoted(layer->name) + " is seen through the lens array " + Quoted(array->element) +
                             " and the real lens " + Quoted(s.element) +
                             ", which layerlab does not trace together; describe the lens as a thin_lens");
    if (layer->panel.tilted())
      Fail(node.where.child("tilt"),
           "a tilted panel behind the lens array " + Quoted(array->element) + " is not modelled; give it no tilt");
    const LensArraySpec& a = *array->lens_array;
    const double P = array->power_diopters;
    const RayTransfer<double>& before = array->arrival;  // pupil to the array
    const RayTransfer<double> through = before.then_power(P);
    // After the array: M2 = m through^-1 (both of determinant 1).
    const double m2_a = m.a * through.d - m.b * through.c, m2_b = -m.a * through.b + m.b * through.a;
    const double half_x = 0.5 * a.cols * a.pitch_m + (a.hexagonal && a.rows > 1 ? 0.25 * a.pitch_m : 0.0);
    const double half_y =
        0.5 * a.pitch_m * (a.hexagonal ? 0.5 * std::sqrt(3.0) * (a.rows - 1) + 2 / std::sqrt(3.0) : a.rows);
    layer->fov_x_rad = std::min(layer->fov_x_rad, 2 * std::atan(half_x / std::abs(before.b)));
    layer->fov_y_rad = std::min(layer->fov_y_rad, 2 * std::atan(half_y / std::abs(before.b)));
    // A ray from pupil point p through lenslet i, at offset d from its centre, meets the array heading
    // d1 h / b1 - p / b1 (the path up to it has determinant 1) and the panel d (alpha - M2.b P) - M2.b p / b1
    // from the centre of i's elemental image, whose half width is alpha w / 2 (alpha = M2.a + M2.b d1 / b1):
    // pupil points within +-E/2 see i's own, E = w (|alpha| - fill |alpha - M2.b P|) |b1 / M2.b|.
    const double alpha = m2_a + m2_b * before.d / before.b;
    // On a hexagonal lattice in every direction: each elemental image's inscribed circle (radius alpha w / 2)
    // against the lenslets' circumscribed one (fill w / sqrt 3).
    const double reach = a.fill * (a.hexagonal ? 2 / std::sqrt(3.0) : 1.0);
    const double span = a.pitch_m * (std::abs(alpha) - reach * std::abs(alpha - m2_b * P)) * std::abs(before.b / m2_b);
    layer->lenslets =
        std::make_shared<const LensletMap>(a, before.a, before.b, layer->diopters, m2_b * P / m.b, std::max(0.0, span));
  }

  // The transfer from the panel to the pupil; refused when it images the panel into the pupil plane.
  RayTransfer<double> PanelTransfer(const SceneNode& node, const PanelSpec& spec, const PathState& state,
                                    const VirtualLayer& layer, const char* key) {
    RayTransfer<double> m = state.transfer.then_gap(layer.position_m - state.placed_at);
    if (spec.virtual_depth)
      m.a = spec.virtual_depth->diopters * m.b;
    else if (ZeroWithinRounding(
                 m.a, std::abs(state.transfer.a) + std::abs((layer.position_m - state.placed_at) * state.transfer.c)))
      m.a = 0;  // a + t c at the focal plane: the image is at infinity
    if (ZeroWithinRounding(
            m.b, std::abs(state.transfer.b) + std::abs((layer.position_m - state.placed_at) * state.transfer.d)))
      Fail(node.where.child(key), "panel " + Quoted(layer.name) +
                                      " is imaged into the pupil plane, where no eye "
                                      "can focus; move it or the optics in front of it");
    return m;
  }

  // The panel's image through transfer m: its depth, magnification, pitch, offset, flips and field.
  static void SetImage(const PanelSpec& spec, const PathState& state, const RayTransfer<double>& m,
                       VirtualLayer* layer) {
    const double D = m.a / m.b;
    layer->transfer = m;
    layer->diopters = D;
    layer->depth_m = D == 0 ? std::numeric_limits<double>::infinity() : 1.0 / D;
    layer->inverted = m.b < 0;
    const double inf = std::numeric_limits<double>::infinity();
    layer->magnification = m.a == 0 ? (layer->inverted ? -inf : inf) : 1.0 / m.a;
    const double tan_per_meter = 1.0 / std::abs(m.b);
    layer->pitch_x_m = std::abs(layer->magnification) * spec.pitch_x_m;
    layer->pitch_y_m = std::abs(layer->magnification) * spec.pitch_y_m;
    layer->tan_pitch_x = tan_per_meter * spec.pitch_x_m;
    layer->tan_pitch_y = tan_per_meter * spec.pitch_y_m;
    layer->cols = static_cast<int>(spec.active_cols);
    layer->rows = static_cast<int>(spec.active_rows);
    layer->eye_from_layer_tan_x = tan_per_meter * spec.eye_from_panel_m[0];
    layer->eye_from_layer_tan_y = tan_per_meter * spec.eye_from_panel_m[1];
    layer->rotation_rad = spec.rotation_rad;
    layer->flip_x = (state.flip_x != layer->inverted) != spec.reversed;
    layer->flip_y = state.flip_y != layer->inverted;
    layer->fov_x_rad = FieldOfView(layer->tan_pitch_x, layer->cols);
    layer->fov_y_rad = FieldOfView(layer->tan_pitch_y, layer->rows);
    layer->max_cpd = std::max(NyquistCyclesPerDegree(layer->tan_pitch_x), NyquistCyclesPerDegree(layer->tan_pitch_y));
  }

  // A layer the eye cannot focus on is only ever seen blurred.
  void WarnOutsideAccommodation() {
    const EyeModel& eye = system_.eye;
    for (const VirtualLayer& l : system_.layers)
      if (l.diopters < eye.accommodation_min_diopters - 1e-9 || l.diopters > eye.accommodation_max_diopters + 1e-9)
        system_.warnings.push_back("layer \"" + l.name + "\" at " + FormatFixed(l.diopters, 2) +
                                   " D lies outside the eye's accommodation range (" +
                                   FormatFixed(eye.accommodation_min_diopters, 2) + " to " +
                                   FormatFixed(eye.accommodation_max_diopters, 2) +
                                   " D, the eye's accommodation_range): the eye cannot focus on it");
  }

  // A virtual_depth that no place behind the last placed element reaches.
  [[noreturn]] void FailUnreachableDepth(const SceneNode& node, const PathState& state, double D) const {
    const Location at = node.where.child("virtual_depth");
    const std::string wanted = "a virtual image at " + FormatFixed(D, 3) + " D (" + Mm(1.0 / D) + " from the eye)";
    // One lens and free space before it: panels behind it are imaged nearer than the lens itself.
    const bool magnifier_only = state.powered == 1 && state.steps[*state.last_power].kind == ElementKind::kLens &&
                                state.placed_name == state.steps[*state.last_power].element;
    if (magnifier_only) {
      const double f = 1.0 / state.steps[*state.last_power].power_diopters;
      Fail(at, wanted + " cannot be formed behind the lens: it is " + Mm(state.placed_at) +
                   " from the eye, and a panel behind it is imaged between 0 D (at its focal plane, " + Mm(f) +
                   " behind it) and " + FormatFixed(1.0 / state.placed_at, 1) + " D (against it)");
    }
    const double nearest = state.transfer.a / state.transfer.b, farthest = state.transfer.c / state.transfer.d;
    Fail(at, wanted + " cannot be formed behind " + Quoted(state.placed_name) + " (" + Mm(state.placed_at) +
                 " from the pupil): panels behind it are imaged between " +
                 FormatFixed(std::min(nearest, farthest), 3) + " and " + FormatFixed(std::max(nearest, farthest), 3) +
                 " D");
  }

  [[noreturn]] void FailBehindTheEye(const SceneNode& node, const char* key, const PathState& state,
                                     const VirtualLayer& layer, double D) const {
    const Location at = node.where.child(key);
    std::string why;
    if (state.powered == 1 && state.steps[*state.last_power].kind == ElementKind::kLens) {
      const double f = 1.0 / state.steps[*state.last_power].power_diopters;
      if (layer.panel_distance_m > f)
        why = " (it is " + Mm(layer.panel_distance_m) + " from the lens, beyond the focal length " + Mm(f) + ")";
    }
    Fail(at, "panel " + Quoted(layer.name) + " would be imaged " + Mm(-1.0 / D) + " behind the eye (" +
                 FormatFixed(D, 3) + " D)" + why +
                 ": the optics in front of it form a real image beyond the pupil, whose light converges into the "
                 "eye, which no eye can focus; a real image in front of the eye is accepted");
  }

  void CheckOrder(const VirtualLayer& front, const VirtualLayer& back, const SceneNode& node, const char* key,
                  bool has_lens) const {
    if (back.position_m == front.position_m)
      Fail(node.where.child(key), "panels \"" + front.name + "\" and \"" + back.name +
                                      "\" of one stack are at the same depth (" + FormatFixed(front.diopters, 4) +
                                      " D); a stack needs distinct planes");
    if (back.position_m < front.position_m)
      Fail(node.where.child(key), "panel \"" + back.name + "\" is behind \"" + front.name +
                                      "\" in the stack but nearer the " + (has_lens ? "lens (" : "eye (") +
                                      Mm(back.panel_distance_m) + " < " + Mm(front.panel_distance_m) +
                                      "); list each stack from the eye outward");
  }

  Rgb PathEfficiency(const std::vector<LightStep>& path, double polarization_angle) {
    bool polarized = std::any_of(path.begin(), path.end(), [](const LightStep& s) { return s.element->polarizing(); });
    system_.polarization_tracked = system_.polarization_tracked || polarized;
    Light light;
    for (ChannelLight& channel : light) {
      channel.polarized = polarized;
      if (polarized) channel.field = LinearPolarization(polarization_angle);
    }
    for (auto step = path.rbegin(); step != path.rend(); ++step)  // from the panel toward the eye
      ApplyLightStep(*step, system_.eye.channel_wavelengths_m, light);
    return {light[0].power(), light[1].power(), light[2].power()};
  }

  void FindMagnifier();
  void CheckApertures();
  void CheckLensletCrosstalk();
  void CheckFirstOrderValidity();
  void CheckEyePose();
  void MapRealLenses();
  void Finish();
  void SortFarthestFirst();
  void AddUpLight();
  void DescribeComponents();

  const Scene& scene_;
  DisplaySystem system_;
  std::set<const SceneNode*> visited_;
  struct Predecessor {
    const SceneNode* node;
    size_t port;
  };
  std::map<const SceneNode*, Predecessor> predecessor_;           // who leads to each element, and by which port
  std::vector<std::pair<const SceneNode*, PathState>> arrivals_;  // stacks reached (their front panel) and how
  size_t folded_steps_ = 0;
  int routes_cut_ = 0;   // routes ended at kMaxPasses
  bool folded_ = false;  // a stack is reached by a route that turned
  size_t ghost_layers_ = 0;
  int combiners_ = 0;
  int subframe_ = 0;
};

// The paper's layout: one lens, the first element with power on every path.
void Walker::FindMagnifier() {
  std::optional<std::string> lens;
  for (const VirtualLayer& l : system_.layers) {
    std::vector<const PathStep*> powered;
    for (const PathStep& s : l.path)
      if (s.power_diopters != 0) powered.push_back(&s);
    if (powered.size() != 1 || powered[0]->kind != ElementKind::kLens || (lens && *lens != powered[0]->element)) return;
    lens = powered[0]->element;
  }
  if (!lens) return;
  const auto& element = static_cast<const LensElement&>(*scene_.find(*lens)->element);
  if (element.tunable() || element.lens_array()) return;
  system_.lens = *lens;
  system_.focal_length_m = element.focal_length();
  system_.clear_aperture_m = element.clear_aperture();
  for (const PathStep& s : system_.layers.front().path)
    if (s.element == *lens) system_.eye.eye_relief_m = *s.position_m;  // pupil to magnifier, however it was placed
}

// Warns of every lens whose clear aperture cuts rays from the eyebox to a layer's field.
void Walker::CheckApertures() {
  const EyeModel& eye = system_.eye;
  std::vector<std::pair<std::string, std::vector<std::string>>> cut;  // lens -> layers
  for (const VirtualLayer& l : system_.layers) {
    for (const PathStep& s : l.path) {
      if (s.clear_aperture_m) {
        const RayTransfer<double>& m = s.arrival;
        // The ray from pupil point x toward tan-angle t of the layer has slope t - x D;
        // its height here is a x + b (t - x D). The largest over the eyebox and field corners:
        const double tx = 0.5 * l.cols * l.tan_pitch_x + std::abs(l.eye_from_layer_tan_x);
        const double ty = 0.5 * l.rows * l.tan_pitch_y + std::abs(l.eye_from_layer_tan_y);
        double largest = 0;
        for (double x : {-0.5 * eye.eyebox_width_m, 0.5 * eye.eyebox_width_m})
          for (double y : {-0.5 * eye.eyebox_height_m, 0.5 * eye.eyebox_height_m})
            for (double u : {-tx, tx})
              for (double v : {-ty, ty}) {
                const double hx = m.a * x + m.b * (u - x * l.diopters), hy = m.a * y + m.b * (v - y * l.diopters);
                largest = std::max(largest, std::hypot(hx, hy));
              }
        if (largest > 0.5 * *s.clear_aperture_m) {
          auto it = std::find_if(cut.begin(), cut.end(), [&](const auto& c) { return c.first == s.element; });
          if (it == cut.end()) cut.push_back({s.element, {}}), it = cut.end() - 1;
          it->second.push_back(Quoted(l.name) + " (rays up to " + Mm(largest) + " from its axis)");
        }
      }
    }
  }
  for (const auto& [lens, layers] : cut)
    system_.warnings.push_back("the clear aperture of " + Quoted(lens) + " vignettes " + JoinWords(layers, ", ") +
                               " seen from the edges of the eyebox");
}

// Warns of every first-order lens (a thin lens, a tunable lens) modelled beyond where first-order optics
// holds: a layer seen through it over a field wider than kFirstOrderFieldDeg, or a lens faster than
// f/kFirstOrderFNumber at its strongest power on the paths. A thin lens's remedy is the real-lens model,
// traced exactly (docs/optics.md, "Real lenses"); a tunable lens has none yet.
void Walker::CheckFirstOrderValidity() {
  struct Worst {
    std::string element;
    const VirtualLayer* widest = nullptr;  // the layer seen through it over the widest field
    const PathStep* strongest = nullptr;   // its step of the strongest power
  };
  std::vector<Worst> lenses;  // in the order first met
  for (const VirtualLayer& l : system_.layers)
    for (const PathStep& s : l.path) {
      const bool curved_mirror = s.type == "mirror" || s.type == "half_mirror";
      if ((s.type != "thin_lens" && s.type != "tunable_lens" && !curved_mirror) || s.power_diopters == 0)
        continue;  // a mirror with power is a curved one
      auto it = std::find_if(lenses.begin(), lenses.end(), [&](const Worst& w) { return w.element == s.element; });
      if (it == lenses.end()) it = lenses.insert(lenses.end(), Worst{s.element, &l, &s});
      if (std::max(l.fov_x_rad, l.fov_y_rad) > std::max(it->widest->fov_x_rad, it->widest->fov_y_rad)) it->widest = &l;
      if (std::abs(s.power_diopters) > std::abs(it->strongest->power_diopters)) it->strongest = &s;
    }
  for (const Worst& w : lenses) {
    const VirtualLayer& l = *w.widest;
    const PathStep& s = *w.strongest;
    const double fx = l.fov_x_rad / kRadiansPerDegree, fy = l.fov_y_rad / kRadiansPerDegree;
    const double f = std::abs(1.0 / s.power_diopters);
    std::string why;
    if (std::max(fx, fy) > kFirstOrderFieldDeg)
      why = Quoted(l.name) + " is seen through it over " + FormatFixed(fx, 0) + " x " + FormatFixed(fy, 0) +
            " deg, beyond the " + FormatFixed(kFirstOrderFieldDeg, 0) +
            " deg within which its distortion and field "
            "curvature stay small";
    else if (s.clear_aperture_m && f / *s.clear_aperture_m < kFirstOrderFNumber)
      why = "it is f/" + FormatFixed(f / *s.clear_aperture_m, 2) + " (" + Mm(f) + " over a " + Mm(*s.clear_aperture_m) +
            " clear aperture), faster than f/" + FormatFixed(kFirstOrderFNumber, 0) +
            ", where its spherical aberration is no longer small";
    if (why.empty()) continue;
    const std::string kind = s.type == "thin_lens"      ? "thin lens"
                             : s.type == "tunable_lens" ? "tunable lens"
                                                        : "curved mirror";
    system_.warnings.push_back(
        "the " + kind + " " + Quoted(w.element) + " is modelled to first order outside where that holds: " + why +
        (s.type == "thin_lens"
             ? "; describe it as a \"lens\" of surfaces and glass for the exact trace (docs/optics.md, "
               "\"Real lenses\")"
             : "; layerlab has no exact model of a " + kind +
                   ", so its images there leave out those aberrations (docs/optics.md, \"Real "
                   "lenses\")"));
  }
}

// Rays from pupil points beyond a lens array's crosstalk-free span read neighbouring elemental images: modelled,
// and said, with the limit.
void Walker::CheckLensletCrosstalk() {
  const EyeModel& eye = system_.eye;
  const double reach = std::max(eye.eyebox_width_m, eye.eyebox_height_m) + eye.pupil_diameter_m;  // along an axis
  for (const VirtualLayer& l : system_.layers)
    if (l.lenslets && reach > l.lenslets->crosstalk_free_m() * (1 + 1e-9) && l.subframe == 0)
      system_.warnings.push_back(
          "through the lens array, pupil points reach " + Mm(reach) +
          " across (the eyebox and the pupil), beyond the " + Mm(l.lenslets->crosstalk_free_m()) +
          " within which each lenslet shows " + Quoted(l.name) +
          "'s own elemental image behind it: rays from beyond read the neighbouring elemental images (crosstalk, "
          "modelled in the solve and the retinal images)");
}

void Walker::Finish() {
  if (system_.layers.empty())
    Fail({scene_.file, "/elements"}, "no panel lies on any path from the eye: a display needs at least one");
  SortFarthestFirst();
  system_.fov_x_rad = system_.fov_y_rad = INFINITY;
  for (const VirtualLayer& l : system_.layers) {
    system_.fov_x_rad = std::min(system_.fov_x_rad, l.fov_x_rad);
    system_.fov_y_rad = std::min(system_.fov_y_rad, l.fov_y_rad);
    if (!l.panel.emitter) system_.max_cpd = std::max(system_.max_cpd, l.max_cpd);  // a backlight's grid is no image's
  }
  WarnOutsideAccommodation();
  AddUpLight();
  ResolvePupil();
  FindMagnifier();
  const EyeModel& eye = system_.eye;
  if (!system_.lens.empty() && system_.clear_aperture_m) {
    double radius = *system_.clear_aperture_m / 2;
    auto field = [&](double eyebox) { return 2 * std::atan(std::max(0.0, radius - eyebox / 2) / eye.eye_relief_m); };
    system_.vignetting_free_fov_x_rad = field(eye.eyebox_width_m);
    system_.vignetting_free_fov_y_rad = field(eye.eyebox_height_m);
  }
  if (routes_cut_ > 0)
    system_.warnings.push_back(std::to_string(routes_cut_) +
                               " routes of light reflected back and forth were cut "
                               "after meeting one element " +
                               std::to_string(kMaxPasses) + " times; what they would show is left out");
  CheckApertures();
  CheckLensletCrosstalk();
  CheckFirstOrderValidity();
  CheckEyePose();
  MapRealLenses();
  DescribeComponents();
}

// The scene's pose: a gaze outside the display's field is refused, a pupil
// beyond the eyebox warned of (natural viewing reads the edge views there).
void Walker::CheckEyePose() {
  const EyeModel& eye = system_.eye;
  if (const std::string beyond = GazeBeyondField(system_, eye.pose); !beyond.empty())
    throw Error(FindEye().where.child("gaze"), beyond);
  if (const std::string warning = PupilBeyondEyeboxWarning(eye); !warning.empty()) system_.warnings.push_back(warning);
}

// The exact ray map of every layer behind a real lens or on a tilted panel,
// sampled over the pupils of the eyebox and the directions that reach any layer's field, a
// quarter wider (a light field is normally the display's own field).
void Walker::MapRealLenses() {
  const EyeModel& eye = system_.eye;
  const double pupil_reach = PupilReach(eye);
  std::array<double, 2> field_min{INFINITY, INFINITY}, field_max{-INFINITY, -INFINITY};  // U over every layer
  for (const VirtualLayer& l : system_.layers) {
    const double half = 1.25 * 0.5 * std::hypot(l.cols * l.tan_pitch_x, l.rows * l.tan_pitch_y);
    const std::array<double, 2> centre{l.eye_from_layer_tan_x, l.eye_from_layer_tan_y};
    for (int a = 0; a < 2; ++a)
      field_min[a] = std::min(field_min[a], centre[a] - half), field_max[a] = std::max(field_max[a], centre[a] + half);
  }
  for (VirtualLayer& l : system_.layers) {
    if (!l.panel.tilted() &&
        std::none_of(l.path.begin(), l.path.end(), [](const PathStep& s) { return s.lens_system != nullptr; }))
      continue;
    RayMapDomain domain;
    domain.pupil_max_m = {0.5 * eye.eyebox_width_m + pupil_reach, 0.5 * eye.eyebox_height_m + pupil_reach};
    domain.pupil_min_m = {-domain.pupil_max_m[0], -domain.pupil_max_m[1]};
    for (int a = 0; a < 2; ++a) {  // u = U - D p over the field and the pupils
      const double sweep = std::abs(l.diopters) * domain.pupil_max_m[a];
      domain.tan_min[a] = field_min[a] - sweep;
      domain.tan_max[a] = field_max[a] + sweep;
    }
    auto exact = std::make_shared<const LayerRayMap>(l, eye.channel_wavelengths_m);
    l.ray_map = std::make_shared<const SampledRayMap>(exact, domain, l.tan_pitch_x, l.tan_pitch_y);
    if (l.ray_map->bound_pixels() > kMapTolerancePixels)
      system_.warnings.push_back("the ray map of layer " + Quoted(l.name) + " reaches only " +
                                 FormatFixed(l.ray_map->bound_pixels(), 4) + " px against the exact trace (" +
                                 FormatFixed(kMapTolerancePixels, 4) + " px wanted) at its largest grid");
  }
}

// Farthest first, as the paper numbers its panels.
void Walker::SortFarthestFirst() { SortLayersFarthestFirst(&system_); }

// The display's peak luminance and its efficiencies, each backlight counted once.
void Walker::AddUpLight() {
  double emitted = 0;
  std::set<std::string> backlights;  // each once, whatever the subframes
  for (const Branch& b : system_.branches) {
    if (backlights.insert(b.backlight).second) emitted += b.backlight_luminance_cd_m2;
    for (int c = 0; c < 3; ++c) system_.peak_luminance_cd_m2[c] += b.backlight_luminance_cd_m2 * b.efficiency[c];
  }
  for (int c = 0; c < 3; ++c) {
    system_.brightness_efficiency[c] = system_.peak_luminance_cd_m2[c] / emitted;
    system_.luminance_efficiency += kLuminanceWeights[c] * system_.brightness_efficiency[c];
  }
}

// What the display is made of, in words (`info` and the report).
void Walker::DescribeComponents() {
  const auto& layers = system_.layers;
  auto& parts = system_.components;
  std::set<std::string> real;
  for (const VirtualLayer& l : layers)
    for (const PathStep& s : l.path)
      if (s.lens_system) real.insert(Quoted(s.element) + " (" + std::to_string(s.lens_system->size()) + " surfaces)");
  if (!system_.lens.empty() && real.empty()) {
    parts.push_back("thin-lens floating (" + std::to_string(layers.size()) + " virtual layers)");
  } else if (!system_.lens.empty()) {
    parts.push_back("real-lens floating (" + std::to_string(layers.size()) + " virtual layers)");
  } else {
    std::set<std::string> lenses, mirrors;
    for (const VirtualLayer& l : layers)
      for (const PathStep& s : l.path) {
        if (s.kind == ElementKind::kLens) lenses.insert(s.element);
        if (s.kind == ElementKind::kMirror || (s.kind == ElementKind::kCombiner && s.power_diopters != 0))
          mirrors.insert(s.element);  // fold mirrors and curved half mirrors
      }
    if (lenses.empty() && mirrors.empty())
      parts.push_back("direct view, no optics with power (" + std::to_string(layers.size()) + " layers)");
    else
      parts.push_back("first-order optics: " + std::to_string(lenses.size()) + " lens" +
                      (lenses.size() == 1 ? "" : "es") + ", " + std::to_string(mirrors.size()) + " mirror" +
                      (mirrors.size() == 1 ? "" : "s") + " (" + std::to_string(layers.size()) + " virtual layers)");
  }
  if (!real.empty())
    parts.push_back("real lenses traced exactly per channel: " + JoinWords({real.begin(), real.end()}, ", ") +
                    " (general projection path)");
  const int K = system_.subframes;
  if (K > 1)
    parts.push_back("time multiplexing: " + std::to_string(K) + " subframes per frame at " +
                    FormatFixed(system_.frame_rate_hz, 0) + " Hz (panels refresh at " +
                    FormatFixed(K * system_.frame_rate_hz, 0) + " Hz), seen as their mean");
  const size_t branches = system_.branches.size() / K;
  const int combiners = combiners_ / K;
  if (branches > 1)
    parts.push_back("additive combination of " + std::to_string(branches) + " branches (" + std::to_string(combiners) +
                    " combiner" + (combiners > 1 ? "s" : "") + ")");
  int products = 0;
  for (const Branch& b : system_.branches) products += b.subframe == 0 && b.layers.size() > 1;
  if (products)
    parts.push_back("multiplicative stacks in " + std::to_string(products) + " branch" + (products > 1 ? "es" : ""));
  parts.push_back(system_.polarization_tracked ? "polarization (Jones vectors per channel)"
                                               : "no polarization model (no polarizing element)");
  for (const VirtualLayer& l : layers)
    if (l.lenslets && l.subframe == 0) {
      const LensArraySpec& a = l.lenslets->array();
      parts.push_back("lens array: " + std::to_string(a.cols) + " x " + std::to_string(a.rows) +
                      (a.hexagonal ? " hexagonal" : " square") + " lenslets " + Mm(a.pitch_m) + " apart before " +
                      Quoted(l.name) + ", each its elemental image's own to pupil points within " +
                      Mm(l.lenslets->crosstalk_free_m()));
    }
  if (folded_)
    parts.push_back("folded paths: each stack placed and solved by its brightest route; " +
                    std::to_string(system_.ghosts.size() / K) + " ghost" + (system_.ghosts.size() / K == 1 ? "" : "s") +
                    " by other routes, added in the retinal images");
  if (std::any_of(layers.begin(), layers.end(), [](const VirtualLayer& l) { return l.inverted; }))
    parts.push_back("inverted layers (real intermediate images)");
  if (std::any_of(layers.begin(), layers.end(), [](const VirtualLayer& l) { return l.flip_x || l.flip_y; }))
    parts.push_back("mirrored layers (reversed panels or reflected branches)");
  if (std::any_of(layers.begin(), layers.end(), [](const VirtualLayer& l) { return l.rotation_rad != 0; }))
    parts.push_back("rotated layers (general projection path)");
}

}  // namespace

DisplaySystem Compile(const Scene& scene) { return Walker(scene).Run(); }

}  // namespace layerlab
