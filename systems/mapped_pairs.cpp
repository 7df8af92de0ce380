#include "layerlab/systems/mapped_pairs.h"

#include <omp.h>

#include <algorithm>

#include "layerlab/framework/fixed_parts.h"

namespace layerlab {
namespace {

// View v's pixel of `P` per ray and channel, [ray][rgb] (-1: misses): the
// projection's own table behind a real lens, else from its taps into `buffer`.
const int32_t* ChannelPixels(const LayerProjection& P, size_t view, std::vector<int32_t>* buffer) {
  if (const int32_t* table = P.mapped_nearest(view)) return table;
  buffer->assign(P.geometry().pixels_per_view() * 3, -1);
  P.ForEachChannelTap(view, [&](size_t ray, int c, int32_t pixel, float) { (*buffer)[ray * 3 + c] = pixel; });
  return buffer->data();
}

bool OneTapPerChannel(const LayerProjection& P) {
  return P.sampling() == Sampling::kNearest && (P.mapped() || P.one_tap());
}

// Channel c's (pixel of a, pixel of b) of every ray that reads both, as
// buckets by a's pixel: bucket p holds the b pixels of the rays that read
// p, values[first[p] .. first[p + 1]). Two passes over the views on a fixed
// team, so each thread fills the places it counted.
struct Buckets {
  std::vector<size_t> first;
  std::vector<int32_t> values;
};

Buckets BucketsOf(const LayerProjection& a, const LayerProjection& b, int c) {
  const LightFieldGeometry& g = a.geometry();
  const size_t pixels = a.pixel_count(), views = g.view_count(), rays = g.pixels_per_view();
  const int threads = std::max(1, omp_get_max_threads());
  std::vector<std::vector<size_t>> next(threads, std::vector<size_t>(pixels, 0));
  auto each_ray = [&](auto op) {
#pragma omp parallel num_threads(threads)
    {
      std::vector<int32_t> buffer_a, buffer_b;
      std::vector<size_t>& mine = next[omp_get_thread_num()];
#pragma omp for schedule(static)
      for (size_t v = 0; v < views; ++v) {
        const int32_t* pa = ChannelPixels(a, v, &buffer_a);
        const int32_t* pb = ChannelPixels(b, v, &buffer_b);
        for (size_t ray = 0; ray < rays; ++ray)
          if (pa[ray * 3 + c] >= 0 && pb[ray * 3 + c] >= 0) op(mine, pa[ray * 3 + c], pb[ray * 3 + c]);
      }
    }
  };
  each_ray([](std::vector<size_t>& mine, int32_t p, int32_t) { ++mine[p]; });
  Buckets out;
  out.first.assign(pixels + 1, 0);
  for (size_t p = 0; p < pixels; ++p) {
    size_t at = out.first[p];
    for (auto& mine : next) {
      const size_t seen = mine[p];
      mine[p] = at;  // where this thread's rays of p go
      at += seen;
    }
    out.first[p + 1] = at;
  }
  out.values.resize(out.first.back());
  each_ray([&](std::vector<size_t>& mine, int32_t p, int32_t q) { out.values[mine[p]++] = q; });
  return out;
}

}  // namespace

bool MappedPairs::Suits(const LayerProjection& a, const LayerProjection& b) {
  return OneTapPerChannel(a) && OneTapPerChannel(b) && (a.mapped() || b.mapped());
}

size_t MappedPairs::Bytes() const {
  size_t bytes = (count_.capacity() + ray_pair_.capacity()) * 4;
  for (const Side& side : side_)
    bytes += side.first.capacity() * sizeof(size_t) + (side.other.capacity() + side.pair.capacity()) * 4;
  return bytes;
}

size_t MappedPairs::SetUpBytes(const LayerProjection& a, int threads) {
  const size_t pixels = a.pixel_count() + 1;
  return a.geometry().ray_count() * sizeof(int32_t) + pixels * sizeof(size_t) * (2 + size_t(std::max(threads, 1)));
}

MappedPairs::MappedPairs(int layer_a, const LayerProjection& a, int layer_b, const LayerProjection& b)
    : geometry_(a.geometry()), layer_{layer_a, layer_b} {
  Side &side_a = side_[0], &side_b = side_[1];
  side_a.pixels = a.pixel_count(), side_b.pixels = b.pixel_count();
  side_a.first.assign(3 * side_a.pixels + 1, 0);
  for (int c = 0; c < 3; ++c) {
    Buckets buckets = BucketsOf(a, b, c);
    std::vector<size_t> distinct(side_a.pixels + 1, 0);
#pragma omp parallel for schedule(dynamic, 4096)
    for (size_t p = 0; p < side_a.pixels; ++p) {
      const auto begin = buckets.values.begin() + buckets.first[p], end = buckets.values.begin() + buckets.first[p + 1];
      std::sort(begin, end);
      size_t runs = 0;
      for (auto it = begin; it != end; it = std::upper_bound(it, end, *it)) ++runs;
      distinct[p + 1] = runs;
    }
    const size_t base = count_.size();
    for (size_t p = 0; p < side_a.pixels; ++p) {
      side_a.first[c * side_a.pixels + p] = base + distinct[p];
      distinct[p + 1] += distinct[p];
    }
    side_a.first[(c + 1) * side_a.pixels] = base + distinct[side_a.pixels];
    count_.resize(base + distinct[side_a.pixels]);
    side_a.other.resize(count_.size());
#pragma omp parallel for schedule(dynamic, 4096)
    for (size_t p = 0; p < side_a.pixels; ++p) {
      const auto begin = buckets.values.begin() + buckets.first[p], end = buckets.values.begin() + buckets.first[p + 1];
      size_t k = base + distinct[p];
      for (auto it = begin; it != end; ++k) {
        const auto run = std::upper_bound(it, end, *it);
        side_a.other[k] = *it, count_[k] = static_cast<float>(run - it);
        it = run;
      }
    }
  }
  for (float n : count_) rays_ += n;
  // Side b: the same pairs grouped by b's pixel (within each, a's pixel ascending).
  side_b.first.assign(3 * side_b.pixels + 1, 0);
  for (int c = 0; c < 3; ++c)
    for (size_t k = side_a.first[c * side_a.pixels]; k < side_a.first[(c + 1) * side_a.pixels]; ++k)
      ++side_b.first[c * side_b.pixels + side_a.other[k] + 1];
  for (size_t i = 0; i + 1 < side_b.first.size(); ++i) side_b.first[i + 1] += side_b.first[i];
  side_b.other.resize(count_.size()), side_b.pair.resize(count_.size());
  std::vector<size_t> next(side_b.first.begin(), side_b.first.end() - 1);
  for (int c = 0; c < 3; ++c)
    for (size_t p = 0; p < side_a.pixels; ++p)
      for (size_t k = side_a.first[c * side_a.pixels + p]; k < side_a.first[c * side_a.pixels + p + 1]; ++k) {
        const size_t at = next[c * side_b.pixels + side_a.other[k]]++;
        side_b.other[at] = static_cast<int32_t>(p), side_b.pair[at] = static_cast<uint32_t>(k);
      }
  ListRayPairs(a, b);
}

void MappedPairs::ListRayPairs(const LayerProjection& a, const LayerProjection& b) {
  const LightFieldGeometry& g = geometry_;
  const size_t per_view = g.pixels_per_view() * 3;
  ray_pair_.resize(g.view_count() * per_view);
#pragma omp parallel
  {
    std::vector<int32_t> buffer_a, buffer_b;
#pragma omp for schedule(static)
    for (size_t v = 0; v < g.view_count(); ++v) {
      const int32_t* pa = ChannelPixels(a, v, &buffer_a);
      const int32_t* pb = ChannelPixels(b, v, &buffer_b);
      uint32_t* out = &ray_pair_[v * per_view];
      for (size_t k = 0; k < per_view; ++k)
        out[k] = pa[k] >= 0 && pb[k] >= 0 ? PairOf(static_cast<int>(k % 3), pa[k], pb[k]) : kNoPair;
    }
  }
}

uint32_t MappedPairs::PairOf(int c, int32_t a, int32_t b) const {
  const Side& side = side_[0];
  const size_t at = c * side.pixels + a;
  for (size_t k = side.first[at]; k < side.first[at + 1]; ++k)
    if (side.other[k] == b) return static_cast<uint32_t>(k);
  return kNoPair;  // unreachable: every pair a ray reads was listed
}

void MappedPairs::Bin(const LightField& r, std::vector<float>* binned, std::vector<std::vector<float>>* parts) const {
  const LightFieldGeometry& g = geometry_;
  const size_t n = pairs(), per_view = g.pixels_per_view() * 3;
  binned->resize(n);
  // Views cut into fixed parts, each part's sums kept apart and added in part order: the same bits on any
  // team of at most that many threads (framework/fixed_parts.h).
  const int part_count = FixedParts();
  if (parts->size() < size_t(part_count)) parts->resize(part_count);
#pragma omp parallel
  {
    ForEachPartOfThread(part_count, [&](int p) {
      std::vector<float>& mine = (*parts)[p];
      mine.assign(n, 0.0f);
      const ItemRange views = StaticShare(g.view_count(), p, part_count);
      for (size_t v = views.begin; v < views.end; ++v) {
        const uint32_t* pair = &ray_pair_[v * per_view];
        const float* rv = r.view(v);
        for (size_t k = 0; k < per_view; ++k)
          if (pair[k] != kNoPair) mine[pair[k]] += rv[k];
      }
    });
#pragma omp barrier
#pragma omp for schedule(static)
    for (size_t k = 0; k < n; ++k) {
      float sum = 0.0f;
      for (int p = 0; p < part_count; ++p) sum += (*parts)[p][k];
      (*binned)[k] = sum;
    }
  }
}

void MappedPairs::UpdateSums(int layer, const float* other, const std::vector<float>& binned, double* num,
                             double* den) const {
  const Side& side = side_[layer == layer_[0] ? 0 : 1];
  const bool own_order = side.pair.empty();
#pragma omp parallel for schedule(static)
  for (size_t p = 0; p < side.pixels; ++p)
    for (int c = 0; c < 3; ++c) {
      double n = 0, d = 0;
      const size_t at = c * side.pixels + p;
      for (size_t e = side.first[at]; e < side.first[at + 1]; ++e) {
        const size_t k = own_order ? e : side.pair[e];
        const double q = other[static_cast<size_t>(side.other[e]) * 3 + c];
        n += binned[k] * q;
        d += count_[k] * q * q;
      }
      num[p * 3 + c] = n, den[p * 3 + c] = d;
    }
}

}  // namespace layerlab
