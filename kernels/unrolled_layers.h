// The hot path's kernels are unrolled over the layers of a branch: each is a
// class template over the layer count L with a static Run, compiled for L = 1
// to kMaxOneTapLayers, and ForLayerCount picks the instantiation at run time.
// One switch for every kernel and both builds of the row kernels (the AVX2
// build's Run carries its target attribute; this switch needs none).
#pragma once

#include <utility>

namespace layerlab {

// Branches of up to this many layers take the fast path (one_tap_view.h).
constexpr int kMaxOneTapLayers = 4;

// Kernel<layers>::Run(args...) for 1 <= layers <= kMaxOneTapLayers; nothing otherwise.
template <template <int> class Kernel, class... Args>
inline void ForLayerCount(int layers, Args&&... args) {
  static_assert(kMaxOneTapLayers == 4, "one case per layer count");
  switch (layers) {
    case 1:
      return Kernel<1>::Run(std::forward<Args>(args)...);
    case 2:
      return Kernel<2>::Run(std::forward<Args>(args)...);
    case 3:
      return Kernel<3>::Run(std::forward<Args>(args)...);
    case 4:
      return Kernel<4>::Run(std::forward<Args>(args)...);
  }
}

}  // namespace layerlab
