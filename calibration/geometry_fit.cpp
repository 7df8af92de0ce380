#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include <ceres/ceres.h>

#include "layerlab/calibration/fit_steps.h"
#include "layerlab/calibration/marker_model.h"
#include "layerlab/calibration/scalar_fit.h"
#include "layerlab/calibration/similarity_fit.h"
#include "layerlab/calibration/traced_marker_model.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

struct MarkerDatum {
  int layer = 0;
  size_t capture = 0;
  MarkerPlacement placement;
  Point2 pixel;  // (col, row)
  double angle_x = 0, angle_y = 0;
  Location where;
  int block = 0;  // the photograph (capture and panel) it was found in
};

// A lens or curved mirror on the path of some panel with markers.
struct Optic {
  std::string name;
  double focal_length = 0;    // as designed, m
  double position = 0;        // m of path length from the pupil
  double gap = 0;             // from the element before it (the pupil), m
  std::string before;         // that element's name; "" for the pupil
  bool placed_before = true;  // whether that element has a place of its own, so that "gap" can be written
  std::vector<int> layers;    // whose path holds it
  bool surfaces = false;      // a real lens: its power and distortion are its surfaces', traced
  int focal = -1, gap_index = -1, distortion = -1;  // into the ScalarFit
};

// A marker's parameter blocks: distance, eye_from_panel_x_m, eye_from_panel_y_m, rotation, pan, tilt,
// roll, then a gap, a focal length and a distortion per element with power on its path (`optics` of them).
template <typename T>
MarkerParameters<T> ParametersOfBlocks(T const* const* p, size_t optics) {
  MarkerParameters<T> q{p[0][0], p[1][0], p[2][0], p[3][0], p[4][0], p[5][0], p[6][0], {}, {}, {}};
  for (size_t i = 0; i < optics; ++i) {
    q.gaps.push_back(p[7 + 3 * i][0]);
    q.focal_lengths.push_back(p[8 + 3 * i][0]);
    q.distortions.push_back(p[9 + 3 * i][0]);
  }
  return q;
}

// The residual of one marker, over the blocks of ParametersOfBlocks.
struct MarkerCost {
  MarkerPlacement placement;
  LayerOptics optics;
  double angle_x, angle_y;
  double weight;  // 1 / the detection noise (rad) when measured, else 1

  template <typename T>
  bool operator()(T const* const* p, T* residual) const {
    T angle[2];
    PredictVisualAngle(ParametersOfBlocks(p, optics.element.size()), optics, placement, angle);
    residual[0] = (angle[0] - angle_x) * weight;
    residual[1] = (angle[1] - angle_y) * weight;
    return true;
  }
};

using MarkerCostFunction = ceres::DynamicAutoDiffCostFunction<MarkerCost, 4>;

// The same parameter blocks for a marker seen through real lenses
// (traced_marker_model.h), its derivatives by central differences.
struct TracedMarkerCost {
  const TracedLayerModel* model;
  TracedMarker marker;
  size_t optics;
  double weight;

  bool operator()(double const* const* p, double* residual) const {
    if (!model->AngleError(ParametersOfBlocks(p, optics), marker, residual)) return false;
    residual[0] *= weight, residual[1] *= weight;
    return true;
  }
};

using TracedMarkerCostFunction = ceres::DynamicNumericDiffCostFunction<TracedMarkerCost, ceres::CENTRAL>;

// Indices into the ScalarFit of one panel's parameters.
struct PanelIndices {
  int distance = -1, eye_from_panel_x_m = -1, eye_from_panel_y_m = -1, rotation = -1;
};

std::string Quoted(const std::string& name) { return "\"" + name + "\""; }

// The lenses and curved mirrors on the paths of `measured` layers, nearest the
// eye first, and each layer's view of them (marker_model.h's c_i).
std::vector<Optic> FindOptics(const DisplaySystem& system, const std::vector<bool>& measured,
                              std::vector<LayerOptics>* layer_optics) {
  std::vector<Optic> optics;
  layer_optics->assign(system.layers.size(), {});
  for (size_t k = 0; k < system.layers.size(); ++k) {
    if (!measured[k]) continue;
    const std::vector<PathStep>& path = system.layers[k].path;
    double previous_optic = 0;
    for (size_t j = 0; j < path.size(); ++j) {
      const PathStep& step = path[j];
      if (step.power_diopters == 0) continue;
      auto it = std::find_if(optics.begin(), optics.end(), [&](const Optic& o) { return o.name == step.element; });
      if (it == optics.end()) {
        Optic o;
        o.name = step.element;
        o.focal_length = 1.0 / step.power_diopters;
        o.position = *step.position_m;
        // The nearest element before it with a place (the magnifier placed by eye_relief may follow an unplaced one).
        double placed_at = 0;
        for (size_t i = j; i-- > 0;)
          if (path[i].position_m) {
            placed_at = *path[i].position_m;
            break;
          }
        o.gap = o.position - placed_at;
        o.before = j > 0 ? path[j - 1].element : "";
        o.placed_before = j == 0 || path[j - 1].position_m.has_value();
        o.surfaces = step.lens_system != nullptr;
        optics.push_back(o);
        it = optics.end() - 1;
      }
      it->layers.push_back(static_cast<int>(k));
      (*layer_optics)[k].element.push_back(static_cast<int>(it - optics.begin()));
      (*layer_optics)[k].fixed_spacing.push_back(it->position - previous_optic - it->gap);
      previous_optic = it->position;
    }
  }
  return optics;
}

