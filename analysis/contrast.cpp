#include "layerlab/analysis/contrast.h"

#include <omp.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iterator>
#include <map>
#include <memory>
#include <numbers>
#include <optional>

#include "layerlab/analysis/svg_plot.h"
#include "layerlab/eye/eye_description.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/option_table.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/units.h"
#include "layerlab/framework/version.h"
#include "layerlab/retina/eye_optics.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/retina/retina.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/systems/lc_response.h"
#include "layerlab/targets/plane_lightfield.h"

namespace layerlab {
namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Luminance along the central retinal row, for the Fourier amplitude.
std::vector<double> CentralRow(const Image& image) {
  std::vector<double> row(image.width);
  int i = image.height / 2;
  for (int j = 0; j < image.width; ++j)
    for (int c = 0; c < 3; ++c) row[j] += kLuminanceWeights[c] * image.at(i, j, c);
  return row;
}

// Two eyes that see alike (the parts the retinal images read).
bool SameEye(const EyeModel& a, const EyeModel& b) {
  return EyeModelLine(a) == EyeModelLine(b) && a.pupil_diameter_m == b.pupil_diameter_m &&
         a.pupil_samples_x == b.pupil_samples_x && a.pupil_samples_y == b.pupil_samples_y &&
         a.pupil_sampling == b.pupil_sampling && a.pupil_seed == b.pupil_seed &&
         a.wavefront.coefficients_m == b.wavefront.coefficients_m &&
         a.chromatic_defocus_diopters == b.chromatic_defocus_diopters &&
         a.channel_wavelengths_m == b.channel_wavelengths_m;
}

bool IsNatural(const ContrastCurve& c) { return c.display.rfind("natural", 0) == 0; }

double Interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
  for (size_t k = 1; k < x.size(); ++k)
    if (at <= x[k] + 1e-12) {
      double f = (at - x[k - 1]) / (x[k] - x[k - 1]);
      return y[k - 1] + std::clamp(f, 0.0, 1.0) * (y[k] - y[k - 1]);
    }
  return y.back();
}

// The retinal window outside the display's horizontal field, which the target
// strip covers: "field_center: value: why", else "". At the centre the window
// is not checked, as before the option (a display narrower than the window shows its dark surround).
std::string WindowOutsideField(const ContrastDisplay& d, const ContrastOptions& o) {
  const double edge = 0.5 * d.system.fov_x_rad / kRadiansPerDegree;
  const double left = o.field_center_deg - 0.5 * o.retina_field_deg,
               right = o.field_center_deg + 0.5 * o.retina_field_deg;
  if (o.field_center_deg == 0 || (left >= -edge && right <= edge)) return "";
  return OptionViolation("field_center", o.field_center_deg,
                         "the retinal window, " + FormatFixed(left, 2) + " to " + FormatFixed(right, 2) +
                             " deg (field_center +- retina_field / 2), leaves the field of " + d.name + ", " +
                             FormatFixed(-edge, 2) + " to " + FormatFixed(edge, 2) +
                             " deg, which its target strip covers");
}

// Why `a`'s patterns cannot be shown on `b`'s layers, or "".
std::string UnlikeLayers(const ContrastDisplay& a, const ContrastDisplay& b) {
  const size_t layers = a.system.layers.size();
  if (layers != b.system.layers.size())
    return std::to_string(layers) + " layers against " + std::to_string(b.system.layers.size());
  if (a.system.subframes != b.system.subframes)
    return std::to_string(a.system.subframes) + " subframes against " + std::to_string(b.system.subframes);
  for (size_t k = 0; k < a.system.layers.size(); ++k) {
    const VirtualLayer &x = a.system.layers[k], &y = b.system.layers[k];
    if (x.cols != y.cols || x.rows != y.rows)
      return "layer " + std::to_string(k) + " (" + x.name + ") has " + std::to_string(x.cols) + " x " +
             std::to_string(x.rows) + " pixels against " + std::to_string(y.cols) + " x " + std::to_string(y.rows) +
             " (" + y.name + ")";
  }
  return "";
}

// A curve's light field: the display's at D_t, cut to `rows` rows around
// the axis (the grating is vertical).
LightFieldGeometry StripGeometry(const DisplaySystem& system, double dt, int rows) {
  LightFieldGeometry g = DisplayLightFieldGeometry(system, dt);
  double row_height = g.window_height_m / g.rows;
  g.rows = std::min(g.rows, rows);
  g.window_height_m = g.rows * row_height;
  g.window_top_m = g.window_height_m / 2;
  return g;
}

// Amplitudes over the accommodation range, on the retina and (for the
// uncertainty) on the shifted retina, of several curves seen by one eye:
// images(focus) makes what a state shares (a display's retinal tables), and
// what it returns the image of curve n on grids[g] (0 the retina, 1 the shifted one).
using RetinalImage = std::function<Image(int grid, const std::array<double, 3>&)>;
using CurveImage = std::function<Image(size_t curve, int grid)>;
using StateImages = std::function<CurveImage(const std::array<double, 3>& focus)>;

