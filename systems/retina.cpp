#include "systems/retina.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "framework/error.h"

namespace layerlab {

RetinaGrid MakeRetinaGrid(double field_x, double field_y, double resolution) {
  if (!(resolution > 0) || !(field_x > 0) || !(field_y > 0))
    throw Error("a retina needs a positive field and resolution");
  RetinaGrid g;
  g.resolution = resolution;
  g.cols = std::max(1, static_cast<int>(std::lround(field_x / resolution)));
  g.rows = std::max(1, static_cast<int>(std::lround(field_y / resolution)));
  if (double(g.cols) * g.rows > 1e8) throw Error("a retina of " + std::to_string(g.cols) + " x " + std::to_string(g.rows) + " samples is too large");
  return g;
}

std::vector<PupilPoint> PupilSamples(const EyeModel& eye) {
  const double a = eye.pupil_diameter;
  if (a == 0) return {PupilPoint{}};
  const int nx = eye.pupil_samples_x, ny = eye.pupil_samples_y;
  const bool round = eye.pupil_shape == PupilShape::kRound;
  auto inside = [&](double x, double y) { return !round || x * x + y * y <= 0.25 * a * a; };
  std::mt19937_64 rng(eye.pupil_seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<PupilPoint> points;
  if (eye.pupil_sampling == PupilSampling::kPoisson) {
    // Dart throwing with a minimum distance that packs about nx * ny points.
    const size_t wanted = static_cast<size_t>(nx) * ny;
    double area = round ? 0.785398 * a * a : a * a;
    double min_distance = 0.75 * std::sqrt(area / wanted);
    for (int attempt = 0; attempt < 200000 && points.size() < wanted; ++attempt) {
      PupilPoint p{(unit(rng) - 0.5) * a, (unit(rng) - 0.5) * a};
      if (!inside(p.x, p.y)) continue;
      bool far = std::all_of(points.begin(), points.end(), [&](const PupilPoint& q) {
        return (p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y) >= min_distance * min_distance;
      });
      if (far) points.push_back(p);
    }
    return points;
  }
  const bool jitter = eye.pupil_sampling == PupilSampling::kJittered;
  for (int i = 0; i < ny; ++i)
    for (int j = 0; j < nx; ++j) {
      double fx = jitter ? unit(rng) : 0.5, fy = jitter ? unit(rng) : 0.5;
      PupilPoint p{-0.5 * a + (j + fx) * a / nx, 0.5 * a - (i + fy) * a / ny};
      if (inside(p.x, p.y)) points.push_back(p);
    }
  if (points.empty()) points.push_back(PupilPoint{});
  return points;
}

std::array<double, 3> ChannelAccommodation(const EyeModel& eye, double diopters) {
  return {diopters + eye.chromatic_defocus[0], diopters + eye.chromatic_defocus[1], diopters + eye.chromatic_defocus[2]};
}

Image RetinaOfDisplay(const DisplayModel& model, const Patterns& t, const RetinaGrid& retina,
                      const std::vector<PupilPoint>& pupil, const std::array<double, 3>& accommodation) {
  Image image{retina.cols, retina.rows, {"R", "G", "B"}, std::vector<float>(size_t(retina.cols) * retina.rows * 3, 0.0f)};
  std::vector<double> tan_x(retina.cols), tan_y(retina.rows);
  for (int j = 0; j < retina.cols; ++j) tan_x[j] = std::tan(retina.angle_x(j));
  for (int i = 0; i < retina.rows; ++i) tan_y[i] = std::tan(retina.angle_y(i));
  const bool same_focus = accommodation[0] == accommodation[1] && accommodation[1] == accommodation[2];
  const size_t layers = model.layer_count();
  const double inverse_count = 1.0 / pupil.size();

#pragma omp parallel
  {
    std::vector<double> sum(size_t(retina.cols) * 3);
    std::vector<RayTaps> taps(layers * 3);  // per layer and channel focus
#pragma omp for schedule(dynamic)
    for (int i = 0; i < retina.rows; ++i) {
      std::fill(sum.begin(), sum.end(), 0.0);
      for (const PupilPoint& u : pupil)
        for (int j = 0; j < retina.cols; ++j) {
          for (size_t k = 0; k < layers; ++k) {
            const LayerSampler& s = model.projection(k).sampler();
            for (int c = 0; c < (same_focus ? 1 : 3); ++c) {
              double blur = s.diopters() - accommodation[c];
              taps[k * 3 + c] = s.At(tan_x[j] + u.x * blur, tan_y[i] + u.y * blur);
            }
          }
          for (size_t b = 0; b < model.branch_count(); ++b) {
            const auto& w = model.weight(b);
            for (int c = 0; c < 3; ++c) {
              double product = w[c];
              for (int k : model.branch_layers(b)) {
                const RayTaps& tap = taps[k * 3 + (same_focus ? 0 : c)];
                double value = 0;
                for (int q = 0; q < tap.count; ++q) value += tap.weight[q] * t[k].rgb[size_t(tap.index[q]) * 3 + c];
                product *= value;
              }
              sum[size_t(j) * 3 + c] += product;
            }
          }
        }
      for (size_t k = 0; k < sum.size(); ++k)
        image.pixels[size_t(i) * retina.cols * 3 + k] = static_cast<float>(sum[k] * inverse_count);
    }
  }
  return image;
}

Image RetinaOfScene(const SceneRadiance& scene, const RetinaGrid& retina, const std::vector<PupilPoint>& pupil,
                    const std::array<double, 3>& accommodation) {
  Image image{retina.cols, retina.rows, {"R", "G", "B"}, std::vector<float>(size_t(retina.cols) * retina.rows * 3, 0.0f)};
  const bool same_focus = accommodation[0] == accommodation[1] && accommodation[1] == accommodation[2];
  const double inverse_count = 1.0 / pupil.size();
#pragma omp parallel for schedule(dynamic)
  for (int i = 0; i < retina.rows; ++i)
    for (int j = 0; j < retina.cols; ++j) {
      double tx = std::tan(retina.angle_x(j)), ty = std::tan(retina.angle_y(i));
      double sum[3] = {0, 0, 0};
      for (const PupilPoint& u : pupil)
        for (int c = 0; c < (same_focus ? 1 : 3); ++c) {
          // Direction through the in-focus point: tan(a) - u D_a per unit depth.
          Rgb radiance = scene(u, tx - u.x * accommodation[c], ty - u.y * accommodation[c]);
          if (same_focus)
            for (int k = 0; k < 3; ++k) sum[k] += radiance[k];
          else
            sum[c] += radiance[c];
        }
      for (int c = 0; c < 3; ++c) image.pixels[(size_t(i) * retina.cols + j) * 3 + c] = float(sum[c] * inverse_count);
    }
  return image;
}

}  // namespace layerlab
