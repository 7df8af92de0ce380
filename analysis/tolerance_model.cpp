#include "layerlab/analysis/tolerance_model.h"

#include <algorithm>
#include <array>

#include "layerlab/framework/random.h"
#include "layerlab/framework/units.h"
#include "layerlab/systems/compile.h"

namespace layerlab {
namespace {

size_t ElementIndex(const nlohmann::json& document, const std::string& name) {
  const nlohmann::json& elements = document.at("elements");
  for (size_t i = 0; i < elements.size(); ++i)
    if (elements[i].value("name", "") == name) return i;
  throw Error("no element named \"" + name + "\" in the scene document");
}

// A value the element's reader accepted: a bare number is SI, a string has its unit.
double Si(const nlohmann::json& value, Dimension d) {
  return value.is_number() ? value.get<double>() : ParseQuantity(value.get<std::string>(), d);
}

void AddToPair(nlohmann::json& element, const char* key, int axis, double value, Dimension d) {
  std::array<double, 2> pair{0, 0};
  if (element.contains(key)) {
    const nlohmann::json& v = element[key];
    pair = v.is_array() ? std::array<double, 2>{Si(v[0], d), Si(v[1], d)} : std::array<double, 2>{Si(v, d), Si(v, d)};
  }
  pair[axis] += value;
  element[key] = {pair[0], pair[1]};
}

void ScaleFocalLength(nlohmann::json& element, double e) {
  if (element.value("type", "") == "thin_lens") {
    element["focal_length"] = Si(element["focal_length"], Dimension::kLength) * (1 + e);
    return;
  }
  for (nlohmann::json& surface : element["surfaces"])
    if (surface.contains("radius")) surface["radius"] = Si(surface["radius"], Dimension::kLength) * (1 + e);
}

bool Powered(const VirtualLayer& layer) {
  return std::any_of(layer.path.begin(), layer.path.end(),
                     [](const PathStep& s) { return s.power_diopters != 0 || s.lens_system; });
}

std::vector<const VirtualLayer*> PanelsInStackOrder(const DisplaySystem& nominal) {
  std::vector<const VirtualLayer*> panels;
  for (const VirtualLayer& l : nominal.layers)
    if (l.subframe == 0) panels.push_back(&l);
  std::sort(panels.begin(), panels.end(), [](const VirtualLayer* a, const VirtualLayer* b) {
    return std::make_pair(a->branch, a->position_in_branch) < std::make_pair(b->branch, b->position_in_branch);
  });
  return panels;
}

std::optional<double> LimitOf(const ToleranceSpec& spec, ToleranceKind kind) {
  for (const Tolerance& t : spec.tolerances)
    if (t.kind == kind) return t.limit;
  return std::nullopt;
}

}  // namespace

std::string ToleranceDof::Name() const {
  const bool paired = kind != ToleranceKind::kGap && kind != ToleranceKind::kFocalLength;
  return ToleranceKey(kind) + " " + element + (paired ? (axis == 0 ? " x" : " y") : "");
}

ToleranceModel::ToleranceModel(const Scene& scene, const DisplaySystem& nominal, const ToleranceSpec& spec)
    : spec_(spec), file_(scene.file), physical_(scene.document) {
  for (const VirtualLayer* l : PanelsInStackOrder(nominal)) {
    const size_t index = ElementIndex(physical_, l->element);
    nlohmann::json& e = physical_["elements"][index];
    if (!e.contains("virtual_depth")) continue;
    if (!Powered(*l))
      throw Error(Location{file_, "/elements/" + std::to_string(index) + "/virtual_depth"},
                  "the tolerance analysis moves panels, not their images, and no lens or curved mirror in front of "
                  "\"" +
                      l->element + "\" gives it a physical \"distance\"; place it by \"gap\"");
    e.erase("virtual_depth");
    e["distance"] = l->panel_distance_m;
  }
  AddPanelDofs(nominal);
  AddOpticDofs(scene);
  for (const Tolerance& t : spec_.tolerances)
    if (std::none_of(dofs_.begin(), dofs_.end(), [&](const ToleranceDof& d) { return d.kind == t.kind; }))
      notes_.push_back(ToleranceKey(t.kind) + ": nothing in the scene it applies to" +
                       (t.kind == ToleranceKind::kLensDecentre || t.kind == ToleranceKind::kLensTilt
                            ? " (no lens of real surfaces; an ideal thin_lens is centred by definition)"
                            : ""));
}

void ToleranceModel::AddPanelDofs(const DisplaySystem& nominal) {
  const std::vector<const VirtualLayer*> panels = PanelsInStackOrder(nominal);
  for (ToleranceKind kind : {ToleranceKind::kPanelDecentre, ToleranceKind::kPanelTilt, ToleranceKind::kGap}) {
    const std::optional<double> limit = LimitOf(spec_, kind);
    if (!limit) continue;
    std::vector<size_t> stack;  // the gap dofs of the current stack so far
    for (size_t k = 0; k < panels.size(); ++k) {
      const VirtualLayer& l = *panels[k];
      const size_t index = ElementIndex(physical_, l.element);
      if (kind != ToleranceKind::kGap) {
        for (int axis = 0; axis < 2; ++axis) dofs_.push_back({kind, *limit, l.element, index, axis, {}});
        continue;
      }
      if (l.position_in_branch == 0) stack.clear();
      stack.push_back(dofs_.size());
      const bool by_distance = physical_["elements"][index].contains("distance");
      dofs_.push_back({kind, *limit, l.element, index, 0, by_distance ? stack : std::vector<size_t>{}});
    }
  }
}

void ToleranceModel::AddOpticDofs(const Scene& scene) {
  for (const SceneNode& node : scene.nodes) {
    const Element& e = *node.element;
    if (e.kind() != ElementKind::kLens && e.kind() != ElementKind::kMirror) continue;
    const size_t index = ElementIndex(physical_, e.name());
    const nlohmann::json& doc = physical_["elements"][index];
    for (const Tolerance& t : spec_.tolerances) {
      const bool real = e.type() == "lens";
      switch (t.kind) {
        case ToleranceKind::kLensDecentre:
        case ToleranceKind::kLensTilt:
          if (real)
            for (int axis = 0; axis < 2; ++axis) dofs_.push_back({t.kind, t.limit, e.name(), index, axis, {}});
          break;
        case ToleranceKind::kGap:
          if (doc.contains("gap")) dofs_.push_back({t.kind, t.limit, e.name(), index, 0, {}});
          break;
        case ToleranceKind::kFocalLength:
          if (e.type() == "thin_lens" || (real && doc.contains("surfaces")))
            dofs_.push_back({t.kind, t.limit, e.name(), index, 0, {}});
          else if (real || e.kind() == ElementKind::kLens)
            notes_.push_back("focal_length: \"" + e.name() + "\" (" + e.type() +
                             ") is not perturbed (a .zmx prescription or a tunable lens)");
          break;
        default:
          break;
      }
    }
  }
}

ToleranceDraw ToleranceModel::Draw(uint64_t seed, uint64_t sample) const {
  Gaussian random(MixSeed(seed, sample));
  ToleranceDraw draw(dofs_.size());
  for (size_t i = 0; i < dofs_.size(); ++i) draw[i] = DrawTruncatedNormal(random, dofs_[i].limit);
  return draw;
}

ToleranceDraw ToleranceModel::AtLimit(ToleranceKind kind, double sign) const {
  ToleranceDraw draw = Zero();
  for (size_t i = 0; i < dofs_.size(); ++i)
    if (dofs_[i].kind == kind) draw[i] = sign * dofs_[i].limit;
  return draw;
}

nlohmann::json ToleranceModel::Perturbed(const ToleranceDraw& draw) const {
  if (draw.size() != dofs_.size()) throw Error("a tolerance draw of the wrong size");
  nlohmann::json document = physical_;
  for (size_t i = 0; i < dofs_.size(); ++i) {
    const ToleranceDof& d = dofs_[i];
    double value = draw[i];
    if (d.kind == ToleranceKind::kGap && !d.moved_by.empty()) {
      value = 0;
      for (size_t j : d.moved_by) value += draw[j];
    }
    if (value == 0) continue;
    nlohmann::json& e = document["elements"][d.index];
    switch (d.kind) {
      case ToleranceKind::kPanelDecentre:
        AddToPair(e, "offset", d.axis, value, Dimension::kLength);
        break;
      case ToleranceKind::kLensDecentre:
        AddToPair(e, "decentre", d.axis, value, Dimension::kLength);
        break;
      case ToleranceKind::kPanelTilt:
      case ToleranceKind::kLensTilt:
        AddToPair(e, "tilt", d.axis, value, Dimension::kAngle);
        break;
      case ToleranceKind::kGap: {
        const char* key = d.moved_by.empty() ? "gap" : "distance";
        e[key] = Si(e[key], Dimension::kLength) + value;
        break;
      }
      case ToleranceKind::kFocalLength:
        ScaleFocalLength(e, value);
        break;
    }
  }
  return document;
}

DisplaySystem ToleranceModel::Compile(const ToleranceDraw& draw) const {
  static const ElementRegistry registry = ElementRegistry::WithBuiltins();
  return layerlab::Compile(ParseScene(Perturbed(draw), file_ + " (perturbed)", registry));
}

}  // namespace layerlab