// The eye's optics on the retina and the shifted retina (nullptr without the peaks' uncertainty).
using GridOptics = std::array<const EyeOptics*, 2>;

// What natural viewing of `scene` puts on the retina of the eye of `optics`.
RetinalImage NaturalImage(const SceneRadiance& scene, const GridOptics& optics) {
  return [scene, optics](int grid, const std::array<double, 3>& focus) {
    return optics[grid]->See([&](const RetinaGrid& traced, const std::vector<PupilPoint>& group) {
      return RetinaOfScene(scene, traced, group, focus);
    });
  };
}

// Natural viewing curves already drawn, per target, by what they saw.
struct DrawnNatural {
  LightFieldGeometry geometry;
  Sampling sampling;
  const EyeModel* eye;
};

// A factorization: the patterns solved on one display for one target (its
// model, and what renders the target again).
struct CurveSolve {
  const ContrastDisplay* display;
  std::string label, solver;
  std::shared_ptr<const Texture> texture;
  std::unique_ptr<DisplayModel> model;
  Patterns t;
  double psnr_db = 0, seconds = 0;
};

// A display curve: the patterns of solves_[patterns] seen through display
// `display`, whose layers solves_[model]'s model (its own solve's) reads;
// the two are one solve but for a curve factorized for another display.
struct CurveView {
  size_t display, target, index;  // of_target[target][index]
  size_t model, patterns;
  size_t seer = kOwnEye;  // the display's eye, or moved_[seer]
  static constexpr size_t kOwnEye = size_t(-1);
};

// A display's eye with its pupil moved across the eyebox (ContrastOptions::eyebox_range_m).
struct MovedEye {
  size_t display;
  std::array<double, 2> moved_m;
  EyeModel eye;
  std::vector<PupilPoint> pupil;
};

// The eye that sees the curve; a binocular one verges on the target, on the midline at its depth.
void SetEye(ContrastCurve* c, const EyeModel& eye) {
  c->eye = EyeModelLine(eye);
  if (!eye.binocular) return;
  Binocular fixating = *eye.binocular;
  fixating.fixation_m = {0, 0, 1 / c->target_diopters};
  c->vergence_diopters = VergenceDiopters(fixating);
}

std::string SolverOf(const ContrastDisplay& d) { return d.solver.empty() ? DefaultSolverFor(d.system) : d.solver; }

std::string TargetLabel(double dt, double f) {
  char label[96];
  std::snprintf(label, sizeof label, "target %.2f D, %.1f cpd", dt, f);
  return label;
}

// One contrast run: the curves planned target by target (natural viewing
// where first seen, then each display's), every factorization solved, each
// display's curves swept together, then their peaks.
class ContrastRun {
 public:
  ContrastRun(const std::vector<ContrastDisplay>& displays, const ContrastOptions& o, const ContrastDisplay* foreign)
      : displays_(displays),
        o_(o),
        foreign_(foreign),
        // Each display is seen by its own scene's eye (an "auto" pupil follows its luminance);
        // the continuous plane by the first display's.
        first_eye_(displays.front().system.eye) {
    for (int k = 0;; ++k) {
      double a = o.accommodation_min_diopters + k * o.accommodation_step_diopters;
      if (a > o.accommodation_max_diopters + 1e-9) break;
      accommodation_.push_back(a);
    }
    for (const ContrastDisplay& d : displays) pupils_.push_back(PupilSamples(d.system.eye));
    for (size_t di = 0; di < displays.size(); ++di)
      for (const std::array<double, 2>& m : EyeboxGridOffsets(o.eyebox_range_m, o.eyebox_step_m)) {
        if (m[0] == 0 && m[1] == 0) continue;  // the eye's own curves
        EyeModel eye = displays[di].system.eye;
        eye.pose = WithPupilMoved(eye.pose, m[0], m[1]);
        moved_.push_back({di, m, eye, PupilSamples(eye)});
      }
    retina_ = MakeRetinaGrid(o.retina_field_deg * kRadiansPerDegree, 3 * o.retina_resolution_deg * kRadiansPerDegree,
                             o.retina_resolution_deg * kRadiansPerDegree);
    retina_.center_x_rad = o.field_center_deg * kRadiansPerDegree;
    shifted_ = retina_;
    shifted_.center_x_rad += 0.5 * retina_.resolution_rad;  // for the peaks' sampling uncertainty
    grids_[0] = retina_, grids_[1] = shifted_;
    texture_of_ = o.texture ? o.texture : CosineGrating(0.5, 1.0, o.grating);
    convention_ = ConventionLabel(o.reference, o.grating);
    reference_ = o.reference;
  }

