#include "layerlab/analysis/tolerance.h"

#include <cmath>
#include <limits>
#include <numeric>

#include "layerlab/solvers/objective.h"
#include "layerlab/systems/layer_ray_map.h"
#include "layerlab/systems/layer_sampler.h"
#include "layerlab/systems/lens_aberrations.h"

namespace layerlab {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double Spread(int k, int n) { return n == 1 ? 0.0 : -0.5 + double(k) / (n - 1); }

const VirtualLayer* Named(const DisplaySystem& s, const std::string& name) {
  for (const VirtualLayer& l : s.layers)
    if (l.name == name) return &l;
  return nullptr;
}

LayerResult MeasureLayer(const VirtualLayer& nominal, const DisplaySystem& system, const EyeModel& eye) {
  LayerResult out;
  out.layer = nominal.name;
  const VirtualLayer* perturbed = Named(system, nominal.name);
  if (!perturbed) throw Error("the perturbed display has no layer \"" + nominal.name + "\"");
  if (nominal.lenslets)
    throw Error("layer \"" + nominal.name +
                "\" is seen through a lens array, whose lenslets the tolerance analysis does not trace");
  out.misregistration =
      MeasureMisregistration(nominal, *perturbed, eye.channel_wavelengths_m, MisregistrationRays(nominal, eye));
  out.distortion_percent = 0;
  if (perturbed->ray_map) {
    try {
      out.distortion_percent = MeasureAberrations(*perturbed, system.eye.pupil_diameter_m).distortion_percent;
    } catch (const Error&) {
      out.distortion_percent = kNaN;  // the field edge's chief ray is lost in the perturbed lens
    }
  }
  return out;
}

}  // namespace

std::vector<EyeRay> MisregistrationRays(const VirtualLayer& l, const EyeModel& eye, int directions, int pupils) {
  std::vector<EyeRay> rays;
  for (int b = 0; b < pupils; ++b)
    for (int a = 0; a < pupils; ++a) {
      const double p_x = Spread(a, pupils) * eye.eyebox_width_m, p_y = Spread(b, pupils) * eye.eyebox_height_m;
      for (int i = 0; i < directions; ++i)
        for (int j = 0; j < directions; ++j) {
          const double U_x = l.eye_from_layer_tan_x + 0.9 * Spread(j, directions) * l.cols * l.tan_pitch_x;
          const double U_y = l.eye_from_layer_tan_y + 0.9 * Spread(i, directions) * l.rows * l.tan_pitch_y;
          rays.push_back({p_x, p_y, U_x - l.diopters * p_x, U_y - l.diopters * p_y});
        }
    }
  return rays;
}

Misregistration MeasureMisregistration(const VirtualLayer& nominal, const VirtualLayer& perturbed,
                                       const std::array<double, 3>& wavelengths_m, const std::vector<EyeRay>& rays) {
  const LayerRayMap before(nominal, wavelengths_m), after(perturbed, wavelengths_m);
  const LayerSampler grid_before(nominal, Sampling::kNearest), grid_after(perturbed, Sampling::kNearest);
  Misregistration m;
  double sum = 0;
  std::array<double, 3> channel_sum{};
  std::array<int, 3> channel_rays{};
  for (const EyeRay& r : rays)
    for (int c = 0; c < 3; ++c) {
      const auto A = before.Trace(c, r.p_x, r.p_y, r.u_x, r.u_y), B = after.Trace(c, r.p_x, r.p_y, r.u_x, r.u_y);
      if (!A || !B) {
        ++m.lost;
        continue;
      }
      const std::array<double, 2> a = grid_before.PanelCoordinates((*A)[0], (*A)[1]),
                                  b = grid_after.PanelCoordinates((*B)[0], (*B)[1]);
      const double d2 = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
      sum += d2, channel_sum[c] += d2, ++channel_rays[c], ++m.rays;
      m.max_px = std::max(m.max_px, std::sqrt(d2));
    }
  m.rms_px = m.rays ? std::sqrt(sum / m.rays) : kNaN;
  for (int c = 0; c < 3; ++c)
    m.channel_rms_px[c] = channel_rays[c] ? std::sqrt(channel_sum[c] / channel_rays[c]) : kNaN;
  return m;
}

LightField EveryNthView(const LightField& lf, int stride) {
  const LightFieldGeometry& g = lf.geometry;
  if (stride == 0) {  // about 3 x 3: half the largest stride that divides both view counts less one
    const int common = std::gcd(g.views_x - 1, g.views_y - 1);
    stride = common == 0 ? 1 : common % 2 == 0 ? common / 2 : common;
  }
  if (stride < 1) throw Error("a view stride of " + std::to_string(stride) + ": at least 1");
  for (int views : {g.views_x, g.views_y})
    if ((views - 1) % stride != 0)
      throw Error("every " + std::to_string(stride) + "-th of " + std::to_string(views) +
                  " views is not symmetric about the eyebox centre; choose a stride that divides " +
                  std::to_string(views - 1));
  LightFieldGeometry sub = g;
  sub.views_x = (g.views_x - 1) / stride + 1, sub.views_y = (g.views_y - 1) / stride + 1;
  sub.eyebox_width_m = g.eyebox_width_m * stride * sub.views_x / g.views_x;  // the same view centres
  sub.eyebox_height_m = g.eyebox_height_m * stride * sub.views_y / g.views_y;
  LightField out(sub);
  const size_t floats = g.pixels_per_view() * 3;
  for (int r = 0; r < sub.views_y; ++r)
    for (int c = 0; c < sub.views_x; ++c)
      std::copy_n(lf.view(g.view_index(r * stride, c * stride)), floats, out.view(sub.view_index(r, c)));
  out.scene = lf.scene;
  return out;
}

