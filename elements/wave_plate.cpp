#include "layerlab/elements/wave_plate.h"

#include <numbers>

#include "layerlab/elements/spectral.h"

namespace layerlab {
namespace {

class WavePlate final : public InlineOpticElement {
 public:
  WavePlate(double axis, std::array<double, 3> retardance, Rgb transmittance)
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

}  // namespace

std::unique_ptr<Element> MakeWavePlate(Params& p, double waves) {
  double axis = p.quantity("fast_axis", Dimension::kAngle, std::numbers::pi / 4);
  double design = p.quantity("design_wavelength", Dimension::kLength, 550e-9);
  p.require_range("design_wavelength", design, 100e-9, 3e-6, false, false);
  int64_t order = p.integer("order", 0, 100, 0);
  bool achromatic = p.boolean("achromatic", false);
  std::array<double, 3> retardance{};
  for (int c = 0; c < 3; ++c)
    retardance[c] = achromatic ? 2 * std::numbers::pi * waves
                               : 2 * std::numbers::pi * (order + waves) * design / kChannelWavelengths[c];
  return std::make_unique<WavePlate>(axis, retardance, ReadSpectralFraction(p, "transmittance", 1.0));
}

}  // namespace layerlab