  std::vector<ContrastCurve> Run() {
    PlanCurves();
    SolveCurves();
    for (size_t di = 0; di < displays_.size(); ++di) SweepDisplay(di, CurveView::kOwnEye);
    for (size_t m = 0; m < moved_.size(); ++m) SweepDisplay(moved_[m].display, m);
    std::vector<ContrastCurve> curves;
    for (std::vector<ContrastCurve>& of : of_target_)
      for (ContrastCurve& c : of) curves.push_back(std::move(c));
    for (ContrastCurve& c : curves) {
      c.peak = FindPeak(c.accommodation, c.contrast);
      c.estimate = EstimatePeak(c.accommodation, c.contrast, c.contrast_shifted, o_.flat_limit_diopters);
      c.at_target = Interpolate(c.accommodation, c.contrast, c.target_diopters);
    }
    if (progress_) progress_->Finish(std::to_string(curves.size()) + " curves");
    return curves;
  }

 private:
  double Amplitude(const Image& image, const RetinaGrid& grid, double f) const {
    std::vector<double> row = CentralRow(image), degrees(grid.cols);
    for (int j = 0; j < grid.cols; ++j) degrees[j] = grid.angle_x(j) / kRadiansPerDegree;
    int n = WholeCycleSamples(grid.cols, o_.retina_resolution_deg, f);
    int start = (grid.cols - n) / 2;
    return FourierAmplitude(std::vector<double>(row.begin() + start, row.begin() + start + n),
                            std::vector<double>(degrees.begin() + start, degrees.begin() + start + n), f);
  }

  // The states one per thread: a retinal image of 3 rows leaves a second
  // thread little of its own to do, and serial set-up (its tables and
  // views) keeps it waiting. Inside the loop an image is made on one
  // thread, the same values as made alone.
  void Sweep(const EyeModel& eye, const StateImages& images, const std::vector<ContrastCurve*>& of) const {
    const int states = static_cast<int>(accommodation_.size());
    for (ContrastCurve* curve : of) {
      curve->contrast.assign(states, 0.0);
      if (o_.peak_uncertainty) curve->contrast_shifted.assign(states, 0.0);
    }
    std::exception_ptr error;
#pragma omp parallel for schedule(dynamic)
    for (int k = 0; k < states; ++k) {
      try {
        const CurveImage image = images(ChannelAccommodation(eye, accommodation_[k]));
        for (size_t n = 0; n < of.size(); ++n) {
          ContrastCurve& c = *of[n];
          c.contrast[k] = Amplitude(image(n, 0), retina_, c.frequency) / c.reference_amplitude;
          if (o_.peak_uncertainty)
            c.contrast_shifted[k] = Amplitude(image(n, 1), shifted_, c.frequency) / c.reference_amplitude;
        }
      } catch (...) {
#pragma omp critical(contrast_sweep_error)
        if (!error) error = std::current_exception();
      }
    }
    if (error) std::rethrow_exception(error);
  }

  void SweepOne(const EyeModel& eye, const RetinalImage& natural, ContrastCurve* curve) const {
    Sweep(eye,
          [&](const std::array<double, 3>& focus) -> CurveImage {
            return [&natural, focus](size_t, int grid) { return natural(grid, focus); };
          },
          {curve});
  }

  // The optics of the eye whose samples are `pupil`, on both grids, made once
  // per eye (outside the parallel sweeps). The grating is vertical: the strips are uniform along y.
  GridOptics Optics(const EyeModel& eye, const std::vector<PupilPoint>& pupil) {
    GridOptics optics{};
    for (int g = 0; g < (o_.peak_uncertainty ? 2 : 1); ++g) {
      std::unique_ptr<EyeOptics>& made = optics_[{&pupil, g}];
      if (!made) made = std::make_unique<EyeOptics>(eye, pupil, grids_[g], RowEdges::kUniform);
      optics[g] = made.get();
    }
    return optics;
  }

  ContrastCurve Blank(const std::string& name, double dt, double f) const {
    ContrastCurve c;
    c.display = name, c.target_diopters = dt, c.frequency = f, c.accommodation = accommodation_,
    c.convention = convention_;
    c.reference = reference_;
    return c;
  }

  double ReferenceAmplitude(const EyeModel& seer, const RetinalImage& natural, double dt, double f,
                            const std::string& label) const {
    double r = Amplitude(natural(0, ChannelAccommodation(seer, dt)), retina_, f);
    if (!(r > 0)) throw Error("contrast: the target has no component at " + label);
    return r;
  }

  // The curves of each target (frequency, depth), in order: natural viewing
  // where first seen, then each display's. Display by display, since a
  // display's retinal tables at a state serve all of its curves: its curves
  // are solved, then swept together.
  void PlanCurves() {
    const size_t depths = o_.target_diopters.size();
    of_target_.resize(o_.frequencies_cpd.size() * depths);
    drawn_.resize(of_target_.size());
    continuous_reference_.assign(of_target_.size(), 0.0);
    if (o_.show_progress) progress_.emplace("contrast", (displays_.size() + (foreign_ ? 1 : 0)) * of_target_.size());
    if (foreign_)  // its patterns for each target, shown through every display
      for (size_t fi = 0; fi < o_.frequencies_cpd.size(); ++fi)
        for (size_t ti = 0; ti < depths; ++ti) {
          const double f = o_.frequencies_cpd[fi], dt = o_.target_diopters[ti];
          foreign_solves_.push_back(PlanSolve(*foreign_, texture_of_(1 / dt, f), TargetLabel(dt, f), dt));
        }
    for (size_t di = 0; di < displays_.size(); ++di)
      for (size_t fi = 0; fi < o_.frequencies_cpd.size(); ++fi)
        for (size_t ti = 0; ti < depths; ++ti)
          PlanCurve(di, fi * depths + ti, o_.frequencies_cpd[fi], o_.target_diopters[ti]);
  }

