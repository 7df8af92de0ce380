#include "layerlab/systems/ghosts.h"

#include <algorithm>
#include <numeric>

namespace layerlab {

GhostedDisplay WithGhosts(const DisplaySystem& system) {
  GhostedDisplay g{system, {}};
  g.pattern_of.resize(system.layers.size());
  std::iota(g.pattern_of.begin(), g.pattern_of.end(), 0);
  if (system.ghosts.empty()) return g;
  DisplaySystem& s = g.system;
  for (const Ghost& ghost : system.ghosts) {
    const Branch& shown = system.branches[ghost.branch];
    Branch branch = shown;
    branch.name = ghost.name;
    branch.optics_efficiency = ghost.optics_efficiency;
    branch.efficiency = ghost.efficiency;
    branch.layers.clear();
    for (size_t k = 0; k < ghost.layers.size(); ++k) {
      VirtualLayer layer = ghost.layers[k];
      layer.branch = static_cast<int>(s.branches.size());
      branch.layers.push_back(static_cast<int>(s.layers.size()));
      s.layers.push_back(std::move(layer));
      g.pattern_of.push_back(shown.layers[k]);
    }
    s.branches.push_back(std::move(branch));
  }
  s.ghosts.clear();
  // Farthest first again, as every display's layers are.
  std::vector<int> order(s.layers.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return s.layers[a].diopters < s.layers[b].diopters; });
  std::vector<int> new_index(order.size());
  std::vector<VirtualLayer> layers;
  std::vector<int> pattern_of;
  for (size_t i = 0; i < order.size(); ++i) {
    new_index[order[i]] = static_cast<int>(i);
    layers.push_back(std::move(s.layers[order[i]]));
    pattern_of.push_back(g.pattern_of[order[i]]);
  }
  s.layers = std::move(layers);
  g.pattern_of = std::move(pattern_of);
  for (Branch& b : s.branches)
    for (int& k : b.layers) k = new_index[k];
  return g;
}

Patterns GhostedPatterns(const GhostedDisplay& ghosted, const Patterns& patterns) {
  Patterns out;
  out.reserve(ghosted.pattern_of.size());
  for (int k : ghosted.pattern_of) out.push_back(patterns.at(k));
  return out;
}

}  // namespace layerlab