// One layer's parameters, each read through `value` from its index in the fit.
template <typename T, typename Value>
MarkerParameters<T> LayerParameters(const PanelIndices& p, int pan, int tilt, int roll, const LayerOptics& layer_optics,
                                    const std::vector<Optic>& optics, Value value) {
  MarkerParameters<T> q{value(p.distance),
                        value(p.eye_from_panel_x_m),
                        value(p.eye_from_panel_y_m),
                        value(p.rotation),
                        value(pan),
                        value(tilt),
                        value(roll),
                        {},
                        {},
                        {}};
  for (int o : layer_optics.element) {
    q.gaps.push_back(value(optics[o].gap_index));
    q.focal_lengths.push_back(value(optics[o].focal));
    q.distortions.push_back(value(optics[o].distortion));
  }
  return q;
}

// Markers that fit a mirror image of the panel far better than the panel as
// the scene mounts it: a "reversed" or a combiner fold that is wrong.
void CheckMirroring(const DisplaySystem& system, const std::vector<std::vector<const MarkerDatum*>>& by_layer,
                    CalibrationReport* report) {
  for (size_t k = 0; k < by_layer.size(); ++k) {
    std::map<size_t, std::pair<std::vector<Point2>, std::vector<Point2>>> by_capture;  // parallax differs per capture
    for (const MarkerDatum* d : by_layer[k]) {
      by_capture[d->capture].first.push_back({d->placement.local_x_m, d->placement.local_y_m});
      by_capture[d->capture].second.push_back({std::tan(d->angle_x), std::tan(d->angle_y)});
    }
    double as_given = 0, mirrored = 0;
    size_t count = 0;
    for (auto& [capture, points] : by_capture) {
      auto& [from, to] = points;
      if (Spread(from).collinear) continue;  // a line and its mirror image cannot be told apart
      std::vector<Point2> mirror;
      for (const Point2& p : from) mirror.push_back(std::conj(p));
      const double n = static_cast<double>(from.size());
      as_given += n * std::pow(FitSimilarity(from, to).rms, 2);
      mirrored += n * std::pow(FitSimilarity(mirror, to).rms, 2);
      count += from.size();
    }
    if (count == 0) continue;
    as_given = std::sqrt(as_given / count), mirrored = std::sqrt(mirrored / count);
    if (ArcminFromRadians(as_given) > 1.0 && mirrored < 0.25 * as_given)
      report->warnings.push_back("panel " + Quoted(system.layers[k].name) +
                                 ": its markers fit a mirror image of the panel far better than the panel as the scene "
                                 "mounts it (RMS " +
                                 FormatFixed(ArcminFromRadians(mirrored), 3) + " arcmin mirrored, " +
                                 FormatFixed(ArcminFromRadians(as_given), 3) +
                                 " arcmin as mounted): check its \"reversed\" and the combiner's fold");
  }
}

// Every panel's place with the optics as fitted: a fitted gap moves everything
// behind the element (gaps count from the element before), a panel keeps its
// distance from the nearest element with power in front of it.
void PlaceAsFitted(const DisplaySystem& system, const std::vector<Optic>& optics, CalibratedDisplay* display) {
  struct Walked {
    double position = 0;  // of the panel, fitted
    double before = 0;    // of the element before it, fitted (0: the pupil)
    bool before_is_panel = false;
    std::string before_name;
  };
  std::map<std::string, double> panel_at;
  std::vector<Walked> walked(system.layers.size());
  for (size_t k = 0; k < system.layers.size(); ++k) {
    const VirtualLayer& layer = system.layers[k];
    CalibratedPanel& panel = display->panels[k];
    double shift = 0, optic_at = 0;
    for (const PathStep& step : layer.path) {
      if (step.power_diopters != 0) {
        const CalibratedOptic* fitted = display->find_optic(step.element);
        auto designed =
            std::find_if(optics.begin(), optics.end(), [&](const Optic& o) { return o.name == step.element; });
        if (fitted && designed != optics.end()) {
          shift += fitted->gap_m - designed->gap;
          panel.optics_fitted = panel.optics_fitted || fitted->gap_fitted || fitted->focal_length_fitted;
        }
        optic_at = *step.position_m + shift;
      }
      if (step.kind == ElementKind::kPanel) {
        walked[k].before_is_panel = true;
        walked[k].before_name = step.element;
      } else {
        walked[k].before_is_panel = false;
        walked[k].before = step.position_m.value_or(0.0) + shift;
      }
    }
    walked[k].position = optic_at + panel.distance_m;
    panel_at[layer.name] = walked[k].position;
  }
  for (size_t k = 0; k < system.layers.size(); ++k) {
    const Walked& w = walked[k];
    display->panels[k].gap_m = w.position - (w.before_is_panel ? panel_at.at(w.before_name) : w.before);
  }
}

// One geometry fit, step by step: the markers, the parameters (each held
// where the data's shape cannot determine it), the residuals, the solve, and
// the results by parameter.
class GeometryFitter {
 public:
  GeometryFitter(const DisplaySystem& system, const Measurements& measurements, const CalibrationOptions& options,
                 CalibrationReport* report)
      : system_(system),
        measurements_(measurements),
        options_(options),
        report_(report),
        layer_count_(static_cast<int>(system.layers.size())),
        magnifier_(!system.lens.empty()),  // the paper's layout: one lens, the same on every path
        farthest_reference_(options.reference == AxisReference::kFarthestPanel) {}

  bool Fit(CalibratedDisplay* display) {
    ReadMarkers();
    if (data_.empty()) return true;
    SortByLayer();
    PrepareTracedLayers();
    if (data_.empty()) return true;
    if (!CheckReference()) return false;
    CheckMirroring(system_, by_layer_, report_);
    AddParameters();
    HoldWhatParallaxAloneTells();
    if (!farthest_reference_)
      for (int i : {pan_, tilt_, roll_}) Hold(i, ParameterStatus::kReference);
    AddResiduals();
    if (!Solve() || !CheckFittedImages()) return false;
    if (result_.covariance.size() == 0)
      report_->warnings.push_back("no uncertainties for the geometry: " + result_.covariance_message);
    ReportResiduals();
    WriteResults(display);
    return CheckModelError(blocks_, result_.free_parameters, options_, report_, Remedies());
  }