  void PlanCurve(size_t di, size_t target_index, double f, double dt) {
    const ContrastDisplay& d = displays_[di];
    std::vector<ContrastCurve>& curves = of_target_[target_index];
    std::shared_ptr<const Texture> texture = texture_of_(1 / dt, f);
    const std::string label = TargetLabel(dt, f);
    if (o_.reference == ContrastReference::kContinuous && di == 0) {
      // The continuous plane at D_t as the eye sees it.
      SceneRadiance plane = [&](const PupilPoint& u, double dx, double dy) {
        return texture->Evaluate(u.x_m + dx / dt, u.y_m + dy / dt);
      };
      auto start = std::chrono::steady_clock::now();
      RetinalImage natural = NaturalImage(plane, Optics(first_eye_, pupils_.front()));
      continuous_reference_[target_index] = ReferenceAmplitude(first_eye_, natural, dt, f, label);
      ContrastCurve c = Blank("natural", dt, f);
      c.solver = "-";
      SetEye(&c, first_eye_);
      c.reference_amplitude = continuous_reference_[target_index];
      SweepOne(first_eye_, natural, &c);
      c.sweep_seconds = Seconds(start);
      curves.push_back(std::move(c));
    }

    double reference = continuous_reference_[target_index];
    if (o_.reference == ContrastReference::kSampledTarget)
      reference =
          DrawSampledNatural(di, target_index, StripGeometry(d.system, dt, o_.strip_rows), *texture, f, dt, label);
    const size_t own = PlanSolve(d, texture, label, dt);
    ContrastCurve curve = Blank(d.name, dt, f);
    curve.reference_amplitude = reference;  // a curve factorized for another display is normalized as its own
    AddCurve(di, target_index, curve, own, own);
    for (size_t m = 0; m < moved_.size(); ++m)
      if (moved_[m].display == di) {
        ContrastCurve seen = curve;
        seen.display = MovedPupilName(d.name, moved_[m].moved_m);
        seen.pupil_moved = true, seen.pupil_moved_m = moved_[m].moved_m;
        AddCurve(di, target_index, seen, own, own, m);
      }
    if (foreign_) {
      curve.display = FactorizedForName(d.name, foreign_->name);
      AddCurve(di, target_index, curve, own, foreign_solves_[target_index]);
    }
  }

  // The factorization of `d` for the target at dt; its index in solves_.
  size_t PlanSolve(const ContrastDisplay& d, std::shared_ptr<const Texture> texture, const std::string& label,
                   double dt) {
    auto model = std::make_unique<DisplayModel>(d.system, StripGeometry(d.system, dt, o_.strip_rows), d.sampling);
    solves_.push_back({&d, label, SolverOf(d), std::move(texture), std::move(model), {}});
    return solves_.size() - 1;
  }

  // Display di's curve of solves_[patterns] seen through it (its layers read by solves_[model]'s model), by its
  // eye or moved_[seer].
  void AddCurve(size_t di, size_t target_index, ContrastCurve curve, size_t model, size_t patterns,
                size_t seer = CurveView::kOwnEye) {
    const CurveSolve& s = solves_[patterns];
    curve.scene = displays_[di].name;
    SetEye(&curve, seer == CurveView::kOwnEye ? displays_[di].system.eye : moved_[seer].eye);
    curve.solver = s.solver;
    if (patterns != model) curve.factorized_for = s.display->name;
    of_target_[target_index].push_back(std::move(curve));
    views_.push_back({di, target_index, of_target_[target_index].size() - 1, model, patterns, seer});
  }

  // The reference amplitude of natural viewing of the display's sampled
  // target; its curve is drawn once per distinct target, named after the
  // display when it is not the first.
  double DrawSampledNatural(size_t di, size_t target_index, const LightFieldGeometry& g, const Texture& texture,
                            double f, double dt, const std::string& label) {
    const ContrastDisplay& d = displays_[di];
    const EyeModel& eye = d.system.eye;
    std::vector<DrawnNatural>& drawn = drawn_[target_index];
    auto start = std::chrono::steady_clock::now();
    LightField target = RenderPlaneLightField(g, g.origin_z_m, texture);  // the plane is the origin plane
    RetinalImage natural = NaturalImage(LightFieldRadiance(target, d.sampling), Optics(eye, pupils_[di]));
    const double reference = ReferenceAmplitude(eye, natural, dt, f, label);
    bool seen = std::any_of(drawn.begin(), drawn.end(), [&](const DrawnNatural& k) {
      return k.sampling == d.sampling && k.geometry == g && SameEye(*k.eye, eye);
    });
    if (!seen) {
      ContrastCurve c = Blank(drawn.empty() ? "natural" : "natural (" + d.name + ")", dt, f);
      c.solver = "-";
      SetEye(&c, eye);
      c.reference_amplitude = reference;
      SweepOne(eye, natural, &c);
      c.sweep_seconds = Seconds(start);
      of_target_[target_index].push_back(std::move(c));
      drawn.push_back({g, d.sampling, &eye});
    }
    return reference;
  }

