#include "layerlab/kernels/solve_workspace.h"

#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "layerlab/kernels/pair_lattice.h"

namespace layerlab {

size_t WorkspaceLayout::bytes() const {
  size_t total = 0;
  for (const WorkspacePart& p : parts) total += p.bytes * static_cast<size_t>(p.per_thread ? threads : 1);
  return total;
}

namespace {

std::string Megabytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MB", bytes / 1e6);
  return text;
}

}  // namespace

std::string WorkspaceLayout::Describe() const {
  std::string per_thread, shared;
  double thread_bytes = 0, shared_bytes = 0;
  for (const WorkspacePart& p : parts) {
    std::string& list = p.per_thread ? per_thread : shared;
    (p.per_thread ? thread_bytes : shared_bytes) += double(p.bytes);
    list += (list.empty() ? "" : ", ") + p.name + " " + Megabytes(double(p.bytes));
  }
  return "per thread " + Megabytes(thread_bytes) + " x " + std::to_string(threads) + " (" + per_thread + ") + shared " +
         Megabytes(shared_bytes) + " (" + shared + ")";
}

void WorkspaceSizer::Record(const std::string& name, size_t bytes, bool per_thread) {
  if (bytes == 0) return;
  for (WorkspacePart& p : layout->parts)
    if (p.name == name && p.per_thread == per_thread) {
      p.bytes += bytes;
      return;
    }
  layout->parts.push_back({name, bytes, per_thread});
}

// Sizes every buffer of a solve's workspace and records it in the layout.
struct SolveWorkspaceSizer : WorkspaceSizer {
  void Size(const DisplayModel& model, int threads, unsigned passes, SolveWorkspace* w) {
    const LightFieldGeometry& g = model.geometry();
    const size_t layers = model.layer_count();
    const size_t n = g.pixels_per_view() * 3;
    const int cols = g.cols;
    if ((passes & kJointPassIfBranches) && model.branch_count() > 1) passes |= kJointPass;
    const bool synthesis = passes & kSynthesisPass, update = passes & kLayerUpdatePass, joint = passes & kJointPass;
    const bool pairs = (passes & kPairLatticePass) || ((passes & kPairLatticeIfOneBranch) && model.branch_count() == 1);

    // Which layers take which path.
    std::vector<bool> fast(layers, false), general(layers, false);
    bool any_fast = false, any_general = false, all_fast = true, all_one_tap = true, any_multi_tap = false;
    for (size_t b = 0; b < model.branch_count(); ++b) {
      const bool f = OneTapBranch(model, b);
      for (int k : model.branch_layers(b)) (f ? fast : general)[k] = true;
      any_fast = any_fast || f, any_general = any_general || !f, all_fast = all_fast && f;
    }
    int max_rows = 0;
    size_t max_pixels = 0;
    for (size_t k = 0; k < layers; ++k) {
      const LayerProjection& P = model.projection(k);
      all_one_tap = all_one_tap && P.one_tap();
      any_multi_tap = any_multi_tap || !P.one_tap();
      max_rows = std::max(max_rows, P.rows());
      max_pixels = std::max(max_pixels, P.pixel_count());
    }
    const bool column_pass = joint && all_fast;      // JointColumnPass
    const bool joint_general = joint && !all_fast;   // JointPass's float sums
    const bool joint_views = joint && !all_one_tap;  // JointPass::ViewGeneral

    threads = std::max(threads, 1);
    layout->threads = threads;
    w->threads_.resize(allocate ? threads : 1);
    for (size_t me = 0; me < w->threads_.size(); ++me) {
      ThreadWorkspace& t = w->threads_[me];
      const bool record = me == 0;
      auto buffer = [&](const char* name, auto* v, size_t count) { Buffer(name, v, count, true, record); };
      t.cache.resize(layers), t.resampled.resize(layers), t.num.resize(layers), t.den.resize(layers);
      for (size_t k = 0; k < layers; ++k) {
        const LayerProjection& P = model.projection(k);
        const size_t cells = static_cast<size_t>(P.rows()) * cols;
        buffer("column caches", &t.cache[k], synthesis && fast[k] ? cells : 0);
        buffer("resampled layers", &t.resampled[k], (update && fast[k]) || column_pass ? cells : 0);
        const bool float_sums = (update && general[k]) || (joint_general);
        buffer("layer sums", &t.num[k], float_sums ? P.pixel_count() * 3 : 0);
        buffer("layer sums", &t.den[k], float_sums ? P.pixel_count() * 3 : 0);
      }
      buffer("ray rows", &t.row, synthesis && any_fast ? cols : 0);
      buffer("ray rows", &t.rest_row, synthesis && any_fast ? cols : 0);
      buffer("view buffers", &t.synthesized, (synthesis && any_general) || joint_views ? n : 0);
      buffer("view buffers", &t.branch, synthesis ? n : 0);
      buffer("view buffers", &t.gathered, (synthesis || update || joint) && any_multi_tap ? n : 0);
      buffer("ray rows", &t.product, update && any_fast ? cols : 0);
      buffer("ray rows", &t.zeros, update && any_fast ? cols : 0);
      buffer("ray rows", &t.light, column_pass ? cols : 0);
      buffer("view buffers", &t.target, update ? n : 0);
      buffer("view buffers", &t.rest, update && any_general ? n : 0);
      buffer("view buffers", &t.sampled, update && any_general ? n : 0);
      buffer("view buffers", &t.samples, joint_views ? n * layers : 0);
      buffer("view buffers", &t.residual_terms, joint_views ? n : 0);
      buffer("view buffers", &t.denominator_terms, joint_views ? n : 0);
      if (update && any_fast) {
        if (record) Record("column sums", ColumnSums::BytesFor(max_rows, cols, max_pixels), true);
        if (allocate) t.update_sums.Allocate(max_rows, cols, max_pixels);
      }
      t.layer_sums.resize(column_pass ? layers : 0);
      for (size_t k = 0; k < t.layer_sums.size(); ++k) {
        const LayerProjection& P = model.projection(k);
        if (record) Record("column sums", ColumnSums::BytesFor(P.rows(), cols, P.pixel_count()), true);
        if (allocate) t.layer_sums[k].Allocate(P.rows(), cols, P.pixel_count());
      }
    }

    // The shared parts.
    std::vector<size_t> padded(layers, 0);
    size_t padded_bytes = 0;
    for (size_t k = 0; k < layers; ++k) {
      if (((synthesis || update) && fast[k]) || column_pass) padded[k] = model.projection(k).pixel_count();
      padded_bytes += padded[k] * sizeof(Rgb4);
    }
    Record("padded patterns", padded_bytes, false);
    if (allocate) w->padded.Allocate(padded);
    Buffer("view errors", &w->view_errors, update && any_fast ? g.view_count() : 0, false, true);
    Buffer("update sums", &w->update_num, update ? max_pixels * 3 : 0, false, true);
    Buffer("update sums", &w->update_den, update ? max_pixels * 3 : 0, false, true);
    Buffer("kept update sums", &w->kept_num, update ? max_pixels * 3 : 0, false, true);
    Buffer("kept update sums", &w->kept_den, update ? max_pixels * 3 : 0, false, true);
    size_t pair_cells = 0;
    for (size_t b = 0; pairs && b < model.branch_count(); ++b)
      if (const std::optional<PairLattice> lattice = PairLattice::IfItPays(model, b))
        pair_cells = std::max(pair_cells, lattice->cells());
    Buffer("pair lattice", &w->pair_cells, pair_cells, false, true);
    size_t pair_list = 0;
    for (size_t b = 0; pairs && b < model.branch_count(); ++b)
      if (const MappedPairs* list = model.pair_list(b)) pair_list = std::max(pair_list, list->pairs());
    Buffer("pair list sums", &w->pair_sums, pair_list, false, true);
    Record("pair list sums", pair_list * sizeof(float), true);
    w->pair_parts.resize(pair_list ? threads : 0);
    for (std::vector<float>& part : w->pair_parts) Buffer("pair list sums", &part, pair_list, true, false);
    w->joint_residual.resize(joint ? layers : 0), w->joint_den.resize(joint ? layers : 0);
    for (size_t k = 0; k < w->joint_residual.size(); ++k) {
      Buffer("joint sums", &w->joint_residual[k], model.projection(k).pixel_count() * 3, false, true);
      Buffer("joint sums", &w->joint_den[k], model.projection(k).pixel_count() * 3, false, true);
    }
  }
};