 private:
  void ReadMarkers() {
    std::set<std::pair<double, double>> positions;
    for (size_t c = 0; c < measurements_.captures.size(); ++c) {
      const Capture& capture = measurements_.captures[c];
      positions.insert({capture.camera_position[0], capture.camera_position[1]});
      for (const PanelMarkers& markers : capture.panels) {
        const int k = LayerIndex(system_, markers.panel);
        blocks_.push_back({markers.panel, capture.camera_position, markers.where, markers.detection_noise});
        for (const MarkerObservation& o : markers.markers)
          data_.push_back(
              {k,
               c,
               PlaceMarker(system_.layers[k], o.col, o.row, capture.camera_position[0], capture.camera_position[1]),
               {o.col, o.row},
               o.angle_x,
               o.angle_y,
               o.where,
               static_cast<int>(blocks_.size()) - 1});
      }
    }
    ReadDetectionNoise();
    report_->markers = static_cast<int>(data_.size());
    report_->captures = static_cast<int>(measurements_.captures.size());
    report_->camera_positions = static_cast<int>(positions.size());
  }

  // The residuals are whitened by the noise detect measured in each
  // photograph when every photograph has it; else the fit estimates the noise
  // from its own residuals, and cannot tell a model error from noise.
  void ReadDetectionNoise() {
    const long with_noise =
        std::count_if(blocks_.begin(), blocks_.end(), [](const MarkerBlock& b) { return b.noise.has_value(); });
    noise_known_ = !blocks_.empty() && with_noise == static_cast<long>(blocks_.size());
    report_->noise_from_detection = noise_known_;
    if (noise_known_) PoolNoise();
    if (with_noise > 0 && !noise_known_)
      report_->warnings.push_back(
          "only " + std::to_string(with_noise) + " of the " + std::to_string(blocks_.size()) +
          " photographs' marker sets carry their detection noise: it is not used; the noise is estimated from the "
          "fit's residuals, which cannot tell a model error from noise");
  }

  // The photographs share one noise for the fit's weights (their variances
  // weighted by their degrees of freedom): the corners' error has a part that
  // does not grow with a photograph's noise (the sensor's sampling phase),
  // which weights by each photograph's own noise would discount where it is
  // largest against that noise. One panel's photographs differ in the
  // camera's position only, so the model-error test pools them by panel.
  void PoolNoise() {
    std::map<std::string, double> variance_sum, dof_sum;
    double all_variance = 0, all_dof = 0;
    for (const MarkerBlock& b : blocks_) {
      const double dof = std::max(1, b.noise->degrees_of_freedom), variance = b.noise->sigma_rad * b.noise->sigma_rad;
      variance_sum[b.panel] += dof * variance, dof_sum[b.panel] += dof;
      all_variance += dof * variance, all_dof += dof;
    }
    weight_noise_rad_ = std::sqrt(all_variance / all_dof);
    // Each keeps its own degrees of freedom: the model-error test adds them up.
    for (MarkerBlock& b : blocks_) b.noise->sigma_rad = std::sqrt(variance_sum[b.panel] / dof_sum[b.panel]);
  }

  // Each layer's markers, the spread of their pixels, the camera positions
  // they are seen from, and the optics on the paths of the layers with markers.
  void SortByLayer() {
    by_layer_.assign(layer_count_, {});
    for (const MarkerDatum& d : data_) by_layer_[d.layer].push_back(&d);
    spread_.assign(layer_count_, {});
    positions_seen_.assign(layer_count_, 0);
    std::vector<bool> measured(layer_count_);
    for (int k = 0; k < layer_count_; ++k) {
      std::vector<Point2> pixels;
      std::set<std::pair<double, double>> seen_from;
      for (const MarkerDatum* d : by_layer_[k]) {
        pixels.push_back(d->pixel);
        const auto& position = measurements_.captures[d->capture].camera_position;
        seen_from.insert({position[0], position[1]});
      }
      spread_[k] = Spread(pixels);
      positions_seen_[k] = static_cast<int>(seen_from.size());
      measured[k] = !by_layer_[k].empty();
    }
    optics_ = FindOptics(system_, measured, &layer_optics_);
  }

  bool CheckReference() {
    if (!farthest_reference_ || spread_[0].distinct >= 2) return true;
    report_->message =
        "the axis reference \"farthest-panel\" needs markers at two or more pixels of the farthest panel " +
        Quoted(system_.layers[0].name) + (by_layer_[0].empty() ? ", which has none" : "");
    return false;
  }

  int Add(ScalarParameter p, const std::string& q) {
    quantity_.push_back(q);
    status_.push_back(ParameterStatus::kFitted);
    return fit_.Add(std::move(p));
  }

  void Hold(int index, ParameterStatus why) {
    fit_.Hold(index);
    status_[index] = why;
  }

  void AddParameters() {
    for (Optic& o : optics_) {
      std::optional<double> beyond_the_eye;  // the magnifier's focal point stays behind the eye
      if (magnifier_) beyond_the_eye = system_.eye.eye_relief_m * (1 + 1e-6);
      o.focal = Add({"the focal length of " + Quoted(o.name), o.focal_length, 0, beyond_the_eye, std::nullopt},
                    "focal_length");
      o.gap_index =
          Add({"the gap of " + Quoted(o.name), o.gap, 0, 0.0, std::nullopt}, "gap");  // after the element before
      o.distortion = Add({"the distortion of " + Quoted(o.name), 0.0, 0, std::nullopt, std::nullopt}, "distortion");
    }
    pan_ = Add({"the camera's pan", 0, 1, {}, {}}, "pan");
    tilt_ = Add({"the camera's tilt", 0, 1, {}, {}}, "tilt");
    roll_ = Add({"the camera's roll", 0, 1, {}, {}}, "roll");
    index_.assign(layer_count_, {});
    for (int k = 0; k < layer_count_; ++k) AddPanelParameters(k);
  }