  // Every factorization, one per thread: on a target of a few
  // thousand rays per view a solve's passes leave a second thread waiting
  // at each barrier (26.6 s on one thread, 17.8 s on two for the default
  // sweep, 2026-12-03). Each solve runs alone on its thread, so a curve has
  // the bits of a one-thread solve on any machine. Its target is rendered
  // again there (a few ms) rather than kept from above for every curve.
  void SolveCurves() {
    std::exception_ptr error;
    size_t error_at = solves_.size(), started = 0;
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t n = 0; n < solves_.size(); ++n) {
      CurveSolve& s = solves_[n];
      const ContrastDisplay& d = *s.display;
#pragma omp critical(contrast_solve_progress)
      {
        if (o_.progress) o_.progress(d.name + ": " + s.label);
        if (progress_) progress_->Update(started++, "solves; now " + d.name + ": " + s.label);
      }
      try {
        omp_set_num_threads(1);  // the solve's own parallel regions, on this thread only
        SolveCurve(&s);
      } catch (...) {
#pragma omp critical(contrast_solve_error)
        if (n < error_at) error = std::current_exception(), error_at = n;  // the first in solve order
      }
    }
    if (error) std::rethrow_exception(error);
    for (const CurveView& v : views_) {
      ContrastCurve& curve = of_target_[v.target][v.index];
      curve.solve_seconds = solves_[v.patterns].seconds;
      curve.psnr_db = solves_[v.patterns].psnr_db;  // on the display it was solved for
    }
  }

  void SolveCurve(CurveSolve* s) {
    const ContrastDisplay& d = *s->display;
    const LightFieldGeometry& g = s->model->geometry();
    LightField target = RenderPlaneLightField(g, g.origin_z_m, *s->texture);
    SolverOptions options = d.options_given ? d.options : SolverRegistry::Builtins().find(s->solver)->defaults;
    options.retinal.target = RetinalTarget::kLightField;  // the grating's light field is its scene, exactly
    auto start = std::chrono::steady_clock::now();
    SolverReport report = SolverRegistry::Builtins().create(s->solver)->Solve(*s->model, target, options, &s->t);
    if (!report.IsSolutionUsable()) throw Error("contrast: " + d.name + ": " + report.message);
    s->seconds = Seconds(start);
    s->psnr_db = report.final_psnr_db;
  }

  // The display's curves seen by one eye (its own, or moved_[seer]) swept together; each is given an equal
  // share of the time.
  void SweepDisplay(size_t di, size_t seer) {
    std::vector<const CurveView*> of_display;
    std::vector<ContrastCurve*> of;
    for (const CurveView& v : views_)
      if (v.display == di && v.seer == seer) of_display.push_back(&v), of.push_back(&of_target_[v.target][v.index]);
    if (of_display.empty()) return;
    const bool own = seer == CurveView::kOwnEye;
    const EyeModel& eye = own ? displays_[di].system.eye : moved_[seer].eye;
    const std::vector<PupilPoint>& pupil = own ? pupils_[di] : moved_[seer].pupil;
    const auto start = std::chrono::steady_clock::now();
    const GridOptics optics = Optics(eye, pupil);
    // Each curve's patterns as this display's panels show them over a frame (their response), each instant
    // as the panels diffract it, once.
    std::vector<std::vector<ShownInstant>> seen;
    for (const CurveView* v : of_display) seen.push_back(SeenOverTime(displays_[di].system, solves_[v->patterns].t));
    Sweep(
        eye,
        [&](const std::array<double, 3>& focus) -> CurveImage {
          // Every model of the display reads the same layers; tables per grid and pupil group.
          const DisplayModel& model = *solves_[of_display.front()->model].model;
          auto tables = std::make_shared<std::vector<std::vector<DisplayRetinaTables>>>();
          for (int g = 0; g < (o_.peak_uncertainty ? 2 : 1); ++g) {
            tables->emplace_back();
            for (size_t k = 0; k < optics[g]->groups(); ++k)
              tables->back().emplace_back(model, optics[g]->traced(), optics[g]->group(k), focus);
          }
          return [&, tables](size_t n, int grid) {
            const CurveView& v = *of_display[n];
            std::vector<Image> images;
            for (const DisplayRetinaTables& of_group : (*tables)[grid])
              images.push_back(RetinaOfDisplay(*solves_[v.model].model, seen[n], of_group));
            return optics[grid]->Combine(images);
          };
        },
        of);
    const double seconds = Seconds(start) / of.size();
    for (ContrastCurve* c : of) c->sweep_seconds = seconds;
  }

  const std::vector<ContrastDisplay>& displays_;
  const ContrastOptions& o_;
  const ContrastDisplay* foreign_;  // factorized_for, or nullptr
  const EyeModel& first_eye_;
  std::vector<double> accommodation_;
  std::vector<std::vector<PupilPoint>> pupils_;
  std::vector<MovedEye> moved_;
  RetinaGrid retina_, shifted_;
  RetinaGrid grids_[2];
  std::map<std::pair<const std::vector<PupilPoint>*, int>, std::unique_ptr<EyeOptics>> optics_;
  PlaneTextureFactory texture_of_;
  std::string convention_;
  ContrastReference reference_ = ContrastReference::kSampledTarget;

  std::vector<std::vector<ContrastCurve>> of_target_;
  std::vector<std::vector<DrawnNatural>> drawn_;
  std::vector<double> continuous_reference_;
  std::optional<Progress> progress_;
  std::vector<CurveSolve> solves_;
  std::vector<size_t> foreign_solves_;  // per target: foreign_'s factorization in solves_
  std::vector<CurveView> views_;
};

}  // namespace

