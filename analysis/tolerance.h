// `layerlab tolerance`: what assembly tolerances do to a display, measured
// per layer on perturbed scenes (analysis/tolerance_model.h) against the
// nominal one (docs/optics.md, "Tolerances"):
//  - misregistration: where a ray of the eye lands on the panel, in the
//    panel's own pixels, perturbed against nominal, over a grid of pupil
//    points and directions across the layer's field, each channel (RMS, max);
//  - distortion at the field edge (systems/lens_aberrations.h; 0 for a layer
//    on the affine path, which has none);
//  - the PSNR of the nominal factorization shown on the perturbed display
//    (a ToleranceProbe), against the target.
// Then a sensitivity pass (each tolerance alone at + and - its limit, every
// element it applies to at once) and a Monte Carlo run of seeded samples.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "layerlab/analysis/tolerance_model.h"
#include "layerlab/framework/lightfield.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

// An eye ray: pupil point (m) and tan-direction.
struct EyeRay {
  double p_x = 0, p_y = 0, u_x = 0, u_y = 0;
};

// `pupils` x `pupils` points over the eyebox (its edges included) and
// `directions` x `directions` points across 90 % of the layer's field (as
// seen from each pupil point: u = U - D p).
std::vector<EyeRay> MisregistrationRays(const VirtualLayer& layer, const EyeModel& eye, int directions = 5,
                                        int pupils = 3);

struct Misregistration {
  double rms_px = 0, max_px = 0;           // panel pixels, over rays and channels
  std::array<double, 3> channel_rms_px{};  // per channel
  int rays = 0, lost = 0;                  // traced in both, lost in either
};

// Each ray traced exactly through both layers (of the same panel) per channel,
// its panel point in the panel's own grid (LayerSampler::PanelCoordinates), the distance between them.
Misregistration MeasureMisregistration(const VirtualLayer& nominal, const VirtualLayer& perturbed,
                                       const std::array<double, 3>& wavelengths_m, const std::vector<EyeRay>& rays);

// The nominal factorization and the target it is scored against, on a
// subset of the target's views; PSNR of any display of the same panels.
class ToleranceProbe {
 public:
  // `patterns` of `nominal`'s layers; keeps EveryNthView(target, stride).
  ToleranceProbe(const DisplaySystem& nominal, const Patterns& patterns, const LightField& target, int stride,
                 Sampling sampling);
  double PsnrDb(const DisplaySystem& system) const;
  const LightFieldGeometry& geometry() const { return views_.geometry; }

 private:
  std::vector<std::string> names_;
  Patterns patterns_;
  LightField views_;
  Sampling sampling_;
};

// A view-subset light field: every `stride`-th view of `lf` (rows and columns
// from 0), as a light field of its own over the eyebox those views span;
// stride 0 picks about 3 x 3 (6 of 13 x 13 views, 2 of 5 x 5). Throws
// layerlab::Error for a stride that would not keep the views symmetric.
LightField EveryNthView(const LightField& lf, int stride);

struct LayerResult {
  std::string layer;
  Misregistration misregistration;
  double distortion_percent = 0;
};

struct ToleranceResult {
  std::vector<LayerResult> layers;  // the nominal system's order
  double psnr_db = 0;               // NaN without a probe
  std::string error;                // a draw that would not compile or measure: why
};

ToleranceResult MeasureDraw(const ToleranceModel& model, const DisplaySystem& nominal, const ToleranceDraw& draw,
                            const ToleranceProbe* probe);

struct SensitivityRow {
  ToleranceKind kind = ToleranceKind::kGap;
  double limit = 0;
  ToleranceResult plus, minus;
};

struct ToleranceRun {
  ToleranceResult nominal;
  std::vector<SensitivityRow> sensitivity;  // one per tolerance with degrees of freedom
  std::vector<ToleranceDraw> draws;
  std::vector<ToleranceResult> samples;
};

struct ToleranceRunOptions {
  int samples = 20;
  uint64_t seed = 1;
};

// `progress(done, total, what)` after each evaluation.
ToleranceRun RunTolerance(const ToleranceModel& model, const DisplaySystem& nominal, const ToleranceRunOptions& options,
                          const ToleranceProbe* probe,
                          const std::function<void(size_t, size_t, const std::string&)>& progress = {});

// The largest RMS misregistration over layers (px) of a result; NaN for a failed one.
double WorstRmsPx(const ToleranceResult& r);
// Of the sensitivity rows, the one whose worse side moves the pixels most,
// and the one that costs most PSNR (-1 when none measured it).
int DominantByMisregistration(const ToleranceRun& run);
int DominantByPsnr(const ToleranceRun& run);

}  // namespace layerlab
