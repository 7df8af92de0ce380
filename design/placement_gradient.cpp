#include "layerlab/design/placement_gradient.h"

#include <array>
#include <cmath>

#include "layerlab/framework/error.h"
#include "layerlab/systems/layer_sampler.h"

namespace layerlab {
namespace {

// A bilinear read of one channel at panel coordinates (col, row) (LayerSampler::PanelCoordinates, pixel
// centres at integers): the value and its slopes along col and row (0 outside the grid, as the sampler reads).
struct Read {
  double value = 0, d_col = 0, d_row = 0;
};

struct Grid {  // in the panel's own order
  const float* rgb;
  int cols, rows;

  double At(int col, int row, int c) const {
    if (col < 0 || col >= cols || row < 0 || row >= rows) return 0;
    return rgb[(static_cast<size_t>(row) * cols + col) * 3 + c];
  }
};

// Where a coordinate lies: its cell's lower index and the fraction across it; on a node (a pixel centre,
// to kNode of a pixel: a light field made for the display meets it there up to rounding) the fraction is 0
// and `node` is set.
constexpr double kNode = 1e-6;
struct Axis {
  int i;
  double f;
  bool node;
};

Axis Locate(double x) {
  const double r = std::round(x);
  if (std::abs(x - r) < kNode) return {static_cast<int>(r), 0.0, true};
  const double low = std::floor(x);
  return {static_cast<int>(low), x - low, false};
}

Read Bilinear(const Grid& g, double col, double row, int c) {
  Read r;
  // The sampler's rule: a point within a cell of the grid or of its one-cell border reads its corners
  // (and a point on the border's outer edge, where the read bends to 0, takes the mean slope below).
  if (!(col >= -1 - kNode && col < g.cols + kNode && row >= -1 - kNode && row < g.rows + kNode)) return r;
  const Axis a = Locate(col), b = Locate(row);
  const int i = a.i, j = b.i;
  const double f = a.f, h = b.f;
  const double v00 = g.At(i, j, c), v01 = g.At(i + 1, j, c), v10 = g.At(i, j + 1, c), v11 = g.At(i + 1, j + 1, c);
  r.value = (1 - h) * ((1 - f) * v00 + f * v01) + h * ((1 - f) * v10 + f * v11);
  // The read is linear within a cell and bends at the pixel centres. On one, the slope is the mean of the
  // two cells' (what a central difference sees): a light field whose rays meet a layer at its pixel
  // centres (one made for the display) is common.
  auto col_slope = [&](int jj) {
    return a.node ? 0.5 * (g.At(i + 1, jj, c) - g.At(i - 1, jj, c)) : g.At(i + 1, jj, c) - g.At(i, jj, c);
  };
  auto row_slope = [&](int ii) {
    return b.node ? 0.5 * (g.At(ii, j + 1, c) - g.At(ii, j - 1, c)) : g.At(ii, j + 1, c) - g.At(ii, j, c);
  };
  r.d_col = (1 - h) * col_slope(j) + h * col_slope(j + 1);
  r.d_row = (1 - f) * row_slope(i) + f * row_slope(i + 1);
  return r;
}

// Per view and layer: sum of rho dL/dcol, of rho dL/dcol (col - centre), and the same for rows.
struct Sums {
  double col = 0, col_moment = 0, row = 0, row_moment = 0;
};

}  // namespace

std::vector<LayerPlacementGradient> PlacementGradient(const DisplayModel& model, const LightField& target,
                                                      const Patterns& t, double* error) {
  const DisplaySystem& system = model.system();
  const LightFieldGeometry& lf = model.geometry();
  const size_t n = model.layer_count();
  if (t.size() != n)
    throw Error("placement gradient: " + std::to_string(t.size()) + " patterns for " + std::to_string(n) + " layers");
  for (size_t k = 0; k < n; ++k) {
    const VirtualLayer& layer = system.layers[k];
    const LayerProjection& p = model.projection(k);
    if (p.sampling() != Sampling::kBilinear)
      throw Error(
          "the gradient with respect to a layer's placement needs bilinear sampling (the solve's "
          "\"sampling\": \"bilinear\"): with nearest sampling the error is a step function of it");
    if (p.mapped())
      throw Error("layer " + layer.name +
                  " is seen through a real lens: its ray map is not affine in its depth, and the placement "
                  "gradient is of the affine (ideal-optics) projection only");
    if (!p.separable())
      throw Error("layer " + layer.name + " is rotated: the placement gradient needs an axis-aligned grid");
    if (layer.lenslets)
      throw Error("layer " + layer.name +
                  " is seen through a lens array: which lenslet a ray passes moves with the layer's depth, which "
                  "the placement gradient does not follow");
    if (t[k].cols != layer.cols || t[k].rows != layer.rows)
      throw Error("placement gradient: the pattern of layer " + layer.name + " is not its size");
  }
  if (target.geometry.ray_count() != lf.ray_count() || target.rgb.size() != lf.ray_count() * 3)
    throw Error("placement gradient: the target is not on the model's rays");

  std::vector<LayerSampler> samplers;
  for (size_t k = 0; k < n; ++k) samplers.emplace_back(system.layers[k], Sampling::kBilinear);
  const double inv_z = 1.0 / lf.origin_z_m;
  const size_t views = lf.view_count(), pixels = lf.pixels_per_view();
  std::vector<std::vector<Sums>> per_view(views, std::vector<Sums>(n));
  std::vector<double> error_per_view(views, 0.0);
#pragma omp parallel for schedule(dynamic, 1)
  for (long long v = 0; v < static_cast<long long>(views); ++v) {
    const int vr = static_cast<int>(v / lf.views_x), vc = static_cast<int>(v % lf.views_x);
    const double px = lf.view_x(vc), py = lf.view_y(vr);
    std::vector<Sums>& sums = per_view[static_cast<size_t>(v)];
    std::vector<Read> reads(n);
    std::vector<double> cols(n), rows(n);  // eye-space order, for the pitch's moment
    std::vector<std::array<double, 2>> at(n);
    double view_error = 0;
    for (int i = 0; i < lf.rows; ++i)
      for (int j = 0; j < lf.cols; ++j) {
        // Where the ray meets each layer (systems/projection.h): u = D p + (x - p) / z_lf.
        const double ux = (lf.pixel_x(j) - px) * inv_z, uy = (lf.pixel_y(i) - py) * inv_z;
        for (size_t k = 0; k < n; ++k) {
          const VirtualLayer& layer = system.layers[k];
          at[k] = samplers[k].PanelCoordinates(layer.diopters * px + ux, layer.diopters * py + uy);
          cols[k] = layer.flip_x ? layer.cols - 1 - at[k][0] : at[k][0];
          rows[k] = layer.flip_y ? layer.rows - 1 - at[k][1] : at[k][1];
        }
        const size_t ray = static_cast<size_t>(v) * pixels + static_cast<size_t>(i) * lf.cols + j;
        for (int c = 0; c < 3; ++c) {
          for (size_t k = 0; k < n; ++k) {
            const VirtualLayer& layer = system.layers[k];
            reads[k] = Bilinear({t[k].rgb.data(), layer.cols, layer.rows}, at[k][0], at[k][1], c);
            // The slopes along the eye-space axes, which a flipped panel runs against.
            if (layer.flip_x) reads[k].d_col = -reads[k].d_col;
            if (layer.flip_y) reads[k].d_row = -reads[k].d_row;
          }
          double light = 0;
          for (size_t b = 0; b < model.branch_count(); ++b) {
            double product = model.weight(b)[c];
            for (int k : model.branch_layers(b)) product *= reads[static_cast<size_t>(k)].value;
            light += product;
          }
          const double rho = light - target.rgb[ray * 3 + c];
          view_error += rho * rho;
          if (rho == 0) continue;
          for (size_t b = 0; b < model.branch_count(); ++b) {
            const std::vector<int>& in = model.branch_layers(b);
            for (int k : in) {
              double others = rho * model.weight(b)[c];
              for (int m : in)
                if (m != k) others *= reads[static_cast<size_t>(m)].value;
              const size_t kk = static_cast<size_t>(k);
              const VirtualLayer& layer = system.layers[kk];
              const double dc = others * reads[kk].d_col, dr = others * reads[kk].d_row;
              sums[kk].col += dc;
              sums[kk].col_moment += dc * (cols[kk] - (0.5 * layer.cols - 0.5));
              sums[kk].row += dr;
              sums[kk].row_moment += dr * (rows[kk] - (0.5 * layer.rows - 0.5));
            }
          }
        }
      }
    error_per_view[static_cast<size_t>(v)] = view_error;
  }
  // In view order: the same sums whatever the threads.
  std::vector<LayerPlacementGradient> g(n);
  double total = 0;
  for (size_t v = 0; v < views; ++v) {
    const int vr = static_cast<int>(v / lf.views_x), vc = static_cast<int>(v % lf.views_x);
    const double px = lf.view_x(vc), py = lf.view_y(vr);
    total += error_per_view[v];
    for (size_t k = 0; k < n; ++k) {
      const VirtualLayer& layer = system.layers[k];
      const Sums& s = per_view[v][k];
      const double ax = layer.tan_pitch_x, ay = layer.tan_pitch_y;
      g[k].diopters += 2 * (s.col * px / ax - s.row * py / ay);
      g[k].center_tan_x += 2 * (-s.col / ax);
      g[k].center_tan_y += 2 * (s.row / ay);
      g[k].tan_pitch_x += 2 * (-s.col_moment / ax);
      g[k].tan_pitch_y += 2 * (-s.row_moment / ay);
    }
  }
  if (error) *error = total;
  return g;
}

}  // namespace layerlab
