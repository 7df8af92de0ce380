// half_mirror: a polarization-blind beam splitter combining two branches, or
// at normal incidence a partial mirror that light passes more than once (a
// pancake lens's curved half mirror, a birdbath's combiner).
//
// | key           | type                | default    | meaning                                     |
// |---------------|---------------------|------------|---------------------------------------------|
// | reflectance   | fraction or [r,g,b] | 0.5        | toward the eye from the reflected branch    |
// | transmittance | fraction or [r,g,b] | 0.5        | toward the eye from the transmitted branch  |
// | fold          | horizontal, vertical, back | horizontal | plane of the fold; a horizontal fold mirrors the reflected branch left-right; back: at normal incidence, reflecting back along the path |
// | focal_length  | length              | flat       | of its reflection, for light meeting its face toward the eye (concave: positive); the other face reflects with -f |
// | gap           | length              | see thin_lens | path length from the element before it   |
// | transmitted   | name or null        | required   | the branch straight behind the mirror; null: nothing there |
// | reflected     | name or null        | required, none with fold back | the branch off to the side |
// | reflected_from_behind | name or null | nothing    | seen by light returning from the transmitted branch (elements/splitter_ports.h) |
#include <cmath>

#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"
#include "layerlab/elements/splitter_ports.h"

namespace layerlab {
namespace {

class HalfMirror final : public CombinerElement {
 public:
  HalfMirror(Rgb r, Rgb t, Fold fold, double power) : r_(r), t_(t), fold_(fold), power_(power) {}
  std::vector<std::string> output_ports() const override { return SplitterPorts(fold_); }
  std::vector<std::string> optional_ports() const override { return {"reflected_from_behind"}; }
  bool flips_x(size_t action) const override { return ReflectedFlipsX(action, fold_); }
  bool flips_y(size_t action) const override { return ReflectedFlipsY(action, fold_); }
  bool reflects_back() const override { return fold_ == Fold::kBack; }
  double reflection_power() const override { return power_; }
  void transfer(size_t action, Light& light) const override {
    const Rgb& eff = action == kReflectedPort ? r_ : t_;
    for (int c = 0; c < 3; ++c) light[c].attenuate(eff[c]);
  }

 private:
  Rgb r_, t_;
  Fold fold_;
  double power_;
};

std::unique_ptr<Element> MakeHalfMirror(Params& p) {
  Rgb r = p.fraction_rgb("reflectance", 0.5);
  Rgb t = p.fraction_rgb("transmittance", 0.5);
  for (int c = 0; c < 3; ++c)
    if (r[c] + t[c] > 1.0 + 1e-12)
      p.fail("transmittance", "reflectance + transmittance is " + FormatFixed(r[c] + t[c], 4) + " in channel " +
                                  kChannelNames[c] + "; a passive mirror cannot exceed 1");
  std::optional<double> f = p.optional_quantity("focal_length", Dimension::kLength);
  if (f && *f == 0) p.fail("focal_length", "a curved mirror needs a nonzero focal length; leave it out for a flat one");
  if (f && std::abs(*f) > 10.0)
    p.fail("focal_length", "must be at most 10 m either way, got " + FormatFixed(*f, 4) + " m");
  return std::make_unique<HalfMirror>(r, t, ReadFold(p, true), f ? 1.0 / *f : 0.0);
}

}  // namespace

ElementType HalfMirrorType() {
  return {"half_mirror", ElementKind::kCombiner, "partially reflecting beam splitter", MakeHalfMirror};
}

}  // namespace layerlab