SolveWorkspace::SolveWorkspace(const DisplayModel& model, int threads, unsigned passes) {
  WorkspaceLayout ignored;
  SolveWorkspaceSizer{{true, &ignored}}.Size(model, threads, passes, this);
}

WorkspaceLayout SolveWorkspace::Layout(const DisplayModel& model, int threads, unsigned passes) {
  WorkspaceLayout layout;
  SolveWorkspace skeleton;
  SolveWorkspaceSizer{{false, &layout}}.Size(model, threads, passes, &skeleton);
  return layout;
}

ThreadWorkspace& SolveWorkspace::thread() {
  const int me = omp_get_thread_num();
  if (me >= threads()) {
    // A team larger than the one the workspace was sized for: a programming error, not bad input.
    std::fprintf(stderr, "layerlab: thread %d of a team larger than the solve's workspace (%d threads)\n", me,
                 threads());
    std::abort();
  }
  return threads_[me];
}

namespace {

template <class T, class A>
size_t Held(const std::vector<T, A>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace

size_t SolveWorkspace::Bytes() const {
  size_t bytes = padded.Bytes() + Held(pair_cells) + Held(pair_sums) + Held(view_errors) + Held(update_num) +
                 Held(update_den) + Held(kept_num) + Held(kept_den);
  for (size_t k = 0; k < joint_residual.size(); ++k) bytes += Held(joint_residual[k]) + Held(joint_den[k]);
  for (const std::vector<float>& part : pair_parts) bytes += Held(part);
  for (const ThreadWorkspace& t : threads_) {
    for (size_t k = 0; k < t.cache.size(); ++k)
      bytes += Held(t.cache[k]) + Held(t.resampled[k]) + Held(t.num[k]) + Held(t.den[k]);
    for (const ColumnSums& s : t.layer_sums) bytes += s.Bytes();
    bytes += t.update_sums.Bytes();
    for (const std::vector<Rgb4>* v : {&t.row, &t.rest_row, &t.product, &t.zeros, &t.light}) bytes += Held(*v);
    for (const std::vector<float>* v : {&t.synthesized, &t.branch, &t.gathered, &t.target, &t.rest, &t.sampled,
                                        &t.samples, &t.residual_terms, &t.denominator_terms})
      bytes += Held(*v);
  }
  return bytes;
}

}  // namespace layerlab
