// Where an eye ray meets a panel behind real lenses: the exact map from an
// eye-space ray to the panel point it reaches, per channel, and its sampled
// form that the projections and the retina read.
//
// A ray leaves pupil point p = (p_x, p_y) (m, in the pupil plane) with
// direction tan u = (u_x, u_y). Through the layer's path it is carried
// element by element in the unfolded frame: free space exactly, an ideal
// thin lens or curved mirror of power P as u -= P h (the ray-transfer model,
// exact for an ideal element), a real lens by the exact sequential trace
// (lenses/sequential_trace.h) at the channel's wavelength. Where it meets the
// panel plane, at height X, the map returns the tan-angle U = X / b on the
// layer's paraxial grid (b of VirtualLayer::transfer, the design
// wavelength's), so the layer's one sampling rule (layer_sampler.h) turns it
// into pixels. Through ideal optics U = D p + u exactly, the affine map the
// fast path uses.
//
// A tilted panel (PanelSpec::tilt_rad) is met where the ray crosses its
// tilted plane, turned R = Ry(tilt_y) Rx(tilt_x) about its active region's
// centre C (the offset, on the side of the axis where the layer's b puts it);
// the point's coordinates along the panel's own in-plane axes, added to C, are
// the X above. An untilted panel is met at its plane as before, bit for bit.
//
// The sampled map stores the residual U - (D p + u) on a regular grid over
// the pupil and tan-angle domain the layer is seen through, read by 4-point
// Lagrange cubics along each of (p_x, p_y, u_x, u_y) (the residual holds the
// lens's aberrations, odd powers of p and u that a linear read would need
// ten times the nodes for), refined until 4096 random probe rays agree with
// the exact trace to within kMapTolerancePixels; a ray outside the grid, or
// whose stencil holds a lost node (near the edge of what the lenses pass), is
// traced exactly, and one whose stencil's nodes are all lost is lost (a ray
// could pass there only through a gap narrower than a grid cell).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "layerlab/lenses/sequential_trace.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

// The interpolation's bound against the exact trace, in panel pixels.
inline constexpr double kMapTolerancePixels = 0.005;

// What a calibration fit changes on a layer's path (calibration/geometry_fit.cpp):
// each element with power (the map's elements, nearest the eye first) moved
// along the path and, for an ideal one, its power replaced; the panel's plane
// moved. Empty vectors change nothing.
struct RayMapAdjustment {
  std::vector<double> element_moved_m;
  std::vector<double> element_power_diopters;  // NaN keeps the compiled power; a real lens keeps its surfaces
  double panel_moved_m = 0;
};

class LayerRayMap {
 public:
  // `layer` compiled with its path (the map keeps what it needs, not the layer).
  LayerRayMap(const VirtualLayer& layer, const std::array<double, 3>& wavelengths_m);

  // The tan-angle on the layer's paraxial grid where channel c's ray (p, u)
  // meets the panel; nullopt when the ray is lost (missed, vignetted, totally
  // reflected) or turns back before the panel.
  std::optional<std::array<double, 2>> Trace(int channel, double p_x, double p_y, double u_x, double u_y) const;

  // Where channel c's ray (p, u) meets the untilted panel's plane with the
  // path changed as `a` says: the point X (m from the axis, in the unfolded
  // frame; Trace's tan-angle is X / b). nullopt as for Trace.
  std::optional<std::array<double, 2>> PanelPoint(int channel, double p_x, double p_y, double u_x, double u_y,
                                                  const RayMapAdjustment& a) const;

  double diopters() const { return diopters_; }
  double wavelength_m(int channel) const { return wavelengths_m_[channel]; }
  // The elements with power on the path (ideal or real), nearest the eye first.
  int element_count() const { return static_cast<int>(steps_.size()); }
  bool element_is_real_lens(int i) const { return steps_[i].lens >= 0; }
  bool panel_tilted() const { return panel_tilted_; }

 private:
  // Where a ray leaves the path's last element: point o, direction d with d_z = 1.
  struct ExitRay {
    Eigen::Vector3d o, d;
  };
  // The ray (p, u) carried through the path's elements (changed as `a` says,
  // when given); nullopt when it is lost.
  std::optional<ExitRay> Carry(int channel, double p_x, double p_y, double u_x, double u_y,
                               const RayMapAdjustment* a) const;

