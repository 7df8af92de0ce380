#include "layerlab/systems/layer_ray_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "layerlab/framework/error.h"
#include "layerlab/framework/random.h"
#include "layerlab/lenses/lens_system.h"

namespace layerlab {
namespace {

constexpr int kProbes = 4096;
constexpr size_t kMaxNodesPerChannel = size_t(1) << 20;
constexpr float kLost = std::numeric_limits<float>::quiet_NaN();

}  // namespace

LayerRayMap::LayerRayMap(const VirtualLayer& layer, const std::array<double, 3>& wavelengths_m)
    : wavelengths_m_(wavelengths_m),
      panel_position_m_(layer.position_m),
      b_(layer.transfer.b),
      diopters_(layer.diopters) {
  if (layer.panel.tilted()) {
    const double tx = layer.panel.tilt_rad[0], ty = layer.panel.tilt_rad[1];
    const Eigen::Matrix3d eye_from_panel =
        (Eigen::AngleAxisd(ty, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(tx, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    panel_tilted_ = true;
    panel_from_eye_ = eye_from_panel.transpose();
    const double side = b_ < 0 ? -1.0 : 1.0;  // an inverted image puts the offset's point across the axis
    panel_centre_m_ = {side * layer.panel.eye_from_panel_m[0], side * layer.panel.eye_from_panel_m[1],
                       panel_position_m_};
  }
  for (const PathStep& s : layer.path) {
    if (!s.position_m || s.kind == ElementKind::kPanel) continue;
    Step step;
    step.position_m = *s.position_m;
    if (s.lens_system) {
      step.lens = static_cast<int>(systems_.size());
      systems_.push_back(s.lens_system);
      std::array<std::unique_ptr<lenses::SequentialTrace>, 3> per_channel;
      for (int c = 0; c < 3; ++c)
        per_channel[c] = std::make_unique<lenses::SequentialTrace>(*s.lens_system, wavelengths_m[c]);
      tracers_.push_back(std::move(per_channel));
    } else {
      step.power_diopters = s.power_diopters;
      if (step.power_diopters == 0) continue;
    }
    steps_.push_back(step);
  }
}

std::optional<LayerRayMap::ExitRay> LayerRayMap::Carry(int channel, double p_x, double p_y, double u_x, double u_y,
                                                       const RayMapAdjustment* a) const {
  // The ray as a point and a slope direction (d_z = 1) in the unfolded frame, z from the pupil.
  Eigen::Vector3d o(p_x, p_y, 0.0), d(u_x, u_y, 1.0);
  for (size_t i = 0; i < steps_.size(); ++i) {
    const Step& s = steps_[i];
    double position = s.position_m, power = s.power_diopters;
    if (a && i < a->element_moved_m.size()) position += a->element_moved_m[i];
    if (a && i < a->element_power_diopters.size() && !std::isnan(a->element_power_diopters[i]))
      power = a->element_power_diopters[i];
    if (position < o.z()) return std::nullopt;  // a real lens's exit surface reaches past the next element
    o += d * (position - o.z());
    if (s.lens < 0) {
      d.x() -= power * o.x();
      d.y() -= power * o.y();
      continue;
    }
    lenses::Ray ray;
    ray.origin = Eigen::Vector3d(o.x(), o.y(), 0.0);
    ray.direction = d.normalized();
    const lenses::TraceResult r = tracers_[s.lens][channel]->Trace(ray);
    if (!r.exited() || !(r.exit.direction.z() > 0)) return std::nullopt;
    o = r.exit.origin + Eigen::Vector3d(0, 0, position);
    d = r.exit.direction / r.exit.direction.z();
  }
  return ExitRay{o, d};
}

std::optional<std::array<double, 2>> LayerRayMap::Trace(int channel, double p_x, double p_y, double u_x,
                                                        double u_y) const {
  const std::optional<ExitRay> exit = Carry(channel, p_x, p_y, u_x, u_y, nullptr);
  if (!exit) return std::nullopt;
  Eigen::Vector3d o = exit->o;
  const Eigen::Vector3d& d = exit->d;
  if (panel_tilted_) return AtTiltedPanel(o, d);
  if (panel_position_m_ < o.z()) return std::nullopt;
  o += d * (panel_position_m_ - o.z());
  return std::array<double, 2>{o.x() / b_, o.y() / b_};
}

std::optional<std::array<double, 2>> LayerRayMap::PanelPoint(int channel, double p_x, double p_y, double u_x,
                                                             double u_y, const RayMapAdjustment& a) const {
  if (panel_tilted_) throw Error("LayerRayMap::PanelPoint: a tilted panel (calibration refuses it)");
  const std::optional<ExitRay> exit = Carry(channel, p_x, p_y, u_x, u_y, &a);
  if (!exit) return std::nullopt;
  Eigen::Vector3d o = exit->o;
  const Eigen::Vector3d& d = exit->d;
  const double panel = panel_position_m_ + a.panel_moved_m;
  if (panel < o.z()) return std::nullopt;
  o += d * (panel - o.z());
  return std::array<double, 2>{o.x(), o.y()};
}

std::optional<std::array<double, 2>> LayerRayMap::AtTiltedPanel(const Eigen::Vector3d& o,
                                                                const Eigen::Vector3d& d) const {
  // In the panel's frame (origin C, its normal the local z) the ray crosses local z = 0.
  const Eigen::Vector3d o_local = panel_from_eye_ * (o - panel_centre_m_), d_local = panel_from_eye_ * d;
  if (!(d_local.z() > 0)) return std::nullopt;  // runs along the panel or away from it
  const double t = -o_local.z() / d_local.z();
  if (t < 0) return std::nullopt;  // the panel lies behind where the ray leaves the last element
  const Eigen::Vector3d hit = o_local + t * d_local;
  return std::array<double, 2>{(panel_centre_m_.x() + hit.x()) / b_, (panel_centre_m_.y() + hit.y()) / b_};
}

SampledRayMap::SampledRayMap(std::shared_ptr<const LayerRayMap> exact, const RayMapDomain& domain, double tan_pitch_x,
                             double tan_pitch_y)
    : exact_(std::move(exact)), domain_(domain), tan_pitch_x_(tan_pitch_x), tan_pitch_y_(tan_pitch_y) {
  for (int a = 0; a < 2; ++a) {  // a degenerate axis (a pinhole eye) gets a sliver
    if (!(domain_.pupil_max_m[a] - domain_.pupil_min_m[a] > 1e-9))
      domain_.pupil_min_m[a] -= 1e-6, domain_.pupil_max_m[a] += 1e-6;
    if (!(domain_.tan_max[a] - domain_.tan_min[a] > 1e-9)) domain_.tan_min[a] -= 1e-6, domain_.tan_max[a] += 1e-6;
  }
  nodes_ = {5, 5, 17, 17};
  for (;;) {
    Fill();
    // The error of each pair of axes alone: probes on the other pair's nodes.
    auto error_with = [&](bool pupil_on_nodes, bool tan_on_nodes) {
      double worst = 0;
      SplitMix64 random(pupil_on_nodes * 2 + tan_on_nodes + 1);
      for (int k = 0; k < kProbes; ++k) {
        std::array<double, 4> v;
        for (int a = 0; a < 4; ++a) {
          const double lo = a < 2 ? domain_.pupil_min_m[a] : domain_.tan_min[a - 2];
          const bool on_nodes = a < 2 ? pupil_on_nodes : tan_on_nodes;
          const double t = on_nodes ? std::floor(random.uniform() * nodes_[a]) : random.uniform() * (nodes_[a] - 1);
          v[a] = lo + t * step_[a];
        }
        const int c = k % 3;
        const auto exact_value = exact_->Trace(c, v[0], v[1], v[2], v[3]);
        const auto grid_value = Lookup(c, v[0], v[1], v[2], v[3]);
        if (!exact_value || !grid_value) continue;
        worst = std::max({worst, std::abs((*exact_value)[0] - (*grid_value)[0]) / tan_pitch_x_,
                          std::abs((*exact_value)[1] - (*grid_value)[1]) / tan_pitch_y_});
      }
      return worst;
    };
    bound_pixels_ = error_with(false, false);
    if (bound_pixels_ <= kMapTolerancePixels) return;
    const bool refine_tan = error_with(true, false) > kMapTolerancePixels / 2;
    const bool refine_pupil = error_with(false, true) > kMapTolerancePixels / 2;
    std::array<int, 4> finer = nodes_;
    for (int a = 0; a < 4; ++a)
      if ((a < 2 ? refine_pupil : refine_tan) || (!refine_pupil && !refine_tan)) finer[a] = 2 * nodes_[a] - 1;
    if (size_t(finer[0]) * finer[1] * finer[2] * finer[3] > kMaxNodesPerChannel) return;
    nodes_ = finer;
  }
}

size_t SampledRayMap::Node(int c, int a, int b, int i, int j) const {
  return (((size_t(c) * nodes_[1] + b) * nodes_[0] + a) * nodes_[3] + i) * nodes_[2] + j;
}

SampledRayMap::Cell SampledRayMap::Stencil(int axis, double value) const {
  Cell cell;
  cell.u = value;
  const double lo = axis < 2 ? domain_.pupil_min_m[axis] : domain_.tan_min[axis - 2];
  const double g = (value - lo) / step_[axis];
  if (!(g >= 0 && g <= nodes_[axis] - 1)) return cell;
  cell.first = std::clamp(static_cast<int>(g) - 1, 0, nodes_[axis] - 4);
  const double t = g - cell.first;  // the Lagrange cubic through nodes 0, 1, 2, 3 at t
  cell.weight = {-(t - 1) * (t - 2) * (t - 3) / 6, t * (t - 2) * (t - 3) / 2, -t * (t - 1) * (t - 3) / 2,
                 t * (t - 1) * (t - 2) / 6};
  return cell;
}

void SampledRayMap::Fill() {
  for (int a = 0; a < 2; ++a) {
    step_[a] = (domain_.pupil_max_m[a] - domain_.pupil_min_m[a]) / (nodes_[a] - 1);
    step_[a + 2] = (domain_.tan_max[a] - domain_.tan_min[a]) / (nodes_[a + 2] - 1);
  }
  residual_.assign(3 * size_t(nodes_[0]) * nodes_[1] * nodes_[2] * nodes_[3], {kLost, kLost});
  const double D = exact_->diopters();
  const int rows = 3 * nodes_[1] * nodes_[0];
#pragma omp parallel for schedule(dynamic)
  for (int row = 0; row < rows; ++row) {
    const int c = row / (nodes_[1] * nodes_[0]), b = row / nodes_[0] % nodes_[1], a = row % nodes_[0];
    const double p_x = domain_.pupil_min_m[0] + a * step_[0], p_y = domain_.pupil_min_m[1] + b * step_[1];
    for (int i = 0; i < nodes_[3]; ++i)
      for (int j = 0; j < nodes_[2]; ++j) {
        const double u_x = domain_.tan_min[0] + j * step_[2], u_y = domain_.tan_min[1] + i * step_[3];
        if (const auto U = exact_->Trace(c, p_x, p_y, u_x, u_y))
          residual_[Node(c, a, b, i, j)] = {float((*U)[0] - (D * p_x + u_x)), float((*U)[1] - (D * p_y + u_y))};
      }
  }
}

std::optional<std::array<double, 2>> SampledRayMap::Lookup(int channel, double p_x, double p_y, double u_x,
                                                           double u_y) const {
  const std::array<Cell, 4> cell{Stencil(0, p_x), Stencil(1, p_y), Stencil(2, u_x), Stencil(3, u_y)};
  for (const Cell& c : cell)
    if (c.first < 0) return exact_->Trace(channel, p_x, p_y, u_x, u_y);
  double rx = 0, ry = 0;
  int lost = 0;
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
          const double w = cell[1].weight[b] * cell[0].weight[a] * cell[3].weight[i] * cell[2].weight[j];
          const std::array<float, 2>& r =
              residual_[Node(channel, cell[0].first + a, cell[1].first + b, cell[3].first + i, cell[2].first + j)];
          rx += w * r[0], ry += w * r[1];
          lost += std::isnan(r[0]);
        }
  if (lost == 256) return std::nullopt;  // deep inside what the lenses stop
  if (std::isnan(rx) || std::isnan(ry)) return exact_->Trace(channel, p_x, p_y, u_x, u_y);
  const double D = exact_->diopters();
  return std::array<double, 2>{D * p_x + u_x + rx, D * p_y + u_y + ry};
}

SampledRayMap::Cell SampledRayMap::TanCell(int axis, double u) const { return Stencil(axis + 2, u); }

RayMapView::RayMapView(const SampledRayMap& map, double p_x, double p_y) : map_(map), p_x_(p_x), p_y_(p_y) {
  const SampledRayMap::Cell x = map.Stencil(0, p_x), y = map.Stencil(1, p_y);
  inside_ = x.first >= 0 && y.first >= 0;
  if (!inside_) return;
  const std::array<int, 4>& n = map.nodes_;
  const size_t plane = size_t(n[2]) * n[3];
  slice_.assign(3 * plane, {0.0f, 0.0f});
  std::vector<double> sum(2 * plane);
  for (int c = 0; c < 3; ++c) {
    std::fill(sum.begin(), sum.end(), 0.0);
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a) {
        const double w = y.weight[b] * x.weight[a];
        const std::array<float, 2>* node = &map.residual_[map.Node(c, x.first + a, y.first + b, 0, 0)];
        for (size_t k = 0; k < plane; ++k) sum[2 * k] += w * node[k][0], sum[2 * k + 1] += w * node[k][1];
      }
    const double D = map.exact().diopters();
    for (size_t k = 0; k < plane; ++k) {
      if (std::isnan(sum[2 * k]) || std::isnan(sum[2 * k + 1])) {
        // A lost node in the pupil stencil (the lenses' apertures cut there): this pupil point's own ray.
        const double u_x = map.domain_.tan_min[0] + double(k % n[2]) * map.step_[2];
        const double u_y = map.domain_.tan_min[1] + double(k / n[2]) * map.step_[3];
        const auto U = map.exact().Trace(c, p_x, p_y, u_x, u_y);
        sum[2 * k] = U ? (*U)[0] - (D * p_x + u_x) : sum[2 * k];
        sum[2 * k + 1] = U ? (*U)[1] - (D * p_y + u_y) : sum[2 * k + 1];
      }
      slice_[c * plane + k] = {static_cast<float>(sum[2 * k]), static_cast<float>(sum[2 * k + 1])};
    }
  }
}

std::optional<std::array<double, 2>> RayMapView::Lookup(int channel, const SampledRayMap::Cell& x,
                                                        const SampledRayMap::Cell& y) const {
  if (!inside_ || x.first < 0 || y.first < 0) return map_.exact().Trace(channel, p_x_, p_y_, x.u, y.u);
  const int cols = map_.nodes_[2];
  const std::array<float, 2>* r = &slice_[(size_t(channel) * map_.nodes_[3] + y.first) * cols + x.first];
  double rx = 0, ry = 0;
  int lost = 0;
  for (int i = 0; i < 4; ++i, r += cols) {
    double row_x = 0, row_y = 0;
    for (int j = 0; j < 4; ++j) {
      row_x += x.weight[j] * r[j][0], row_y += x.weight[j] * r[j][1];
      lost += std::isnan(r[j][0]);
    }
    rx += y.weight[i] * row_x, ry += y.weight[i] * row_y;
  }
  if (lost == 16) return std::nullopt;  // deep inside what the lenses stop
  if (std::isnan(rx) || std::isnan(ry)) return map_.exact().Trace(channel, p_x_, p_y_, x.u, y.u);
  const double D = map_.exact().diopters();
  return std::array<double, 2>{D * p_x_ + x.u + rx, D * p_y_ + y.u + ry};
}

void RayMapView::Grid(int channel, const std::vector<SampledRayMap::Cell>& cols,
                      const std::vector<SampledRayMap::Cell>& rows, double* out) const {
  const double nan = std::numeric_limits<double>::quiet_NaN(), D = map_.exact().diopters();
  const size_t n_cols = cols.size();
  auto exact = [&](size_t i, size_t j, double* to) {
    const auto U = map_.exact().Trace(channel, p_x_, p_y_, cols[j].u, rows[i].u);
    to[0] = U ? (*U)[0] : nan, to[1] = U ? (*U)[1] : nan;
  };
  if (!inside_) {
    for (size_t i = 0; i < rows.size(); ++i)
      for (size_t j = 0; j < n_cols; ++j) exact(i, j, out + (i * n_cols + j) * 2);
    return;
  }
  const int nx = map_.nodes_[2], ny = map_.nodes_[3];
  std::vector<double> along_x(size_t(ny) * n_cols * 2, nan);  // [tan row][column][2]
  std::vector<uint8_t> all_lost(size_t(ny) * n_cols, 0);      // that row's 4 stencil nodes all lost
  for (int y = 0; y < ny; ++y) {
    const std::array<float, 2>* r = &slice_[(size_t(channel) * ny + y) * nx];
    for (size_t j = 0; j < n_cols; ++j) {
      if (cols[j].first < 0) continue;
      double sx = 0, sy = 0;
      int lost = 0;
      for (int k = 0; k < 4; ++k) {
        const std::array<float, 2>& node = r[cols[j].first + k];
        sx += cols[j].weight[k] * node[0], sy += cols[j].weight[k] * node[1];
        lost += std::isnan(node[0]);
      }
      along_x[(size_t(y) * n_cols + j) * 2] = sx, along_x[(size_t(y) * n_cols + j) * 2 + 1] = sy;
      all_lost[size_t(y) * n_cols + j] = lost == 4;
    }
  }
  for (size_t i = 0; i < rows.size(); ++i) {
    double* row_out = out + i * n_cols * 2;
    if (rows[i].first < 0) {
      for (size_t j = 0; j < n_cols; ++j) exact(i, j, row_out + j * 2);
      continue;
    }
    const double* a = &along_x[size_t(rows[i].first) * n_cols * 2];
    const std::array<double, 4>& w = rows[i].weight;
    const size_t stride = n_cols * 2;
    for (size_t q = 0; q < stride; ++q)
      row_out[q] = w[0] * a[q] + w[1] * a[q + stride] + w[2] * a[q + 2 * stride] + w[3] * a[q + 3 * stride];
    const double base_x = D * p_x_, base_y = D * p_y_ + rows[i].u;
    for (size_t j = 0; j < n_cols; ++j) {
      double* U = row_out + j * 2;
      if (std::isnan(U[0]) || std::isnan(U[1])) {
        const uint8_t* lost = &all_lost[size_t(rows[i].first) * n_cols + j];
        if (cols[j].first >= 0 && lost[0] && lost[n_cols] && lost[2 * n_cols] && lost[3 * n_cols]) continue;
        exact(i, j, U);  // near the edge of what the lenses pass
        continue;
      }
      U[0] += base_x + cols[j].u, U[1] += base_y;
    }
  }
}

}  // namespace layerlab