PlaneTextureFactory CosineGrating(double mean, double contrast, GratingSpacing spacing) {
  return [=](double depth, double cpd) -> std::shared_ptr<const Texture> {
    GratingSpec spec;
    spec.cycles_per_meter = cpd / (depth * kRadiansPerDegree);  // at the line of sight
    spec.angle_depth_m = spacing == GratingSpacing::kVisualAngle ? depth : 0;
    spec.mean = mean;
    spec.contrast = contrast;
    return MakeGratingTexture(spec);
  };
}

std::string ConventionLabel(ContrastReference reference, GratingSpacing spacing) {
  std::string r = reference == ContrastReference::kSampledTarget
                      ? "reference: natural viewing of the sampled target light field, pixels read as the layers are"
                      : "reference: natural viewing of the continuous plane";
  return r + (spacing == GratingSpacing::kVisualAngle ? "; grating uniform in visual angle"
                                                      : "; grating uniform on the plane (meters)");
}

ContrastDisplay LoadContrastDisplay(const std::string& scene_file) {
  return ContrastDisplayOf(LoadScene(scene_file), scene_file);
}

ContrastDisplay ContrastDisplayOf(const Scene& scene, const std::string& scene_file) {
  ContrastDisplay d;
  d.system = Compile(scene);
  d.name = std::filesystem::path(scene_file).stem().string();
  if (scene.document.contains("solve")) {
    SolveConfig config = ReadSolveConfig(scene, d.system);
    d.solver = config.solver;
    d.options = config.options;
    d.options_given = true;
    d.sampling = config.sampling;
  }
  return d;
}

std::vector<std::string> ContrastWarnings(const std::vector<ContrastDisplay>& displays, const ContrastOptions& o) {
  std::vector<std::string> warnings;
  for (const ContrastDisplay& d : displays)
    for (double f : o.frequencies_cpd)
      if (f > d.system.max_cpd)
        warnings.push_back(d.name + ": " + FormatFixed(f, 2) + " cpd is above the " + FormatFixed(d.system.max_cpd, 2) +
                           " cpd the display can show (its finest layer's Nyquist frequency); the curve at " +
                           FormatFixed(f, 2) + " cpd measures aliasing, not the display's contrast");
  return warnings;
}

std::vector<ContrastCurve> RunContrast(const std::vector<ContrastDisplay>& displays, const ContrastOptions& o,
                                       const ContrastDisplay* factorized_for) {
  if (displays.empty()) throw Error("contrast: no display given");
  if (std::string why; !o.IsValid(&why)) throw Error("contrast: " + why);
  if (std::string why = ContrastDisplayProblem(displays, o, factorized_for); !why.empty())
    throw Error("contrast: " + why);
  return ContrastRun(displays, o, factorized_for).Run();
}

std::string MovedPupilName(const std::string& display, const std::array<double, 2>& moved_m) {
  char text[64];
  std::snprintf(text, sizeof text, " (pupil %+.2f %+.2f mm)", moved_m[0] * 1e3, moved_m[1] * 1e3);
  return display + text;
}

std::string FactorizedForName(const std::string& display, const std::string& other) {
  return display + " (factorized for " + other + ")";
}

std::string ContrastDisplayProblem(const std::vector<ContrastDisplay>& displays, const ContrastOptions& o,
                                   const ContrastDisplay* factorized_for) {
  std::vector<const ContrastDisplay*> all;
  for (const ContrastDisplay& d : displays) all.push_back(&d);
  if (factorized_for) all.push_back(factorized_for);
  for (const ContrastDisplay* d : all)
    if (std::string why = WindowOutsideField(*d, o); !why.empty()) return why;
  if (factorized_for)
    for (const ContrastDisplay& d : displays)
      if (std::string why = UnlikeLayers(*factorized_for, d); !why.empty())
        return "factorized_for: " + factorized_for->name + ": its patterns cannot be shown on " + d.name + ": " + why;
  return "";
}

