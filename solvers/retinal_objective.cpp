#include "layerlab/solvers/retinal_objective.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <exception>

#include "layerlab/eye/contrast_sensitivity.h"
#include "layerlab/eye/spectral_filter.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/fixed_order_sum.h"
#include "layerlab/framework/heap_block.h"
#include "layerlab/framework/huge_page_allocator.h"
#include "layerlab/framework/units.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/solvers/objective.h"

namespace layerlab {

std::vector<double> RetinalStates(const EyeModel& eye, const RetinalObjectiveOptions& options) {
  if (!options.states_diopters.empty()) return options.states_diopters;
  return AccommodationStates(eye.accommodation_min_diopters, eye.accommodation_max_diopters, kDefaultStateStep);
}

std::vector<std::vector<PupilPoint>> RetinalPupils(const EyeModel& eye, const RetinalObjectiveOptions& options,
                                                   std::vector<double>* weights) {
  std::vector<std::vector<PupilPoint>> samples;
  std::vector<double> w;
  if (options.pupils.empty()) {
    samples.push_back(PupilSamples(eye));
    w.push_back(1);
  }
  double sum = 0;
  for (const PupilWeight& p : options.pupils) {
    if (!(p.weight >= 0) || !std::isfinite(p.weight))
      throw Error("a pupil position's weight in the retinal objective must be finite and >= 0");
    sum += p.weight;
    if (p.weight == 0) continue;  // it adds nothing: no operator
    EyeModel moved = eye;
    moved.pose = WithPupilMoved(eye.pose, p.offset_x_m, p.offset_y_m);
    samples.push_back(PupilSamples(moved));
    w.push_back(p.weight);
  }
  if (!options.pupils.empty()) {
    if (!(sum > 0)) throw Error("the retinal objective's pupil positions all have weight 0");
    for (double& v : w) v /= sum;
  }
  if (weights) *weights = std::move(w);
  return samples;
}

RetinaGrid RetinalObjectiveGrid(const LightFieldGeometry& g, double resolution) {
  const double pixel = std::atan(g.window_width_m / g.cols / g.origin_z_m);
  RetinaGrid grid;
  grid.resolution_rad = resolution > 0 ? resolution : pixel;
  const double field_x = 2 * std::atan(g.window_width_m / 2 / g.origin_z_m);
  const double field_y = 2 * std::atan(g.window_height_m / 2 / g.origin_z_m);
  if (resolution > 0) {
    grid = MakeRetinaGrid(field_x, field_y, resolution);
  } else {
    grid.cols = g.cols, grid.rows = g.rows;
  }
  grid.center_x_rad = std::atan((g.window_left_m + g.window_width_m / 2) / g.origin_z_m);
  grid.center_y_rad = std::atan((g.window_top_m - g.window_height_m / 2) / g.origin_z_m);
  return grid;
}

namespace {

// <r, H r> for channel c of an interleaved RGB image r on `grid`, r replaced by H r (H: gain S(f)^2, periodic).
double ContrastSensitivityChannel(float* r, const RetinaGrid& grid, int c) {
  const size_t n = size_t(grid.cols) * grid.rows;
  std::vector<std::complex<double>> field(n);
  for (size_t k = 0; k < n; ++k) field[k] = r[k * 3 + c];
  constexpr double kCyclesPerRadianInCpd = 3.14159265358979323846 / 180;
  FilterPeriodic(&field, grid.cols, grid.rows, grid.resolution_rad, [](double fx, double fy) {
    const double s = ContrastSensitivityWeight(std::hypot(fx, fy) * kCyclesPerRadianInCpd);
    return s * s;
  });
  double weighted = 0;
  for (size_t k = 0; k < n; ++k) {
    weighted += double(r[k * 3 + c]) * field[k].real();
    r[k * 3 + c] = static_cast<float>(field[k].real());
  }
  return weighted;
}

double SquaredDifference(const std::vector<float>& a, const std::vector<float>& b) {
  return FixedOrderSquaredDifference(a.data(), b.data(), a.size());
}

}  // namespace

RetinalObjective::RetinalObjective(const DisplayModel& model, const LightField& target,
                                   const RetinalObjectiveOptions& options) {
  const EyeModel& eye = model.system().eye;
  states_ = RetinalStates(eye, options);
  if (states_.empty()) throw Error("the retinal objective needs at least one accommodation state");
  weights_ = options.weights.empty() ? std::vector<double>(states_.size(), 1.0) : options.weights;
  if (weights_.size() != states_.size())
    throw Error("the retinal objective has " + std::to_string(states_.size()) + " states but " +
                std::to_string(weights_.size()) + " weights");
  for (double w : weights_)
    if (!(w >= 0) || !std::isfinite(w)) throw Error("a state weight of the retinal objective must be >= 0");
  const RetinaGrid grid = RetinalObjectiveGrid(model.geometry(), options.resolution_rad);
  grid_ = grid;
  contrast_sensitivity_ = options.contrast_sensitivity;
  std::vector<std::array<double, 3>> foci;
  for (double d : states_) foci.push_back(ChannelAccommodation(eye, d));
  if (options.target == RetinalTarget::kTraced && !options.target_radiance)
    throw Error("the retinal objective's traced target needs a target scene (target_scene), not a light field");
  std::vector<double> pupil_weights;
  const std::vector<std::vector<PupilPoint>> samples = RetinalPupils(eye, options, &pupil_weights);
  for (size_t p = 0; p < samples.size(); ++p) {
    Pupil pupil;
    pupil.weight = pupil_weights[p];
    pupil.op =
        std::make_unique<RetinalOperator>(model.geometry(), model.projection(0).sampling(), grid, samples[p], foci);
    if (options.target == RetinalTarget::kTraced) {
      pupil.target_images.resize(states_.size());
      for (size_t a = 0; a < states_.size(); ++a)
        pupil.target_images[a] = RetinaOfScene(options.target_radiance, grid, samples[p], foci[a]).pixels;
    } else {
      pupil.op->Apply(target, &pupil.target_images);
    }
    pupils_.push_back(std::move(pupil));
  }

  // Bound(): the largest entry of M 1, summed over the pupils.
  LightField ones(model.geometry());
  std::fill(ones.rgb.begin(), ones.rgb.end(), 1.0f);
  LightField m1(model.geometry());
  std::vector<std::vector<float>> images;
  for (size_t p = 0; p < pupils_.size(); ++p) {
    pupils_[p].op->Apply(ones, &images);
    for (size_t a = 0; a < states_.size(); ++a)
      for (float& v : images[a]) v = static_cast<float>(v * weights_[a] * pupils_[p].weight);
    pupils_[p].op->ApplyTranspose(images, &m1, p > 0);
  }
  const float largest = *std::max_element(m1.rgb.begin(), m1.rgb.end());
  bound_ = largest > 0 ? largest : 1.0;
}

std::vector<double> RetinalObjective::WeightResiduals() const {
  const size_t states = states_.size();
  std::vector<double> weighted(states * 3);
#pragma omp parallel for schedule(dynamic)
  for (size_t k = 0; k < states * 3; ++k)
    weighted[k] = ContrastSensitivityChannel(images_[k / 3].data(), grid_, int(k % 3));
  std::vector<double> per_state(states);
  for (size_t a = 0; a < states; ++a) per_state[a] = weighted[3 * a] + weighted[3 * a + 1] + weighted[3 * a + 2];
  return per_state;
}

double RetinalObjective::Evaluate(const LightField& x, std::vector<double>* per_state) const {
  LightField* no_adjoint = nullptr;
  return EvaluateWithAdjoint(x, per_state, no_adjoint);
}

double RetinalObjective::EvaluateWithAdjoint(const LightField& x, std::vector<double>* per_state,
                                             LightField* m_r) const {
  if (m_r && m_r->geometry.ray_count() != x.geometry.ray_count()) *m_r = LightField(x.geometry);
  std::vector<double> errors(states_.size(), 0.0);
  double f = 0;
  for (size_t p = 0; p < pupils_.size(); ++p) AddPupil(pupils_[p], x, &errors, &f, m_r, p == 0);
  if (per_state) *per_state = std::move(errors);
  return f;
}

void RetinalObjective::AddPupil(const Pupil& p, const LightField& x, std::vector<double>* errors, double* f,
                                LightField* m_r, bool first) const {
  std::vector<std::vector<float>>& images = images_;
  p.op->Apply(x, &images);
  std::vector<double> weighted(states_.size());
  for (size_t a = 0; a < states_.size(); ++a) {
    weighted[a] = SquaredDifference(images[a], p.target_images[a]);
    (*errors)[a] += p.weight * weighted[a];
  }
  // The adjoint's images w_p w_a (A_ap x - r_ap), or w_p w_a C^T C (A_ap x - r_ap): the residual and its weight
  // in one pass when there is no filter between them.
  if (contrast_sensitivity_) {
    for (size_t a = 0; a < states_.size(); ++a) {
      std::vector<float>& image = images[a];
      const std::vector<float>& target = p.target_images[a];
#pragma omp parallel for schedule(static)
      for (size_t i = 0; i < image.size(); ++i) image[i] = image[i] - target[i];
    }
    weighted = WeightResiduals();
  }
  for (size_t a = 0; a < states_.size(); ++a) *f += p.weight * weights_[a] * weighted[a];
  if (!m_r) return;
  for (size_t a = 0; a < states_.size(); ++a) {
    std::vector<float>& image = images[a];
    const std::vector<float>& target = p.target_images[a];
    const float w = static_cast<float>(p.weight * weights_[a]);
    if (contrast_sensitivity_) {
#pragma omp parallel for schedule(static)
      for (size_t i = 0; i < image.size(); ++i) image[i] = w * image[i];
    } else {
#pragma omp parallel for schedule(static)
      for (size_t i = 0; i < image.size(); ++i) image[i] = w * (image[i] - target[i]);
    }
  }
  p.op->ApplyTranspose(images, m_r, !first);
}

size_t RetinalObjective::TableBytes() const {
  size_t bytes = 0;
  for (const Pupil& p : pupils_) bytes += p.op->TableBytes();
  return bytes;
}

RetinalObjectiveMemory RetinalObjectiveBytes(const DisplayModel& model, const RetinalObjectiveOptions& options,
                                             int threads) {
  const EyeModel& eye = model.system().eye;
  const std::vector<double> states = RetinalStates(eye, options);
  std::vector<std::array<double, 3>> foci;
  for (double d : states) foci.push_back(ChannelAccommodation(eye, d));
  const RetinaGrid grid = RetinalObjectiveGrid(model.geometry(), options.resolution_rad);
  const std::vector<std::vector<PupilPoint>> pupils = RetinalPupils(eye, options);
  const std::vector<PupilPoint>& pupil = pupils.front();
  const LightFieldGeometry& g = model.geometry();
  const size_t samples = size_t(grid.cols) * grid.rows;
  RetinalObjectiveMemory m;
  m.pupils = pupils.size();
  for (const std::vector<PupilPoint>& p : pupils)
    m.tables += RetinalOperator::TableBytes(g, model.projection(0).sampling(), grid, p, foci);
  m.images = HeapBlockBytes(states.size() * sizeof(std::vector<float>)) +
             states.size() * HeapBlockBytes(samples * 3 * sizeof(float));
  m.apply_buffer = HeapBlockBytes(RetinalOperator::ApplyBufferValues(g, pupil.size()) * sizeof(float));
  if (options.target == RetinalTarget::kTraced)
    if (const LightFieldRays* rays = options.target_radiance.target<LightFieldRays>())
      m.retina_workspace =
          RetinaWorkspace::Layout(LightFieldRetinaSizes(rays->light_field().geometry, grid, pupil), threads).bytes();
  m.construction = std::max(2 * LargeAllocationBytes(g.ray_count() * 3 * sizeof(float)) + m.images, m.retina_workspace);
  if (options.contrast_sensitivity) {
    const size_t line = HeapBlockBytes(size_t(std::max(grid.cols, grid.rows)) * sizeof(std::complex<double>));
    m.filter = size_t(std::max(threads, 1)) * (HeapBlockBytes(samples * sizeof(std::complex<double>)) + 4 * line);
  }
  return m;
}

std::vector<double> RetinalObjective::MeanScores(const LightField& x, const std::vector<const RetinalMetric*>& metrics,
                                                 double white_cd_m2, const MetricSettings& settings) const {
  CheckMetricSize(metrics, grid_.cols, grid_.rows, "the focal stack's metrics (one sample per light-field pixel)");
  const MetricViewing viewing = MetricViewing::Of(grid_.resolution_rad / kRadiansPerDegree, white_cd_m2, settings);
  const size_t states = states_.size(), items = states * metrics.size();
  std::vector<double> mean(metrics.size(), 0.0);
  for (const Pupil& p : pupils_) {
    std::vector<std::vector<float>> images;
    p.op->Apply(x, &images);
    auto image = [&](std::vector<float> pixels) {
      return Image{grid_.cols, grid_.rows, {"R", "G", "B"}, std::move(pixels)};
    };
    std::vector<double> score(items);
    std::vector<std::exception_ptr> failed(items);
#pragma omp parallel for schedule(dynamic)
    for (size_t i = 0; i < items; ++i) {
      const size_t a = i / metrics.size(), k = i % metrics.size();
      try {
        score[i] = metrics[k]->score(image(images[a]), image(p.target_images[a]), viewing);
      } catch (...) {
        failed[i] = std::current_exception();
      }
    }
    for (size_t i = 0; i < items; ++i) {
      if (failed[i]) std::rethrow_exception(failed[i]);
      mean[i % metrics.size()] += p.weight * score[i] / double(states);
    }
  }
  return mean;
}

double RetinalObjective::FocalStackPsnr(const std::vector<double>& per_state) const {
  double sum = 0;
  for (double e : per_state) sum += PsnrDb(e, samples_per_state());
  return sum / static_cast<double>(per_state.size());
}

}  // namespace layerlab
