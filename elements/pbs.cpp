// pbs: a polarizing beam splitter. It transmits p (along its p axis) and
// reflects s, with wavelength-dependent efficiencies and leakage.
//
// | key             | type                       | default    | meaning                          |
// |-----------------|----------------------------|------------|----------------------------------|
// | transmittance_p | fraction, [r,g,b] or table | 1          | Tp (tables: see spectral.h)      |
// | reflectance_s   | fraction, [r,g,b] or table | 1          | Rs                               |
// | transmittance_s | fraction, [r,g,b] or table | 0          | Ts (leakage)                     |
// | reflectance_p   | fraction, [r,g,b] or table | 0          | Rp (leakage)                     |
// | p_axis          | angle                      | 0 deg      | p direction, from eye-space x    |
// | fold            | horizontal, vertical, back | horizontal | as for half_mirror; back: a reflective polarizer at normal incidence |
// | gap             | length                     | see thin_lens | path length from the element before it |
// | transmitted     | name or null               | required   | branch straight behind           |
// | reflected       | name or null               | required, none with fold back | branch off to the side |
// | reflected_from_behind | name or null         | nothing    | as for half_mirror               |
#include <cmath>

#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"
#include "layerlab/elements/spectral.h"
#include "layerlab/elements/splitter_ports.h"

namespace layerlab {
namespace {

class PolarizingBeamSplitter final : public CombinerElement {
 public:
  PolarizingBeamSplitter(Rgb tp, Rgb rs, Rgb ts, Rgb rp, double axis, Fold fold)
      : tp_(tp), rs_(rs), ts_(ts), rp_(rp), axis_(axis), fold_(fold) {}
  std::vector<std::string> output_ports() const override { return SplitterPorts(fold_); }
  std::vector<std::string> optional_ports() const override { return {"reflected_from_behind"}; }
  bool polarizing() const override { return true; }
  bool flips_x(size_t action) const override { return ReflectedFlipsX(action, fold_); }
  bool flips_y(size_t action) const override { return ReflectedFlipsY(action, fold_); }
  bool reflects_back() const override { return fold_ == Fold::kBack; }

  void transfer(size_t action, Light& light) const override {
    const Rgb& p_eff = action == kReflectedPort ? rp_ : tp_;
    const Rgb& s_eff = action == kReflectedPort ? rs_ : ts_;
    double c = std::cos(axis_), s = std::sin(axis_);
    for (int k = 0; k < 3; ++k) {
      ChannelLight& ch = light[k];
      if (!ch.polarized) {
        ch.intensity *= 0.5 * (p_eff[k] + s_eff[k]);
        continue;
      }
      // Components along p and s, scaled by their amplitude efficiencies.
      Complex ep = (c * ch.field.x + s * ch.field.y) * std::sqrt(p_eff[k]);
      Complex es = (-s * ch.field.x + c * ch.field.y) * std::sqrt(s_eff[k]);
      ch.field = {c * ep - s * es, s * ep + c * es};
    }
  }

 private:
  Rgb tp_, rs_, ts_, rp_;
  double axis_;
  Fold fold_;
};

std::unique_ptr<Element> MakePbs(Params& p) {
  Rgb tp = ReadSpectralFraction(p, "transmittance_p", 1.0);
  Rgb rs = ReadSpectralFraction(p, "reflectance_s", 1.0);
  Rgb ts = ReadSpectralFraction(p, "transmittance_s", 0.0);
  Rgb rp = ReadSpectralFraction(p, "reflectance_p", 0.0);
  for (int c = 0; c < 3; ++c) {
    if (tp[c] + rp[c] > 1.0 + 1e-12)
      p.fail("reflectance_p", std::string("Tp + Rp exceeds 1 in channel ") + kChannelNames[c]);
    if (ts[c] + rs[c] > 1.0 + 1e-12)
      p.fail("transmittance_s", std::string("Ts + Rs exceeds 1 in channel ") + kChannelNames[c]);
  }
  double axis = p.quantity("p_axis", Dimension::kAngle, 0.0);
  return std::make_unique<PolarizingBeamSplitter>(tp, rs, ts, rp, axis, ReadFold(p, true));
}

}  // namespace

ElementType PbsType() { return {"pbs", ElementKind::kCombiner, "polarizing beam splitter", MakePbs}; }

}  // namespace layerlab
