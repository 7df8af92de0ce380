#include "layerlab/systems/ghosts.h"

#include <numeric>

#include "layerlab/systems/layer_order.h"

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
  std::vector<int> pattern_of;  // farthest first again, as every display's layers are
  for (int before : SortLayersFarthestFirst(&s)) pattern_of.push_back(g.pattern_of[before]);
  g.pattern_of = std::move(pattern_of);
  return g;
}

Patterns GhostedPatterns(const GhostedDisplay& ghosted, const Patterns& patterns) {
  Patterns out;
  out.reserve(ghosted.pattern_of.size());
  for (int k : ghosted.pattern_of) out.push_back(patterns.at(k));
  return out;
}

}  // namespace layerlab