  // Whether the focal length may be fitted (before the parameters that decide it for sure exist).
  bool MayFitFocalLength() const {
    return options_.focal_length == FitChoice::kFit ||
           (options_.focal_length == FitChoice::kAuto &&
            std::any_of(positions_seen_.begin(), positions_seen_.end(), [](int n) { return n >= 2; }));
  }

  void AddPanelParameters(int k) {
    const VirtualLayer& layer = system_.layers[k];
    const std::string panel = "panel " + Quoted(layer.name);
    if (by_layer_[k].empty()) {
      report_->warnings.push_back(panel + " has no markers: its distance, offset and rotation keep their scene values");
      return;
    }
    const bool reference = farthest_reference_ && k == 0;
    std::optional<double> beyond_focus;
    if (magnifier_ && !MayFitFocalLength()) beyond_focus = system_.focal_length_m;
    const double closest = 1e-3 * (magnifier_ ? system_.focal_length_m : layer.panel_distance_m);
    PanelIndices& index = index_[k];
    index.distance = Add({"the distance of " + panel, layer.panel_distance_m, 2, closest, beyond_focus}, "distance");
    index.rotation =
        Add({"the rotation of " + panel, reference ? 0.0 : layer.panel.rotation_rad, 3, {}, {}}, "rotation");
    index.eye_from_panel_x_m =
        Add({"the offset x of " + panel, reference ? 0.0 : layer.panel.eye_from_panel_m[0], 4, {}, {}}, "offset_x");
    index.eye_from_panel_y_m =
        Add({"the offset y of " + panel, reference ? 0.0 : layer.panel.eye_from_panel_m[1], 4, {}, {}}, "offset_y");
    if (reference)
      for (int i : {index.rotation, index.eye_from_panel_x_m, index.eye_from_panel_y_m})
        Hold(i, ParameterStatus::kReference);
    if (spread_[k].distinct == 1) {
      HoldWhatOnePixelCannotTell(k, reference);
    } else if (spread_[k].collinear) {
      report_->warnings.push_back(panel +
                                  ": its markers lie on one line of the panel, so its magnification and rotation "
                                  "rest on that line's length and tilt alone and nothing checks the other "
                                  "direction; add markers off the line");
    }
  }

  // One pixel fixes where the panel is, not how it is turned; its size only
  // through parallax, when it is seen from two camera positions.
  void HoldWhatOnePixelCannotTell(int k, bool reference) {
    const VirtualLayer& layer = system_.layers[k];
    const bool parallax = positions_seen_[k] >= 2;
    if (!parallax) Hold(index_[k].distance, ParameterStatus::kUndetermined);
    if (!reference) Hold(index_[k].rotation, ParameterStatus::kUndetermined);
    const Point2 pixel = by_layer_[k].front()->pixel;
    report_->warnings.push_back(
        "panel " + Quoted(layer.name) + ": its markers show a single panel pixel (" + FormatFixed(pixel.real(), 1) +
        ", " + FormatFixed(pixel.imag(), 1) + "), which fixes the offset but not the rotation" +
        (parallax ? "" : " nor the magnification") + ": its " +
        (parallax ? "rotation keeps its scene value ("
                  : "distance and rotation keep their scene values (" + ShowValue("distance", layer.panel_distance_m) +
                        ", ") +
        ShowValue("rotation", layer.panel.rotation_rad) + "); show markers at three or more pixels not on one line");
  }

  // Layers behind real lenses are seen through the exact trace: each marker
  // with its Jacobian at the scene's values. A marker whose ray the scene's
  // lenses lose is left out before anything counts it, and said so.
  void PrepareTracedLayers() {
    traced_.clear();
    traced_.resize(layer_count_);
    for (int k = 0; k < layer_count_; ++k)
      if (!by_layer_[k].empty() && system_.layers[k].ray_map)
        traced_[k] = std::make_unique<TracedLayerModel>(system_.layers[k], ParametersBefore(k));
    std::vector<MarkerDatum> kept;
    traced_markers_.clear();
    int lost = 0;
    std::string first_lost;
    for (const MarkerDatum& d : data_) {
      std::optional<TracedMarker> t;
      if (traced_[d.layer] && !(t = traced_[d.layer]->Prepare(d.placement, d.angle_x, d.angle_y))) {
        if (lost++ == 0) first_lost = d.where.str();
        continue;
      }
      kept.push_back(d);
      traced_markers_.push_back(std::move(t));
    }
    if (lost == 0) return;
    report_->warnings.push_back(std::to_string(lost) + " marker" + (lost > 1 ? "s" : "") +
                                " seen by the camera would not reach its panel through the scene's lenses (the first "
                                "at " +
                                first_lost + "): left out of the fit");
    data_ = std::move(kept);
    report_->markers = static_cast<int>(data_.size());
    SortByLayer();
  }

  // The layer's parameters as designed (seen by an unturned camera), from the
  // scene alone: usable before the fit's parameters exist.
  MarkerParameters<double> ParametersBefore(int k) const {
    const VirtualLayer& layer = system_.layers[k];
    MarkerParameters<double> q{layer.panel_distance_m,
                               layer.panel.eye_from_panel_m[0],
                               layer.panel.eye_from_panel_m[1],
                               layer.panel.rotation_rad,
                               0,
                               0,
                               0,
                               {},
                               {},
                               {}};
    for (int o : layer_optics_[k].element)
      q.gaps.push_back(optics_[o].gap), q.focal_lengths.push_back(optics_[o].focal_length), q.distortions.push_back(0);
    return q;
  }

