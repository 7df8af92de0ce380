// What every two-way beam splitter shares: its ports, its fold and the mirror
// flip of what it reflects.
//
// A splitter folded sideways ("fold": "horizontal" or "vertical") has four
// sides: the eye's (A), the transmitted branch straight behind it (C), the
// reflected branch off to the side (B), and the side opposite that (D). From
// A, light goes on to C or B; light returning from C (after a reflection
// behind it) goes back to A or on to D, the port "reflected_from_behind". A
// splitter at normal incidence ("fold": "back", a pancake lens's half mirror
// or reflective polarizer) has only its transmitted side: what it reflects
// returns along the path it came by (systems/compile.cpp walks both).
#pragma once

#include <string>
#include <vector>

#include "layerlab/framework/params.h"

namespace layerlab {

// What light does at a splitter (also the index of its port from the eye's side).
inline constexpr size_t kTransmittedPort = 0;
inline constexpr size_t kReflectedPort = 1;
// The fourth side of a sideways splitter, seen by light returning from its transmitted branch.
inline constexpr size_t kBehindPort = 2;

// A horizontal fold (the reflected branch off to the side) mirrors that
// branch left-right; a vertical fold mirrors it top-bottom; a fold back (at
// normal incidence) mirrors it left-right.
enum class Fold { kHorizontal, kVertical, kBack };

inline std::vector<std::string> SplitterPorts(Fold f) {
  if (f == Fold::kBack) return {"transmitted"};
  return {"transmitted", "reflected", "reflected_from_behind"};
}

// "back" only where `back_allowed` (a splitter: a full mirror at normal incidence would return every ray).
inline Fold ReadFold(Params& p, bool back_allowed) {
  const std::string fold = p.choice("fold",
                                    back_allowed ? std::vector<std::string>{"horizontal", "vertical", "back"}
                                                 : std::vector<std::string>{"horizontal", "vertical"},
                                    "horizontal");
  return fold == "horizontal" ? Fold::kHorizontal : fold == "vertical" ? Fold::kVertical : Fold::kBack;
}
inline bool ReflectedFlipsX(size_t action, Fold f) { return action == kReflectedPort && f != Fold::kVertical; }
inline bool ReflectedFlipsY(size_t action, Fold f) { return action == kReflectedPort && f == Fold::kVertical; }

}  // namespace layerlab
