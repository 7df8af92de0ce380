// What every two-way beam splitter shares: its ports and the mirror flip of
// its reflected branch.
#pragma once

#include <string>
#include <vector>

#include "layerlab/framework/params.h"

namespace layerlab {

inline constexpr size_t kTransmittedPort = 0;
inline constexpr size_t kReflectedPort = 1;

inline std::vector<std::string> SplitterPorts() { return {"transmitted", "reflected"}; }

// A horizontal fold (the reflected branch off to the side) mirrors that
// branch left-right; a vertical fold mirrors it top-bottom.
enum class Fold { kHorizontal, kVertical };

inline Fold ReadFold(Params& p) {
  return p.choice("fold", {"horizontal", "vertical"}, "horizontal") == "horizontal" ? Fold::kHorizontal
                                                                                    : Fold::kVertical;
}
inline bool ReflectedFlipsX(size_t port, Fold f) { return port == kReflectedPort && f == Fold::kHorizontal; }
inline bool ReflectedFlipsY(size_t port, Fold f) { return port == kReflectedPort && f == Fold::kVertical; }

}  // namespace layerlab