std::string ContrastCsv(const std::vector<ContrastCurve>& curves) {
  std::string csv =
      "display,target_D,frequency_cpd,accommodation_D,normalized_contrast,normalized_contrast_half_sample_shift\n";
  char line[256];
  for (const ContrastCurve& c : curves)
    for (size_t k = 0; k < c.accommodation.size(); ++k) {
      std::snprintf(line, sizeof line, "%s,%.4f,%.4f,%.4f,%.6f,", c.display.c_str(), c.target_diopters, c.frequency,
                    c.accommodation[k], c.contrast[k]);
      csv += line;
      if (k < c.contrast_shifted.size()) {
        std::snprintf(line, sizeof line, "%.6f", c.contrast_shifted[k]);
        csv += line;
      }
      csv += "\n";
    }
  return csv;
}

std::string AboveOneNote(const std::vector<ContrastCurve>& curves) {
  const ContrastCurve* top = nullptr;
  for (const ContrastCurve& c : curves)
    if (!IsNatural(c) && c.peak.value > 1 && (!top || c.peak.value > top->peak.value)) top = &c;
  if (!top) return "";
  char what[160];
  std::snprintf(what, sizeof what, "%s: %.3f at %.2f D, %.1f cpd", top->display.c_str(), top->peak.value,
                top->target_diopters, top->frequency);
  if (top->reference == ContrastReference::kContinuous) {
    char why[200];
    std::snprintf(why, sizeof why,
                  "its retinal amplitude exceeds the grating's by %.1f %%, against a light-field error of %.1f %% rms "
                  "(PSNR %.2f dB)",
                  100 * (top->peak.value - 1), 100 * std::pow(10.0, -top->psnr_db / 20), top->psnr_db);
    return std::string("A normalized contrast above 1 (") + what + ") against the continuous grating: " + why + ".";
  }
  const ContrastCurve* natural = nullptr;
  for (const ContrastCurve& c : curves)
    if (IsNatural(c) && c.target_diopters == top->target_diopters && c.frequency == top->frequency) natural = &c;
  char kept[120] = "";
  if (natural)
    std::snprintf(kept, sizeof kept, " (here natural viewing's amplitude in focus is %.4f; the default grating's: 0.5)",
                  natural->reference_amplitude);
  return std::string("A normalized contrast above 1 (") + what +
         ") is not more contrast than the grating has. The reference, natural viewing of the sampled target light "
         "field, reads the light field's pixels on the grating's own plane, where the eye focuses, and so loses their "
         "hold, sinc(f p) for pixels of p degrees" +
         kept +
         "; the display forms the grating from layers off that plane, whose pixels the eye sees out of focus, and "
         "loses less. --reference continuous divides by the grating itself (docs/accommodation.md).";
}

std::string PeakTable(const std::vector<ContrastCurve>& curves) {
  std::string out;
  out += "# " + VersionLine() + "\n";
  if (!curves.empty()) out += "# " + curves.front().convention + "\n";
  std::vector<std::string> eyes;  // each eye once, in order
  for (const ContrastCurve& c : curves)
    if (std::find(eyes.begin(), eyes.end(), c.eye) == eyes.end()) eyes.push_back(c.eye);
  for (const std::string& eye : eyes) {
    std::string seen_by;
    if (eyes.size() > 1)
      for (const ContrastCurve& c : curves)
        if (c.eye == eye && !IsNatural(c) && seen_by.find(" " + c.display + ",") == std::string::npos)
          seen_by += " " + c.display + ",";
    out += "# eye" + (seen_by.empty() ? "" : " of" + seen_by.substr(0, seen_by.size() - 1)) + ": " + eye + "\n";
  }
  // What the normalization divides by: natural viewing focused at the target.
  for (const ContrastCurve& c : curves)
    if (IsNatural(c)) {
      char line[200];
      std::snprintf(line, sizeof line,
                    "# %s at %.2f D, %.1f cpd: amplitude in focus %.4f (the default grating's: 0.5)\n",
                    c.display.c_str(), c.target_diopters, c.frequency, c.reference_amplitude);
      out += line;
    }
  if (const std::string note = AboveOneNote(curves); !note.empty()) out += "# " + note + "\n";
  int width = 24;  // the display column: as wide as its longest name
  for (const ContrastCurve& c : curves) width = std::max(width, static_cast<int>(c.display.size()));
  // A binocular eye's conflict: its vergence on the target less its accommodation response (the curve's peak).
  const bool binocular = std::any_of(curves.begin(), curves.end(),
                                     [](const ContrastCurve& c) { return !std::isnan(c.vergence_diopters); });
  if (binocular)
    out +=
        "# VAC (D): the vergence demand of the target (binocular eye, fixating it) less the accommodation "
        "response, the parabola's peak; '-' where the curve is too flat to place one\n";
  out += "display" + std::string(width - 6, ' ') +
         "target (D)  f (cpd)  peak (D)  parabola (D)  +- (D)  placed  peak contrast  at target  "
         "solver                 PSNR (dB)  solve (s)  sweep (s)" +
         (binocular ? "  vergence (D)  VAC (D)" : "") + "\n";
  std::vector<char> line(width + 320);
  for (const ContrastCurve& c : curves) {
    std::snprintf(line.data(), line.size(),
                  "%-*s %10.2f %8.1f %9.2f %13.3f %7s  %-6s %14.3f %10.3f  %-22s %9.2f %10.3f %10.3f", width,
                  c.display.c_str(), c.target_diopters, c.frequency, c.peak.at_grid, c.estimate.at,
                  c.contrast_shifted.empty() ? "n/a" : FormatFixed(c.estimate.uncertainty, 3).c_str(),
                  c.estimate.flat ? "flat" : "yes", c.peak.value, c.at_target, c.solver.c_str(), c.psnr_db,
                  c.solve_seconds, c.sweep_seconds);
    out += line.data();
    if (binocular && !std::isnan(c.vergence_diopters)) {
      std::snprintf(line.data(), line.size(), " %13.3f", c.vergence_diopters);
      out += line.data();
      if (c.estimate.flat) {
        out += "        -";
      } else {
        std::snprintf(line.data(), line.size(), " %8.3f", c.vergence_diopters - c.estimate.at);
        out += line.data();
      }
    }
    out += "\n";
  }
  return out;
}

