#include "layerlab/retina/retina_workspace.h"

#include <omp.h>

#include <algorithm>
#include <string>

#include "layerlab/kernels/unrolled_layers.h"

namespace layerlab {

RetinaWorkspaceSizes LightFieldRetinaSizes(const LightFieldGeometry& g, const RetinaGrid& retina,
                                           const std::vector<PupilPoint>& pupil) {
  RetinaWorkspaceSizes s;
  s.retina_cols = retina.cols;
  s.pupil_points = pupil.size();
  s.blended_row = size_t(g.cols) * 3 + 4;  // a blended row and LoadRgbOver's float past it
  return s;
}

// Sizes every buffer of a retina's workspace and records it in the layout.
struct RetinaWorkspaceSizer : WorkspaceSizer {
  void Size(const RetinaWorkspaceSizes& s, int threads, RetinaWorkspace* w) {
    layout->threads = threads;
    size_t padded = 0;
    for (size_t pixels : s.layer_pixels) padded += pixels * sizeof(Rgb4);
    Record("padded patterns", padded, false);
    if (allocate) w->padded.Allocate(s.layer_pixels);
    if (allocate) w->threads_.resize(threads);
    const size_t cols = size_t(s.retina_cols);
    RetinaThreadWorkspace unused;  // what the layout sizes without allocating
    for (int me = 0; me < (allocate ? threads : 1); ++me) {
      RetinaThreadWorkspace& part = allocate ? w->threads_[me] : unused;
      const bool record = me == 0;
      const bool display = s.column_tables > 0, light_field = s.pupil_points > 0;
      Buffer("retinal row", &part.sum, display || light_field ? cols : 0, true, record);
      Buffer("resampled layer rows", &part.resampled_tags, s.column_tables * s.ring, true, record);
      Buffer("resampled layer rows", &part.resampled, s.column_tables * s.ring * cols, true, record);
      Buffer("terms", &part.term_rows, s.terms * kMaxOneTapLayers, true, record);
      Buffer("terms", &part.term_weight, s.terms, true, record);
      Buffer("terms", &part.term_layers, s.terms, true, record);
      Buffer("blended rows", &part.blended, s.pupil_points * s.blended_row, true, record);
      Buffer("blended rows", &part.blended_rows, s.pupil_points, true, record);
    }
  }
};

RetinaWorkspace::RetinaWorkspace(const RetinaWorkspaceSizes& sizes, int threads) : sizes_(sizes) {
  WorkspaceLayout layout;
  RetinaWorkspaceSizer{{true, &layout}}.Size(sizes, threads, this);
}

void RetinaWorkspace::Fit(const RetinaWorkspaceSizes& needed, int threads) {
  RetinaWorkspaceSizes s = sizes_;
  s.retina_cols = std::max(s.retina_cols, needed.retina_cols);
  s.layer_pixels.resize(std::max(s.layer_pixels.size(), needed.layer_pixels.size()), 0);
  for (size_t k = 0; k < needed.layer_pixels.size(); ++k)
    s.layer_pixels[k] = std::max(s.layer_pixels[k], needed.layer_pixels[k]);
  s.column_tables = std::max(s.column_tables, needed.column_tables);
  s.ring = std::max(s.ring, needed.ring);
  s.terms = std::max(s.terms, needed.terms);
  s.pupil_points = std::max(s.pupil_points, needed.pupil_points);
  s.blended_row = std::max(s.blended_row, needed.blended_row);
  if (threads == this->threads() && s.retina_cols == sizes_.retina_cols && s.layer_pixels == sizes_.layer_pixels &&
      s.column_tables == sizes_.column_tables && s.ring == sizes_.ring && s.terms == sizes_.terms &&
      s.pupil_points == sizes_.pupil_points && s.blended_row == sizes_.blended_row)
    return;
  *this = RetinaWorkspace();  // the old buffers freed before the new ones are made
  *this = RetinaWorkspace(s, threads);
}

WorkspaceLayout RetinaWorkspace::Layout(const RetinaWorkspaceSizes& sizes, int threads) {
  WorkspaceLayout layout;
  RetinaWorkspaceSizer{{false, &layout}}.Size(sizes, threads, nullptr);
  return layout;
}

int RetinaWorkspace::TeamSize() {
  return omp_get_active_level() >= omp_get_max_active_levels() ? 1 : omp_get_max_threads();
}

RetinaThreadWorkspace& RetinaWorkspace::thread() { return threads_.at(omp_get_thread_num()); }

namespace {

template <class T>
size_t Held(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace

size_t RetinaWorkspace::Bytes() const {
  size_t bytes = padded.Bytes();
  for (const RetinaThreadWorkspace& t : threads_)
    bytes += Held(t.sum) + Held(t.resampled_tags) + Held(t.resampled) + Held(t.term_rows) + Held(t.term_weight) +
             Held(t.term_layers) + Held(t.blended) + Held(t.blended_rows);
  return bytes;
}

}  // namespace layerlab