ToleranceProbe::ToleranceProbe(const DisplaySystem& nominal, const Patterns& patterns, const LightField& target,
                               int stride, Sampling sampling)
    : patterns_(patterns), views_(EveryNthView(target, stride)), sampling_(sampling) {
  for (const VirtualLayer& l : nominal.layers) names_.push_back(l.name);
  if (names_.size() != patterns_.size()) throw Error("the factorization has another number of layers than the display");
}

double ToleranceProbe::PsnrDb(const DisplaySystem& system) const {
  const DisplayModel model(system, views_.geometry, sampling_);
  Patterns t;
  for (const VirtualLayer& l : system.layers) {
    const auto at = std::find(names_.begin(), names_.end(), l.name);
    if (at == names_.end()) throw Error("the factorization has no pattern for layer \"" + l.name + "\"");
    t.push_back(patterns_[at - names_.begin()]);
  }
  return layerlab::PsnrDb(Objective(model, views_, t), views_.geometry.ray_count() * 3);
}

ToleranceResult MeasureDraw(const ToleranceModel& model, const DisplaySystem& nominal, const ToleranceDraw& draw,
                            const ToleranceProbe* probe) {
  ToleranceResult r;
  r.psnr_db = kNaN;
  try {
    const DisplaySystem system = model.Compile(draw);
    for (const VirtualLayer& l : nominal.layers) r.layers.push_back(MeasureLayer(l, system, nominal.eye));
    if (probe) r.psnr_db = probe->PsnrDb(system);
  } catch (const Error& e) {
    r.error = e.what();
  }
  return r;
}

ToleranceRun RunTolerance(const ToleranceModel& model, const DisplaySystem& nominal, const ToleranceRunOptions& options,
                          const ToleranceProbe* probe,
                          const std::function<void(size_t, size_t, const std::string&)>& progress) {
  ToleranceRun run;
  std::vector<const Tolerance*> measured;
  for (const Tolerance& t : model.spec().tolerances)
    for (const ToleranceDof& d : model.dofs())
      if (d.kind == t.kind) {
        measured.push_back(&t);
        break;
      }
  const size_t total = 1 + 2 * measured.size() + static_cast<size_t>(options.samples);
  size_t done = 0;
  auto step = [&](const std::string& what) {
    if (progress) progress(++done, total, what);
  };
  run.nominal = MeasureDraw(model, nominal, model.Zero(), probe);
  step("nominal");
  for (const Tolerance* t : measured) {
    SensitivityRow row{t->kind, t->limit, MeasureDraw(model, nominal, model.AtLimit(t->kind, +1), probe), {}};
    step(ToleranceKey(t->kind) + " +");
    row.minus = MeasureDraw(model, nominal, model.AtLimit(t->kind, -1), probe);
    step(ToleranceKey(t->kind) + " -");
    run.sensitivity.push_back(std::move(row));
  }
  for (int k = 0; k < options.samples; ++k) {
    run.draws.push_back(model.Draw(options.seed, static_cast<uint64_t>(k)));
    run.samples.push_back(MeasureDraw(model, nominal, run.draws.back(), probe));
    step("sample " + std::to_string(k + 1));
  }
  return run;
}

double WorstRmsPx(const ToleranceResult& r) {
  if (!r.error.empty() || r.layers.empty()) return kNaN;
  double worst = 0;
  for (const LayerResult& l : r.layers) worst = std::max(worst, l.misregistration.rms_px);
  return worst;
}

int DominantByMisregistration(const ToleranceRun& run) {
  int best = -1;
  double most = -1;
  for (size_t i = 0; i < run.sensitivity.size(); ++i) {
    const double worse =
        std::max(WorstRmsPx(run.sensitivity[i].plus), WorstRmsPx(run.sensitivity[i].minus));  // NaN loses
    if (worse > most) most = worse, best = static_cast<int>(i);
  }
  return best;
}

int DominantByPsnr(const ToleranceRun& run) {
  if (std::isnan(run.nominal.psnr_db)) return -1;
  int best = -1;
  double most = -INFINITY;
  for (size_t i = 0; i < run.sensitivity.size(); ++i) {
    const double loss =
        run.nominal.psnr_db - std::min(run.sensitivity[i].plus.psnr_db, run.sensitivity[i].minus.psnr_db);
    if (loss > most) most = loss, best = static_cast<int>(i);
  }
  return best;
}

}  // namespace layerlab
