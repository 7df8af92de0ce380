// thin_lens: the main (magnifier) lens that floats the panels (paper Eq. 1).
//
// | key            | type   | default   | meaning                                    |
// |----------------|--------|-----------|--------------------------------------------|
// | focal_length   | length | required  | f > 0                                      |
// | clear_aperture | length | unlimited | diameter; bounds the vignetting-free field |
// | next           | name   | required  | a combiner, an in-line optic or a panel    |
#include "elements/element.h"
#include "elements/registry.h"

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
  p.require_range("focal_length", f, 0.0, 10.0, true, false);
  std::optional<double> aperture = p.optional_quantity("clear_aperture", Dimension::kLength);
  if (aperture) p.require_range("clear_aperture", *aperture, 0.0, 10.0, true, false);
  return std::make_unique<ThinLens>(f, aperture);
}

}  // namespace

ElementType ThinLensType() {
  return {"thin_lens", ElementKind::kLens, "ideal thin magnifier lens", MakeThinLens};
}

}  // namespace layerlab
