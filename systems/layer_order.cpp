#include "layerlab/systems/layer_order.h"

#include <algorithm>
#include <numeric>

namespace layerlab {

std::vector<int> SortLayersFarthestFirst(DisplaySystem* system) {
  std::vector<VirtualLayer>& layers = system->layers;
  std::vector<int> order(layers.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return layers[a].diopters < layers[b].diopters; });
  std::vector<int> new_index(layers.size());
  std::vector<VirtualLayer> sorted;
  sorted.reserve(layers.size());
  for (size_t i = 0; i < order.size(); ++i)
    new_index[order[i]] = static_cast<int>(i), sorted.push_back(std::move(layers[order[i]]));
  layers = std::move(sorted);
  for (Branch& b : system->branches)
    for (int& k : b.layers) k = new_index[k];
  return order;
}

}  // namespace layerlab
