// hwp: a half-wave plate, rotating linear polarization by twice the angle
// between it and the fast axis. A real plate is a half wave only at its design
// wavelength: a zero-order plate of order m has retardance
// (2m + 1) pi lambda0 / lambda (the birefringence's own dispersion ignored).
//
// | key               | type                       | default   | meaning                      |
// |-------------------|----------------------------|-----------|------------------------------|
// | fast_axis         | angle                      | 45 deg    | from eye-space x             |
// | design_wavelength | length                     | 550 nm    | where the retardance is pi   |
// | order             | integer                    | 0         | multi-order plates are more chromatic |
// | achromatic        | boolean                    | false     | retardance pi at every wavelength |
// | transmittance     | fraction, [r,g,b] or table | 1         | intensity transmittance      |
// | gap               | length                     | see thin_lens | path length from the element before it |
// | next              | name                       | required  | toward the panels            |
#include <numbers>

#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"
#include "layerlab/elements/spectral.h"

namespace layerlab {
namespace {

class HalfWavePlate final : public InlineOpticElement {
 public:
  HalfWavePlate(double axis, std::array<double, 3> retardance, Rgb transmittance)
      : axis_(axis), retardance_(retardance), transmittance_(transmittance) {}
  bool polarizing() const override { return true; }

  void transfer(Light& light) const override {
    for (int c = 0; c < 3; ++c) {
      if (light[c].polarized) light[c].field = Retarder(retardance_[c], axis_) * light[c].field;
      light[c].attenuate(transmittance_[c]);
    }
  }

 private:
  double axis_;
  std::array<double, 3> retardance_;
  Rgb transmittance_;
};

std::unique_ptr<Element> MakeHwp(Params& p) {
  double axis = p.quantity("fast_axis", Dimension::kAngle, std::numbers::pi / 4);
  double design = p.quantity("design_wavelength", Dimension::kLength, 550e-9);
  p.require_range("design_wavelength", design, 100e-9, 3e-6, false, false);
  int64_t order = p.integer("order", 0, 100, 0);
  bool achromatic = p.boolean("achromatic", false);
  std::array<double, 3> retardance{};
  for (int c = 0; c < 3; ++c)
    retardance[c] =
        achromatic ? std::numbers::pi : (2.0 * order + 1.0) * std::numbers::pi * design / kChannelWavelengths[c];
  return std::make_unique<HalfWavePlate>(axis, retardance, ReadSpectralFraction(p, "transmittance", 1.0));
}

}  // namespace

ElementType HwpType() { return {"hwp", ElementKind::kInlineOptic, "half-wave plate (retarder)", MakeHwp}; }

}  // namespace layerlab
