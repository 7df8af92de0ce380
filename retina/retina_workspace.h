// The working memory of the retinal images made image-wise: the display's on
// the one-tap path (RetinaOfDisplay) and a light field's (RetinaOfLightField).
// A part per thread of the team and the padded patterns the team shares;
// nothing of it is a thread_local.
//
// Every buffer is sized before a pass, by the one function that also gives
// the layout without allocating (RetinaWorkspace::Layout), which is what the
// memory estimate counts (RetinalObjectiveBytes), so the two cannot disagree.
// The passes only resize buffers within the sizes given here; Bytes() gives
// what is held, for the test that they did not grow. One workspace serves a
// sweep's states (Fit: sized again only for a state that needs more).
#pragma once

#include <cstddef>
#include <vector>

#include "layerlab/framework/lightfield.h"
#include "layerlab/framework/rgb4.h"
#include "layerlab/kernels/one_tap_view.h"
#include "layerlab/kernels/solve_workspace.h"
#include "layerlab/retina/lightfield_taps.h"
#include "layerlab/retina/retina_grid.h"

namespace layerlab {

// What the workspace is sized for; a part left 0 is not allocated.
struct RetinaWorkspaceSizes {
  int retina_cols = 0;
  // The display's one-tap path: each layer's pixels (padded patterns), the
  // distinct column tables and the ring of layer rows each keeps, the terms
  // (pupil points x branches), each with kMaxOneTapLayers row pointers.
  std::vector<size_t> layer_pixels;
  size_t column_tables = 0, ring = 0, terms = 0;
  // A light field's: per pupil point a blended row of `blended_row` floats.
  size_t pupil_points = 0, blended_row = 0;
};

// The sizes RetinaOfLightField needs for a light field of geometry `g`.
RetinaWorkspaceSizes LightFieldRetinaSizes(const LightFieldGeometry& g, const RetinaGrid& retina,
                                           const std::vector<PupilPoint>& pupil);

// One thread's buffers.
struct RetinaThreadWorkspace {
  std::vector<Rgb4> sum;  // a retinal row of light
  // The display's one-tap path: layer rows resampled to the retinal columns,
  // per column table a ring of the last rows read, [table][slot][column],
  // the layer row each slot holds; a retinal row's terms.
  std::vector<int> resampled_tags;
  std::vector<Rgb4> resampled;
  std::vector<const Rgb4*> term_rows;  // [term][layer of its branch]
  std::vector<Rgb4> term_weight;
  std::vector<int> term_layers;
  // A light field's: per pupil point the blended row of the last retinal row
  // and the light-field rows it blends.
  std::vector<float> blended;
  std::vector<lightfield_taps::Bracket> blended_rows;
};

class RetinaWorkspace {
 public:
  RetinaWorkspace() = default;
  // Allocates (and touches) every part of the layout.
  RetinaWorkspace(const RetinaWorkspaceSizes& sizes, int threads);
  // Sized again, to the larger of each size held and needed, unless it holds them already for `threads`.
  void Fit(const RetinaWorkspaceSizes& needed, int threads);
  const RetinaWorkspaceSizes& sizes() const { return sizes_; }
  // The layout the constructor allocates, without allocating.
  static WorkspaceLayout Layout(const RetinaWorkspaceSizes& sizes, int threads);
  // The threads a parallel region started here would have: 1 inside a
  // region when no nested one is active (the contrast sweep's states).
  static int TeamSize();

  int threads() const { return static_cast<int>(threads_.size()); }
  // The calling thread's part (omp_get_thread_num()); the passes run with num_threads(threads()).
  RetinaThreadWorkspace& thread();

  // Shared: the display's patterns padded to [pixel][rgb, 0].
  PaddedLayers padded;

  // What the buffers hold now (capacities): the layout's bytes unless a pass grew one.
  size_t Bytes() const;

 private:
  friend struct RetinaWorkspaceSizer;
  RetinaWorkspaceSizes sizes_;
  std::vector<RetinaThreadWorkspace> threads_;
};

}  // namespace layerlab