nlohmann::json PeaksJson(const std::vector<ContrastCurve>& curves) {
  nlohmann::json rows = nlohmann::json::array();
  for (const ContrastCurve& c : curves) {
    const bool vac = !std::isnan(c.vergence_diopters) && !c.estimate.flat;
    rows.push_back(
        {{"display", c.display},
         {"target_diopters", c.target_diopters},
         {"frequency_cpd", c.frequency},
         {"peak_diopters", c.peak.at_grid},
         {"parabola_peak_diopters", c.estimate.at},
         {"peak_uncertainty_diopters",
          c.contrast_shifted.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.estimate.uncertainty)},
         {"flat", c.estimate.flat},
         {"peak_contrast", c.peak.value},
         {"contrast_at_target", c.at_target},
         {"solver", c.solver},
         {"psnr_db", c.psnr_db},
         {"solve_seconds", c.solve_seconds},
         {"sweep_seconds", c.sweep_seconds},
         {"vac_diopters", vac ? nlohmann::json(c.vergence_diopters - c.estimate.at) : nlohmann::json(nullptr)}});
  }
  return rows;
}

std::string ContrastSvg(const std::vector<ContrastCurve>& all) {
  static const char* kColors[] = {"#d62728", "#1f77b4", "#ff7f0e", "#9467bd", "#2ca02c", "#8c564b", "#e377c2"};
  // The curves from the eyebox's other pupil positions are drawn by ContrastEyeboxSvg, as their peaks.
  std::vector<ContrastCurve> curves;
  std::copy_if(all.begin(), all.end(), std::back_inserter(curves),
               [](const ContrastCurve& c) { return !c.pupil_moved; });
  std::vector<double> frequencies, depths;
  std::vector<std::string> displays;
  for (const ContrastCurve& c : curves) {
    if (std::find(frequencies.begin(), frequencies.end(), c.frequency) == frequencies.end())
      frequencies.push_back(c.frequency);
    if (std::find(depths.begin(), depths.end(), c.target_diopters) == depths.end()) depths.push_back(c.target_diopters);
    if (!IsNatural(c) && std::find(displays.begin(), displays.end(), c.display) == displays.end())
      displays.push_back(c.display);
  }
  double y_max = 0.1;
  for (const ContrastCurve& c : curves)
    for (double v : c.contrast) y_max = std::max(y_max, v);
  std::vector<PlotPanel> panels;
  for (double f : frequencies)
    for (double dt : depths) {
      PlotPanel panel;
      char title[64];
      std::snprintf(title, sizeof title, "%.1f cpd, target at %.2f D", f, dt);
      panel.title = title;
      panel.x_label = "accommodation (D)";
      panel.y_label = "normalized contrast";
      panel.y_max = std::ceil(y_max * 10.5) / 10;
      panel.markers.push_back({dt});
      for (const ContrastCurve& c : curves) {
        if (c.frequency != f || c.target_diopters != dt) continue;
        panel.x_min = c.accommodation.front();
        panel.x_max = c.accommodation.back();
        size_t index = std::find(displays.begin(), displays.end(), c.display) - displays.begin();
        panel.lines.push_back(
            {c.display, IsNatural(c) ? "#000" : kColors[index % 7], IsNatural(c), c.accommodation, c.contrast});
      }
      panels.push_back(panel);
    }
  return RenderSvg(panels, static_cast<int>(depths.size()), "Normalized contrast against accommodation");
}

}  // namespace layerlab
