// half_mirror: a polarization-blind beam splitter combining two branches.
//
// | key           | type                | default    | meaning                                     |
// |---------------|---------------------|------------|---------------------------------------------|
// | reflectance   | fraction or [r,g,b] | 0.5        | toward the eye from the reflected branch    |
// | transmittance | fraction or [r,g,b] | 0.5        | toward the eye from the transmitted branch  |
// | fold          | horizontal, vertical| horizontal | plane of the fold; a horizontal fold mirrors the reflected branch left-right |
// | gap           | length              | see thin_lens | path length from the element before it   |
// | transmitted   | name                | required   | the branch straight behind the mirror       |
// | reflected     | name                | required   | the branch off to the side                  |
#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"
#include "layerlab/elements/splitter_ports.h"

namespace layerlab {
namespace {

class HalfMirror final : public CombinerElement {
 public:
  HalfMirror(Rgb r, Rgb t, Fold fold) : r_(r), t_(t), fold_(fold) {}
  std::vector<std::string> output_ports() const override { return SplitterPorts(); }
  bool flips_x(size_t port) const override { return ReflectedFlipsX(port, fold_); }
  bool flips_y(size_t port) const override { return ReflectedFlipsY(port, fold_); }
  void transfer(size_t port, Light& light) const override {
    const Rgb& eff = port == kReflectedPort ? r_ : t_;
    for (int c = 0; c < 3; ++c) light[c].attenuate(eff[c]);
  }

 private:
  Rgb r_, t_;
  Fold fold_;
};

std::unique_ptr<Element> MakeHalfMirror(Params& p) {
  Rgb r = p.fraction_rgb("reflectance", 0.5);
  Rgb t = p.fraction_rgb("transmittance", 0.5);
  for (int c = 0; c < 3; ++c)
    if (r[c] + t[c] > 1.0 + 1e-12)
      p.fail("transmittance", "reflectance + transmittance is " + FormatFixed(r[c] + t[c], 4) + " in channel " +
                                  kChannelNames[c] + "; a passive mirror cannot exceed 1");
  return std::make_unique<HalfMirror>(r, t, ReadFold(p));
}

}  // namespace

ElementType HalfMirrorType() {
  return {"half_mirror", ElementKind::kCombiner, "partially reflecting beam splitter", MakeHalfMirror};
}

}  // namespace layerlab
