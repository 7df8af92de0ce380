// thin_lens: an ideal thin lens anywhere on the path: the magnifier that floats
// the panels (paper Eq. 1), a relay lens, a field lens, a diverging lens.
//
// | key            | type   | default   | meaning                                              |
// |----------------|--------|-----------|------------------------------------------------------|
// | focal_length   | length | required  | nonzero; negative for a diverging lens               |
// | clear_aperture | length | unlimited | diameter; a warning names the layers it vignettes    |
// | gap            | length | see meaning | path length from the element before it; the first lens on a path may omit it and sit at the eye's eye_relief |
// | tilt           | refused | none     | an ideal lens is first-order optics, which needs it centred: a tilted lens is a "lens" of real surfaces |
// | decentre       | refused | none     | as tilt                                              |
// | next           | name   | required  | the next element away from the eye                   |
#include <cmath>

#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"

namespace layerlab {
namespace {

class ThinLens final : public LensElement {
 public:
  ThinLens(double f, std::optional<double> aperture) : f_(f), aperture_(aperture) {}
  double focal_length() const override { return f_; }
  std::optional<double> clear_aperture() const override { return aperture_; }

 private:
  double f_;
  std::optional<double> aperture_;
};

std::unique_ptr<Element> MakeThinLens(Params& p) {
  double f = p.quantity("focal_length", Dimension::kLength);
  if (f == 0) p.fail("focal_length", "a thin lens needs a nonzero focal length (0 would be infinite power)");
  if (std::abs(f) > 10.0) p.fail("focal_length", "must be at most 10 m either way, got " + FormatFixed(f, 4) + " m");
  std::optional<double> aperture = p.optional_quantity("clear_aperture", Dimension::kLength);
  if (aperture) p.require_range("clear_aperture", *aperture, 0.0, 10.0, true, false);
  for (const char* key : {"tilt", "decentre"})
    if (p.has(key))
      p.fail(key,
             "an ideal thin lens is first-order optics, which needs it centred on the axis; describe a tilted "
             "or decentred lens by its surfaces (type \"lens\", docs/optics.md)");
  return std::make_unique<ThinLens>(f, aperture);
}

}  // namespace

ElementType ThinLensType() { return {"thin_lens", ElementKind::kLens, "ideal thin magnifier lens", MakeThinLens}; }

}  // namespace layerlab
