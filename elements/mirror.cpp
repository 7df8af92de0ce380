// mirror: a fold mirror on the path, flat or curved (a birdbath's concave
// combiner, a curved relay mirror). In the path unfolded from the eye it
// reverses one eye-space axis (as a combiner's reflected port does) and, when
// curved, acts as a thin lens of focal length f = R / 2.
//
// | key          | type                | default    | meaning                                                |
// |--------------|---------------------|------------|--------------------------------------------------------|
// | focal_length | length              | flat       | nonzero; positive for a concave (converging) mirror     |
// | reflectance  | fraction or [r,g,b] | 1          | toward the eye                                          |
// | fold         | horizontal, vertical| horizontal | plane of the fold; a horizontal fold mirrors left-right |
// | gap          | length              | see thin_lens | path length from the element before it              |
// | next         | name                | required   | the next element away from the eye                     |
#include <cmath>

#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"
#include "layerlab/elements/splitter_ports.h"

namespace layerlab {
namespace {

class Mirror final : public MirrorElement {
 public:
  Mirror(std::optional<double> f, Rgb reflectance, Fold fold) : f_(f), reflectance_(reflectance), fold_(fold) {}
  std::optional<double> focal_length() const override { return f_; }
  bool flips_x() const override { return fold_ == Fold::kHorizontal; }
  bool flips_y() const override { return fold_ == Fold::kVertical; }
  void transfer(Light& light) const override {
    for (int c = 0; c < 3; ++c) light[c].attenuate(reflectance_[c]);
  }

 private:
  std::optional<double> f_;
  Rgb reflectance_;
  Fold fold_;
};

std::unique_ptr<Element> MakeMirror(Params& p) {
  std::optional<double> f = p.optional_quantity("focal_length", Dimension::kLength);
  if (f && *f == 0)
    p.fail("focal_length", "a curved mirror needs a nonzero focal length; leave it out for a flat mirror");
  if (f && std::abs(*f) > 10.0)
    p.fail("focal_length", "must be at most 10 m either way, got " + FormatFixed(*f, 4) + " m");
  Rgb reflectance = p.fraction_rgb("reflectance", 1.0);
  for (double r : reflectance)
    if (!(r > 0)) p.fail("reflectance", "a mirror that reflects no light shows nothing behind it");
  return std::make_unique<Mirror>(f, reflectance, ReadFold(p, false));
}

}  // namespace

ElementType MirrorType() {
  return {"mirror", ElementKind::kMirror, "fold mirror, flat or curved (f = R/2)", MakeMirror};
}

}  // namespace layerlab
