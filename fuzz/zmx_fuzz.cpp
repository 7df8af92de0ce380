// .zmx bytes -> Prescription -> .zmx text -> Prescription. layerlab::Error is
// the documented refusal of the first read. What it accepts must write and
// read back to the same prescription, field by field (zmx_format.h); a
// difference, a crash, a sanitizer report or another exception is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "layerlab/framework/error.h"
#include "layerlab/fuzz/fuzz_util.h"
#include "layerlab/lenses/zmx_format.h"

namespace {

bool Same(const layerlab::lenses::Prescription& a, const layerlab::lenses::Prescription& b) {
  if (a.material_before != b.material_before || a.stop_surface != b.stop_surface ||
      a.surfaces.size() != b.surfaces.size() || !a.placements.empty() || !b.placements.empty()) {
    return false;
  }
  for (size_t i = 0; i < a.surfaces.size(); ++i) {
    const auto& s = a.surfaces[i];
    const auto& t = b.surfaces[i];
    if (s.shape.curvature_per_m != t.shape.curvature_per_m || s.shape.conic != t.shape.conic ||
        s.shape.even_asphere != t.shape.even_asphere || s.shape.fresnel_pitch_m != t.shape.fresnel_pitch_m ||
        s.shape.semi_diameter_m != t.shape.semi_diameter_m || s.material != t.material ||
        s.thickness_m != t.thickness_m) {
      return false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  layerlab::lenses::Prescription read;
  try {
    read = layerlab::lenses::ReadZmx(layerlab::fuzz::AsString(data, size), "fuzz.zmx");
  } catch (const layerlab::Error&) {
    return 0;
  }
  const std::string written = layerlab::lenses::WriteZmx(read, "fuzz");  // an Error here is a finding
  if (!Same(layerlab::lenses::ReadZmx(written, "written.zmx"), read)) std::abort();
  return 0;
}
