// What the eye's optics do beyond its pupil's rays (docs/eye-model.md), for
// every retinal image made from pupil samples (a display's, a light field's,
// a scene's):
//   geometric (no diffraction): nothing; the rays' mean is the image;
//   "mtf": the rays' image times the diffraction-limited MTF of the pupil at
//     each channel's wavelength (diffraction.h);
//   "wave": the generalized pupil function (eye/pupil_function.h). A pupil
//     sample's view V_s (its rays, shifted by its vergence error and its
//     wavefront slope) carries, at retinal frequency f, the part c_s(f) of
//     the OTF whose autocorrelation midpoints lie in its cell (its Voronoi
//     cell in the pupil's own plane, with the rest of the phase), so the image
//     is sum_s c_s(f) V_s(f): the Wigner distribution of the pupil function
//     sampled at the pupil points. Its geometric limit is the rays' mean; in
//     focus it is the MTF times the rays' image; for one depth it is
//     Hopkins' defocused OTF. Samples whose c_s / c_s(0) agree within
//     kWaveShapeTolerance are traced and transformed together (their mean
//     view weighted by their summed c_s; exact for equal shapes); a group
//     whose c_s is flat over the grid's frequencies (the pupil's inner cells)
//     is added without a transform. A square pupil's grid has four shapes
//     (inner, x edges, y edges, corners): three transforms per channel. A
//     round pupil's rim cells each have their own: one transform each
//     (merging them by position instead costs up to 0.18 of contrast at
//     30 cpd and 0.25 D, docs/eye-model.md).
//     The parts are computed once per eye, grid and channel and serve every
//     accommodation state.
// With diffraction the rays are traced on the grid widened on every side by
// the PSF's support, where the PSF's tail beyond it holds less than
// kEdgeTailMass of its light (a 1 / x^2 tail: lambda / (pi^2 D tail)), so the
// tails meet the display or scene itself, not repeated edge values; the
// image is transformed periodically there and cut back to the grid. A grid
// whose content does not change along y (contrast's strips of a vertical
// grating) is widened along x only (RowEdges::kUniform): its rows wrap,
// which for such content is exact.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "layerlab/eye/pupil_function.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/retina/retina_grid.h"
#include "layerlab/retina/scene_radiance.h"

namespace layerlab {

inline constexpr double kEdgeTailMass = 5e-4;
inline constexpr double kWaveShapeTolerance = 0.02;
inline constexpr double kWaveWeightBytes = 256e6;

enum class RowEdges { kTrace, kUniform };

// The rays' image of one group of pupil samples on a grid.
using TraceGroup = std::function<Image(const RetinaGrid& grid, const std::vector<PupilPoint>& group)>;

class EyeOptics {
 public:
  // `pupil` is PupilSamples(eye).
  EyeOptics(const EyeModel& eye, const std::vector<PupilPoint>& pupil, const RetinaGrid& grid,
            RowEdges rows = RowEdges::kTrace, double shape_tolerance = kWaveShapeTolerance);

  const RetinaGrid& grid() const { return grid_; }
  // The grid the rays are traced on: grid() widened by the PSF's support.
  const RetinaGrid& traced() const { return traced_; }
  size_t groups() const { return groups_.size(); }
  const std::vector<PupilPoint>& group(size_t g) const { return groups_[g]; }
  // Groups whose images are transformed (the rest are added as they are).
  size_t transformed_groups() const;

  // The retinal image on grid() from each group's rays' image on traced().
  Image Combine(const std::vector<Image>& group_images) const;
  // Combine(trace of every group).
  Image See(const TraceGroup& trace) const;

 private:
  EyeDiffraction mode_;
  PupilShape shape_;
  double diameter_m_;
  std::array<double, 3> wavelengths_m_;
  RetinaGrid grid_, traced_;
  int left_ = 0, top_ = 0;               // grid() within traced()
  int field_cols_ = 0, field_rows_ = 0;  // the transformed field: traced()
  std::vector<std::vector<PupilPoint>> groups_;
  // Wave optics: per channel the groups' parts; per group whether it is flat and its share at f = 0. The MTF:
  // one group, never flat, its weights the MTF.
  std::array<OtfLattice, 3> parts_;
  std::vector<std::array<bool, 3>> flat_;
  // The parts on the transform's half spectrum, [channel][group] (empty: flat, or read from the lattice
  // when they would not fit in kWaveWeightBytes).
  std::array<std::vector<std::vector<std::complex<float>>>, 3> weights_;
  // Channel c's diffraction-limited MTF (real and even) at the transform's half-spectrum bins.
  std::vector<std::complex<float>> MtfOnHalfSpectrum(int c) const;
  // Part g of channel c at half-spectrum bin (row i, column j).
  std::complex<float> Weight(int c, size_t g, int i, int j) const;
};

}  // namespace layerlab