  bool Traced(const MarkerDatum& d) const { return traced_[d.layer] != nullptr; }
  // Whether every measured panel behind optic `o` is traced: its distortion then enters no residual.
  bool AllTraced(const Optic& o) const {
    return std::all_of(o.layers.begin(), o.layers.end(), [&](int k) { return traced_[k] != nullptr; });
  }

  // What the model-error message may offer to fit.
  ModelErrorRemedies Remedies() const {
    ModelErrorRemedies r;
    r.focal_lengths = std::any_of(optics_.begin(), optics_.end(), [](const Optic& o) { return !o.surfaces; });
    r.distortions = std::any_of(optics_.begin(), optics_.end(), [&](const Optic& o) { return !AllTraced(o); });
    r.surfaces = std::any_of(optics_.begin(), optics_.end(), [](const Optic& o) { return o.surfaces; });
    return r;
  }

  // Model minus measurement of marker i under the layer's parameters `q` (rad).
  std::array<double, 2> AngleError(size_t i, const MarkerParameters<double>& q) const {
    const MarkerDatum& d = data_[i];
    std::array<double, 2> e{NAN, NAN};
    if (Traced(d)) {
      traced_[d.layer]->AngleError(q, *traced_markers_[i], e.data());
      return e;
    }
    PredictVisualAngle(q, layer_optics_[d.layer], d.placement, e.data());
    return {e[0] - d.angle_x, e[1] - d.angle_y};
  }

  // The panel's virtual depth under `q`.
  double Diopters(int k, const MarkerParameters<double>& q) const {
    return traced_[k] ? traced_[k]->Diopters(q) : LayerTransfer(layer_optics_[k], q).diopters();
  }

  // Only parallax tells an element's focal length or gap from the distances of the panels behind it.
  void HoldWhatParallaxAloneTells() {
    for (const Optic& o : optics_) {
      if (o.surfaces) {
        Hold(o.focal, ParameterStatus::kNotFitted);
        Hold(o.distortion, ParameterStatus::kNotFitted);
        report_->notes.push_back(Quoted(o.name) +
                                 " is described by its surfaces: the fit traces them exactly, so its focal length "
                                 "and distortion are not fitted (they are the surfaces')");
      }
      bool parallax = false;
      for (int k : o.layers)
        parallax = parallax || (index_[k].distance >= 0 && !fit_.held(index_[k].distance) && positions_seen_[k] >= 2);
      const std::string named = magnifier_ ? "" : " of " + Quoted(o.name);
      if (!o.surfaces && options_.focal_length == FitChoice::kHold)
        Hold(o.focal, ParameterStatus::kNotFitted);
      else if (!o.surfaces && !parallax)
        HoldWithoutParallax(o.focal, "the focal length" + named);
      if (!o.surfaces && AllTraced(o)) {
        Hold(o.distortion, ParameterStatus::kNotFitted);
        if (options_.distortion != FitChoice::kHold)
          report_->notes.push_back("the distortion of " + Quoted(o.name) +
                                   " is not fitted: every panel behind it is seen through real lenses, traced");
      } else if (options_.distortion == FitChoice::kHold && !o.surfaces) {
        Hold(o.distortion, ParameterStatus::kNotFitted);
      }
      if (options_.lens_gaps == FitChoice::kHold) {
        Hold(o.gap_index, ParameterStatus::kNotFitted);
      } else if (!o.placed_before) {
        Hold(o.gap_index, ParameterStatus::kNotFitted);
        report_->warnings.push_back("the gap of " + Quoted(o.name) + " is not fitted: " + Quoted(o.before) +
                                    " before it has no place of its own (a flat element without \"gap\"), so no gap "
                                    "could be written; give " +
                                    Quoted(o.before) + " a \"gap\"");
      } else if (!parallax) {
        HoldWithoutParallax(o.gap_index, "the gap of " + Quoted(o.name));
      }
    }
  }

  // A focal length or gap left to FitChoice::kAuto that the data cannot
  // determine is held as asked, which the report notes; one the options ask to
  // fit is a warning.
  bool Auto(int i) const {
    return (quantity_[i] == "focal_length" && options_.focal_length == FitChoice::kAuto) ||
           (quantity_[i] == "gap" && options_.lens_gaps == FitChoice::kAuto);
  }
  std::vector<std::string>& NotesOrWarnings(int i) { return Auto(i) ? report_->notes : report_->warnings; }

  void HoldWithoutParallax(int i, const std::string& what) {
    Hold(i, ParameterStatus::kUndetermined);
    NotesOrWarnings(i).push_back(what + " cannot be told from the panel distances while each panel " +
                                 (magnifier_ ? "" : "behind it ") +
                                 "is seen from one camera position only: it keeps "
                                 "its scene value (" +
                                 ShowValue(quantity_[i], fit_.parameter(i).start) +
                                 "); add "
                                 "captures from other camera positions (\"camera_position\") to fit it");
  }

  void AddResiduals() {
    for (size_t i = 0; i < data_.size(); ++i) {
      const MarkerDatum& d = data_[i];
      const PanelIndices& p = index_[d.layer];
      const LayerOptics& path = layer_optics_[d.layer];
      const double weight = noise_known_ ? 1.0 / weight_noise_rad_ : 1.0;
      std::vector<int> blocks = {p.distance, p.eye_from_panel_x_m, p.eye_from_panel_y_m, p.rotation, pan_, tilt_,
                                 roll_};
      for (int o : path.element)
        blocks.insert(blocks.end(), {optics_[o].gap_index, optics_[o].focal, optics_[o].distortion});
      ceres::DynamicCostFunction* cost = nullptr;
      if (Traced(d))
        cost = new TracedMarkerCostFunction(
            new TracedMarkerCost{traced_[d.layer].get(), *traced_markers_[i], path.element.size(), weight});
      else
        cost = new MarkerCostFunction(new MarkerCost{d.placement, path, d.angle_x, d.angle_y, weight});
      for (size_t b = 0; b < blocks.size(); ++b) cost->AddParameterBlock(1);
      cost->SetNumResiduals(2);
      fit_.AddResidual(cost, MakeLoss(options_.loss, options_.marker_loss_scale_rad * weight), blocks);
    }
  }

