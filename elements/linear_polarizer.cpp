// linear_polarizer: an absorbing polarizer in the path: it passes the field's
// component along its axis (times the square root of its transmittance) and
// absorbs the rest; natural light leaves it polarized along the axis, at half
// its intensity times the transmittance. With a quarter-wave plate at 45 deg
// behind it (toward the eye) it is a circular polarizer.
//
// | key           | type                       | default | meaning                          |
// |---------------|----------------------------|---------|----------------------------------|
// | axis          | angle                      | 0 deg   | its transmission axis, from eye-space x |
// | transmittance | fraction, [r,g,b] or table | 1       | of light polarized along the axis |
// | gap           | length                     | see thin_lens | path length from the element before it |
// | next          | name                       | required | toward the panels               |
#include <cmath>

#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"
#include "layerlab/elements/spectral.h"

namespace layerlab {
namespace {

class LinearPolarizer final : public InlineOpticElement {
 public:
  LinearPolarizer(double axis, Rgb transmittance) : axis_(axis), transmittance_(transmittance) {}
  bool polarizing() const override { return true; }

  void transfer(Light& light) const override {
    const Jones along = LinearPolarization(axis_);
    for (int c = 0; c < 3; ++c) {
      ChannelLight& ch = light[c];
      const double amplitude = ch.polarized ? 0 : std::sqrt(0.5 * ch.intensity);
      const Complex projected = ch.polarized ? along.x * ch.field.x + along.y * ch.field.y : Complex(amplitude, 0);
      ch.polarized = true;
      ch.field = {projected * along.x, projected * along.y};
      ch.attenuate(transmittance_[c]);
    }
  }

 private:
  double axis_;
  Rgb transmittance_;
};

std::unique_ptr<Element> MakeLinearPolarizer(Params& p) {
  const double axis = p.quantity("axis", Dimension::kAngle, 0.0);
  p.require_range("axis", axis, -3.2, 3.2, false, false);
  return std::make_unique<LinearPolarizer>(axis, ReadSpectralFraction(p, "transmittance", 1.0));
}

}  // namespace

ElementType LinearPolarizerType() {
  return {"linear_polarizer", ElementKind::kInlineOptic, "absorbing linear polarizer", MakeLinearPolarizer};
}

}  // namespace layerlab
