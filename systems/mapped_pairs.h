// A branch of two nearest-sampled layers behind real lenses, its rays binned
// by the pixel pair they read, per channel: the pair lattice's idea
// (pair_lattice.h) where the lattice cannot hold. Through a real lens a
// ray's pixel on either layer depends on both of its coordinates and on its
// channel (distortion, lateral colour), so the pairs are no product of row
// pairs and column pairs: they are listed, channel by channel, sorted by
// layer a's pixel, with each pair's ray count.
//
// Every ray of channel c that reads pixel p_a of a and p_b of b adds the same
// terms to the multiplicative update's sums,
//   num_a[p_a][c] += r t_b[p_b][c],   den_a[p_a][c] += t_b[p_b][c]^2,
// and likewise for b, except r: a solver that updates the branch several
// times toward the same r bins r once and then sums a few pairs per pixel.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "layerlab/framework/lightfield.h"
#include "layerlab/systems/projection.h"

namespace layerlab {

class MappedPairs {
 public:
  // Layers `layer_a` < `layer_b` of a branch, projected as `a` and `b` (they must suit: Suits).
  MappedPairs(int layer_a, const LayerProjection& a, int layer_b, const LayerProjection& b);
  // Two layers read with one tap per channel (nearest sampling, no rotation
  // unless mapped), at least one of them behind a real lens (else the
  // lattice holds).
  static bool Suits(const LayerProjection& a, const LayerProjection& b);
  // Whether binning pays: the rays are at least twice the pairs.
  bool Pays() const { return pairs() > 0 && rays_ >= 2.0 * double(pairs()); }
  // The bytes it holds.
  size_t Bytes() const;
  // The most its making holds beside it, freed when made (a channel's rays
  // bucketed by a's pixel): a solve that makes it counts this.
  static size_t SetUpBytes(const LayerProjection& a, int threads);

  size_t pairs() const { return count_.size(); }
  // The ray-channels that read both layers (the others add nothing to either's sums).
  double rays() const { return rays_; }
  int layer_a() const { return layer_[0]; }
  int layer_b() const { return layer_[1]; }
  int other_layer(int layer) const { return layer == layer_[0] ? layer_[1] : layer_[0]; }

  // binned[pair] = the sum of r over the pair's ray-channels, r
  // [view][row][col][rgb] with the model's geometry; binned is resized to
  // pairs(). Per-thread float sums in `parts` (one per thread, kept by the
  // caller between calls) merged in thread order: the same bits for a given
  // thread count.
  void Bin(const LightField& r, std::vector<float>* binned, std::vector<std::vector<float>>* parts) const;

  // The sums of `layer` (a or b) from `binned` and the other layer's pattern
  // `other` ([pixel][rgb]), as OneTapUpdateSums gives them: num[p * 3 + c] =
  // sum r q and den[p * 3 + c] = sum q^2 over the ray-channels that read
  // pixel p, q the other layer's value. num and den hold the layer's pixels
  // x 3 and are written whole.
  void UpdateSums(int layer, const float* other, const std::vector<float>& binned, double* num, double* den) const;

 private:
  // One layer's view of the pairs: those of its pixel p in channel c are
  // entries first[c * pixels + p] .. first[c * pixels + p + 1], each with
  // the other layer's pixel and the pair's index.
  struct Side {
    size_t pixels = 0;
    std::vector<size_t> first;
    std::vector<int32_t> other;
    std::vector<uint32_t> pair;  // empty for side a, whose entries are the pairs in order
  };
  uint32_t PairOf(int c, int32_t a, int32_t b) const;
  void ListRayPairs(const LayerProjection& a, const LayerProjection& b);

  LightFieldGeometry geometry_;
  int layer_[2];
  Side side_[2];
  std::vector<float> count_;  // [pair]: its ray-channels
  // [view][ray][rgb]: the pair the ray-channel reads (kNoPair: it misses
  // either layer), so that binning streams (r and this) and scatters.
  static constexpr uint32_t kNoPair = UINT32_MAX;
  std::vector<uint32_t> ray_pair_;
  double rays_ = 0;
};

}  // namespace layerlab