  bool Solve() {
    ScalarFitOptions solve = ScalarFitOptionsOf(options_);
    solve.unit_noise = noise_known_;
    result_ = fit_.Solve(solve);
    report_->geometry_solver = result_.summary.BriefReport();
    if (!result_.usable) {
      report_->message = "the geometry fit failed: " + result_.summary.message;
      return false;
    }
    for (const UndeterminedParameter& u : result_.undetermined) {
      status_[u.index] = ParameterStatus::kUndetermined;
      NotesOrWarnings(u.index).push_back(UndeterminedWarning(fit_, u, quantity_[u.index]));
    }
    return true;
  }

  // A fit that puts a panel where this display cannot image it: beyond the
  // magnifier's focal length, into the pupil plane or behind the eye.
  bool CheckFittedImages() {
    for (int k = 0; k < layer_count_; ++k) {
      if (by_layer_[k].empty()) continue;
      const MarkerParameters<double> q = ParametersAfter(k);
      if (traced_[k]) {
        double diopters = NAN;
        try {
          diopters = traced_[k]->Diopters(q);
        } catch (const Error&) {  // the lenses as fitted lose the paraxial rays
        }
        if (diopters >= 0) continue;
        report_->message = "the fit images panel " + Quoted(system_.layers[k].name) +
                           (std::isnan(diopters) ? " where the real lenses as fitted lose its paraxial rays"
                                                 : " behind the eye (" + FormatFixed(diopters, 3) + " D)") +
                           ", through the real lenses in front of it: the measurements do not match this display";
        return false;
      }
      const RayTransfer<double> m = LayerTransfer(layer_optics_[k], q);
      const std::vector<int>& on_path = layer_optics_[k].element;
      if (magnifier_ && q.distance > q.focal_lengths[0]) {
        report_->message = "the fit puts panel " + Quoted(system_.layers[k].name) + " " +
                           ShowValue("distance", q.distance) + " from the lens, beyond the focal length " +
                           ShowValue("focal_length", q.focal_lengths[0]) +
                           ": the measurements do not match this display";
        return false;
      }
      if (!magnifier_ && (m.b == 0 || m.diopters() < 0)) {
        report_->message =
            "the fit images panel " + Quoted(system_.layers[k].name) + " " +
            (m.b == 0 ? "into the pupil plane" : "behind the eye (" + FormatFixed(m.diopters(), 3) + " D)") +
            (on_path.empty() ? "" : ", through the optics in front of it as fitted") +
            ": the measurements do not match this display";
        return false;
      }
    }
    return true;
  }

  MarkerParameters<double> ParametersAfter(int k) const {
    return LayerParameters<double>(index_[k], pan_, tilt_, roll_, layer_optics_[k], optics_,
                                   [&](int i) { return fit_.value(i); });
  }

  // The markers' RMS errors before and after the fit, in all and by panel.
  void ReportResiduals() {
    std::vector<double> before(layer_count_, 0.0), after(layer_count_, 0.0), components;
    double sum_before = 0, sum_after = 0;
    std::vector<std::pair<double, const MarkerDatum*>> errors;
    for (size_t i = 0; i < data_.size(); ++i) {
      const MarkerDatum& d = data_[i];
      const std::array<double, 2> a = AngleError(i, ParametersBefore(d.layer)),
                                  b = AngleError(i, ParametersAfter(d.layer));
      const double error_before = a[0] * a[0] + a[1] * a[1], error_after = b[0] * b[0] + b[1] * b[1];
      before[d.layer] += error_before, after[d.layer] += error_after;
      sum_before += error_before, sum_after += error_after;
      components.push_back(std::abs(b[0]));
      components.push_back(std::abs(b[1]));
      errors.push_back({std::sqrt(error_after), &d});
      blocks_[d.block].squared_error_rad2 += error_after;
      blocks_[d.block].markers += 1;
    }
    report_->marker_rms_before_rad = std::sqrt(sum_before / data_.size());
    report_->marker_rms_after_rad = std::sqrt(sum_after / data_.size());
    for (int k = 0; k < layer_count_; ++k) {
      if (by_layer_[k].empty()) continue;
      PanelResiduals& r = report_->panels[k];
      r.markers = static_cast<int>(by_layer_[k].size());
      r.marker_rms_before_rad = std::sqrt(before[k] / r.markers);
      r.marker_rms_after_rad = std::sqrt(after[k] / r.markers);
    }
    report_->marker_noise_rad = noise_known_ ? weight_noise_rad_ : result_.noise;
    if (options_.loss == RobustLoss::kNone && components.size() > 8) WarnOutliers(&components, errors);
    if (options_.loss != RobustLoss::kNone) ReportDownWeighted(errors);
  }

  // Gross errors stand out against the median's noise, which they do not inflate.
  void WarnOutliers(std::vector<double>* components, const std::vector<std::pair<double, const MarkerDatum*>>& errors) {
    std::nth_element(components->begin(), components->begin() + components->size() / 2, components->end());
    const double sigma = 1.4826 * (*components)[components->size() / 2];
    auto worst = std::max_element(errors.begin(), errors.end());
    const long beyond = std::count_if(errors.begin(), errors.end(), [&](const auto& x) { return x.first > 6 * sigma; });
    if (sigma > 0 && beyond > 0)
      report_->warnings.push_back(std::to_string(beyond) + " marker" + (beyond > 1 ? "s lie" : " lies") +
                                  " beyond 6 sigma of the noise (the worst " +
                                  FormatFixed(ArcminFromRadians(worst->first), 3) + " arcmin, at " +
                                  worst->second->where.str() +
                                  "): outliers bias a least-squares fit; --loss cauchy discounts them (huber "
                                  "keeps a constant pull from each, which can move the fit well beyond its "
                                  "reported uncertainty)");
  }