  struct Step {
    double position_m = 0;
    double power_diopters = 0;  // an ideal element
    int lens = -1;              // index into tracers_, for a real lens
  };
  std::optional<std::array<double, 2>> AtTiltedPanel(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const;

  std::vector<Step> steps_;
  std::vector<std::shared_ptr<const lenses::LensSystem>> systems_;
  std::vector<std::array<std::unique_ptr<lenses::SequentialTrace>, 3>> tracers_;  // [lens][channel]
  std::array<double, 3> wavelengths_m_;
  double panel_position_m_, b_, diopters_;
  bool panel_tilted_ = false;
  Eigen::Matrix3d panel_from_eye_ = Eigen::Matrix3d::Identity();  // R^T of a tilted panel
  Eigen::Vector3d panel_centre_m_ = Eigen::Vector3d::Zero();      // C, unfolded, m from the pupil
};

// The domain a sampled map covers: the pupil points and tan-angles of the
// rays it will be asked for.
struct RayMapDomain {
  std::array<double, 2> pupil_min_m{}, pupil_max_m{};
  std::array<double, 2> tan_min{}, tan_max{};
};

class SampledRayMap {
 public:
  // Throws nothing for a map it cannot refine to the bound: `bound_pixels()` then says what it reached.
  SampledRayMap(std::shared_ptr<const LayerRayMap> exact, const RayMapDomain& domain, double tan_pitch_x,
                double tan_pitch_y);

  // As LayerRayMap::Trace, from the grid where it can.
  std::optional<std::array<double, 2>> Lookup(int channel, double p_x, double p_y, double u_x, double u_y) const;

  // The cubic stencil of direction u on the tan grid along `axis` (0: x, 1: y):
  // nodes first .. first + 3 with their weights; first is -1 outside the grid.
  struct Cell {
    int first = -1;
    std::array<double, 4> weight{};
    double u = 0;
  };
  Cell TanCell(int axis, double u) const;

  const LayerRayMap& exact() const { return *exact_; }
  const RayMapDomain& domain() const { return domain_; }
  // The largest disagreement of the 4096 probes with the exact trace, panel pixels.
  double bound_pixels() const { return bound_pixels_; }
  std::array<int, 2> pupil_nodes() const { return {nodes_[0], nodes_[1]}; }
  std::array<int, 2> tan_nodes() const { return {nodes_[2], nodes_[3]}; }

 private:
  void Fill();
  Cell Stencil(int axis, double value) const;  // axes 0, 1: the pupil's; 2, 3: the tan grid's
  size_t Node(int c, int a, int b, int i, int j) const;

  std::shared_ptr<const LayerRayMap> exact_;
  RayMapDomain domain_;
  double tan_pitch_x_, tan_pitch_y_;
  std::array<int, 4> nodes_{};  // p_x, p_y, u_x, u_y
  std::array<double, 4> step_{};
  std::vector<std::array<float, 2>> residual_;  // [channel][p_y][p_x][u_y][u_x]; NaN where the ray is lost
  double bound_pixels_ = 0;

  friend class RayMapView;
};

// One pupil point's rays, read fast: the map's pupil axes interpolated once
// into a slice over the tan grid, then bilinear per ray (the same values as
// SampledRayMap::Lookup up to rounding). For the projections, whose views
// each hold one pupil point.
class RayMapView {
 public:
  RayMapView(const SampledRayMap& map, double p_x, double p_y);
  std::optional<std::array<double, 2>> Lookup(int channel, const SampledRayMap::Cell& x,
                                              const SampledRayMap::Cell& y) const;
  // The rays toward a grid of directions, cols[j] x rows[i] (TanCell of each
  // column's u_x and each row's u_y): out[(i * cols + j) * 2 + {0, 1}], NaN
  // for a lost ray. Separable: the columns' cubics once per tan row, then
  // each ray's along y.
  void Grid(int channel, const std::vector<SampledRayMap::Cell>& cols, const std::vector<SampledRayMap::Cell>& rows,
            double* out) const;

 private:
  const SampledRayMap& map_;
  double p_x_, p_y_;
  bool inside_ = false;
  std::vector<std::array<float, 2>> slice_;  // [channel][u_y][u_x]
};

}  // namespace layerlab