  // How many markers the robust loss weighted by less than half (Huber beyond
  // twice its scale, Cauchy beyond its scale: rho'(s^2) = 1 / (1 + s^2 / a^2)),
  // and in which photographs.
  void ReportDownWeighted(const std::vector<std::pair<double, const MarkerDatum*>>& errors) {
    const double beyond = (options_.loss == RobustLoss::kHuber ? 2.0 : 1.0) * options_.marker_loss_scale_rad;
    std::map<int, int> by_block;
    int count = 0;
    for (const auto& [error, d] : errors)
      if (error > beyond) ++by_block[d->block], ++count;
    if (count == 0) return;
    std::vector<std::pair<int, int>> worst(by_block.begin(), by_block.end());
    std::sort(worst.begin(), worst.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    std::vector<std::string> where;
    for (size_t k = 0; k < std::min<size_t>(3, worst.size()); ++k) {
      const MarkerBlock& b = blocks_[worst[k].first];
      where.push_back(std::to_string(worst[k].second) + " of panel " + Quoted(b.panel) +
                      (b.where.file.empty() ? "" : " in " + b.where.file));
    }
    report_->warnings.push_back("the " + ToString(options_.loss) + " loss weighted " + std::to_string(count) + " of " +
                                std::to_string(errors.size()) + " markers by less than half (errors above " +
                                Arcmin(beyond) + "): " + JoinedBySemicolons(where) +
                                (worst.size() > 3 ? "; and others" : ""));
  }

  ParameterEstimate Estimate(const std::string& element, int i) {
    ParameterEstimate p;
    p.element = element;
    p.quantity = quantity_[i];
    p.scene_value = fit_.parameter(i).start;
    p.value = fit_.value(i);
    p.status = status_[i];
    if (p.status == ParameterStatus::kFitted && result_.covariance.size())
      p.std_dev = std::sqrt(result_.covariance(i, i));
    if (p.status != ParameterStatus::kFitted) return p;
    if (const std::string why = Unresolved(fit_.parameter(i), p); !why.empty()) {
      p.status = ParameterStatus::kUnresolved;
      report_->unresolved.push_back(fit_.parameter(i).name + ": it " + why);
      report_->warnings.push_back("the data do not determine " + fit_.parameter(i).name + ": it " + why +
                                  "; it is reported undetermined, and `fit` writes no calibrated scene unless --force");
    }
    return p;
  }

  bool Fitted(int i) const { return status_[i] == ParameterStatus::kFitted; }

  // A lens's measured distortion: the calibrated scene cannot carry it (an
  // ideal lens has none; a real lens's is that of its surfaces), so it is
  // reported, with its size at the edge of what the markers span.
  void ReportDistortion(const Optic& o) {
    report_->parameters.push_back(Estimate(o.name, o.distortion));
    const ParameterEstimate& k = report_->parameters.back();
    if (k.status != ParameterStatus::kFitted) return;
    double widest = 0;  // tan^2 of the farthest marker from the axis, seen from the pupil's center
    for (const MarkerDatum& d : data_)
      widest = std::max(widest, std::pow(std::tan(d.angle_x), 2) + std::pow(std::tan(d.angle_y), 2));
    report_->notes.push_back("the distortion of " + Quoted(o.name) + " is measured, k = " + FormatFixed(k.value, 4) +
                             (k.std_dev ? " +- " + FormatFixed(*k.std_dev, 4) : "") + " (" +
                             FormatFixed(100 * k.value * widest, 2) + " % at the markers' widest " +
                             FormatFixed(std::atan(std::sqrt(widest)) * kDegreesPerRadian, 1) +
                             " deg): the calibrated scene does not carry it (an ideal lens has none; a lens described "
                             "by its surfaces has its own)");
  }

  // The results, by parameter.
  void WriteResults(CalibratedDisplay* display) {
    display->optics.clear();
    for (const Optic& o : optics_) {
      report_->parameters.push_back(Estimate(o.name, o.focal));
      if (options_.lens_gaps != FitChoice::kHold) report_->parameters.push_back(Estimate(o.name, o.gap_index));
      if (options_.distortion != FitChoice::kHold) ReportDistortion(o);
      display->optics.push_back(
          {o.name, fit_.value(o.focal), fit_.value(o.gap_index), Fitted(o.focal), Fitted(o.gap_index)});
    }
    for (int k = 0; k < layer_count_; ++k)
      if (!by_layer_[k].empty()) WritePanelResults(k, &display->panels[k]);
    PlaceAsFitted(system_, optics_, display);
    if (farthest_reference_)
      for (int i : {pan_, tilt_, roll_}) report_->parameters.push_back(Estimate("camera", i));
  }

  void WritePanelResults(int k, CalibratedPanel* out) {
    const VirtualLayer& layer = system_.layers[k];
    const PanelIndices& p = index_[k];
    ParameterEstimate distance = Estimate(layer.name, p.distance);
    ParameterEstimate depth = distance;
    depth.quantity = "virtual_depth";
    depth.derived = true;
    depth.scene_value = layer.diopters;
    depth.value = Diopters(k, ParametersAfter(k));
    if (distance.std_dev) depth.std_dev = VirtualDepthStdDev(k);
    report_->parameters.push_back(distance);
    report_->parameters.push_back(depth);
    for (int i : {p.eye_from_panel_x_m, p.eye_from_panel_y_m, p.rotation})
      report_->parameters.push_back(Estimate(layer.name, i));

    out->geometry_measured = true;
    out->distance_m = distance.value;
    out->eye_from_panel_x_m = fit_.value(p.eye_from_panel_x_m);
    out->eye_from_panel_y_m = fit_.value(p.eye_from_panel_y_m);
    out->rotation_rad = fit_.value(p.rotation);
  }

  // Propagated through D(s, g, f) with the covariance of the path's parameters (derivatives by dual numbers).
  double VirtualDepthStdDev(int k) const {
    const PanelIndices& p = index_[k];
    std::vector<int> on_path = {p.distance};
    for (int o : layer_optics_[k].element)
      on_path.insert(on_path.end(), {optics_[o].gap_index, optics_[o].focal, optics_[o].distortion});
    std::vector<double> gradient;
    for (int wrt : on_path) {
      if (traced_[k]) {  // by central differences of the trace's paraxial limit
        const double h = 1e-7 * std::max(1.0, std::abs(fit_.value(wrt)));
        auto at = [&](double step) {
          return Diopters(k, LayerParameters<double>(p, pan_, tilt_, roll_, layer_optics_[k], optics_,
                                                     [&](int i) { return fit_.value(i) + (i == wrt ? step : 0.0); }));
        };
        gradient.push_back((at(h) - at(-h)) / (2 * h));
        continue;
      }
      using Dual = ceres::Jet<double, 1>;
      const auto q = LayerParameters<Dual>(p, pan_, tilt_, roll_, layer_optics_[k], optics_, [&](int i) {
        Dual x(fit_.value(i));
        if (i == wrt) x.v[0] = 1;
        return x;
      });
      gradient.push_back(LayerTransfer(layer_optics_[k], q).diopters().v[0]);
    }
    double variance = 0;
    for (size_t a = 0; a < on_path.size(); ++a)
      for (size_t b = 0; b < on_path.size(); ++b)
        variance += gradient[a] * gradient[b] * result_.covariance(on_path[a], on_path[b]);
    return std::sqrt(std::max(0.0, variance));
  }

  const DisplaySystem& system_;
  const Measurements& measurements_;
  const CalibrationOptions& options_;
  CalibrationReport* report_;
  const int layer_count_;
  const bool magnifier_;
  const bool farthest_reference_;

  std::vector<MarkerDatum> data_;
  std::vector<MarkerBlock> blocks_;
  bool noise_known_ = false;
  double weight_noise_rad_ = 1;  // rad: the pooled detection noise, when known
  std::vector<std::vector<const MarkerDatum*>> by_layer_;
  std::vector<PointSpread> spread_;
  std::vector<int> positions_seen_;
  std::vector<LayerOptics> layer_optics_;
  std::vector<Optic> optics_;

  ScalarFit fit_;
  std::vector<std::string> quantity_;
  std::vector<ParameterStatus> status_;
  int pan_ = -1, tilt_ = -1, roll_ = -1;
  std::vector<PanelIndices> index_;
  ScalarFitResult result_;
  std::vector<std::unique_ptr<TracedLayerModel>> traced_;    // per layer: set behind real lenses
  std::vector<std::optional<TracedMarker>> traced_markers_;  // per datum of a traced layer
};

}  // namespace

std::string Unresolved(const ScalarParameter& parameter, const ParameterEstimate& p) {
  auto at = [&](const std::optional<double>& bound) {
    return bound && std::abs(p.value - *bound) <= 1e-6 * std::max(std::abs(*bound), 1e-9);
  };
  if (at(parameter.upper) || at(parameter.lower)) {
    const bool focus = p.quantity == "distance" && at(parameter.upper);
    return "ends at a bound of the model (" + ShowValue(p.quantity, p.value) +
           (focus ? ": the focal length, where its image is at infinity, 0 D" : "") + ")";
  }
  const bool length = p.quantity == "distance" || p.quantity == "focal_length" || p.quantity == "gap";
  if (length && p.std_dev && *p.std_dev > kUndeterminedStdDevFraction * std::abs(p.value))
    return "has a standard deviation of " + ShowValue(p.quantity, *p.std_dev) + ", more than " +
           FormatFixed(100 * kUndeterminedStdDevFraction, 0) + " % of its value (" + ShowValue(p.quantity, p.value) +
           ")";
  return "";
}

ScalarFitOptions ScalarFitOptionsOf(const CalibrationOptions& options) {
  ScalarFitOptions o;
  o.max_iterations = options.max_iterations;
  o.function_tolerance = options.function_tolerance;
  o.parameter_tolerance = options.parameter_tolerance;
  o.robust_noise = options.loss != RobustLoss::kNone;
  return o;
}

std::string UndeterminedWarning(const ScalarFit& fit, const UndeterminedParameter& u, const std::string& quantity) {
  std::vector<std::string> partners;
  for (int i : u.partners) partners.push_back(fit.parameter(i).name);
  return "the data do not determine " + fit.parameter(u.index).name + " (it trades off against " +
         JoinWords(partners, " and ") + " without changing any residual): it keeps its scene value (" +
         ShowValue(quantity, fit.parameter(u.index).start) + ")";
}

bool FitGeometry(const DisplaySystem& system, const Measurements& measurements, const CalibrationOptions& options,
                 CalibratedDisplay* display, CalibrationReport* report) {
  for (const VirtualLayer& l : system.layers)
    if (l.lenslets)
      throw Error("layer \"" + l.name +
                  "\" is seen through a lens array, which the geometry fit does not model (it would fit the array "
                  "as one lens)");
  return GeometryFitter(system, measurements, options, report).Fit(display);
}

}  // namespace layerlab
