// lens_array: a microlens array, the lenslets of an integral-imaging
// near-eye display (Lanman and Luebke 2013). Each ray passes the lenslet it
// meets, as a thin lens centred on that lenslet (systems/lenslet_map.h); the
// array is centred on the axis.
//
// | key          | type              | default  | meaning                                              |
// |--------------|-------------------|----------|------------------------------------------------------|
// | focal_length | length            | required | each lenslet's; nonzero                               |
// | pitch        | length            | required | lenslet centre to centre                              |
// | count        | [cols, rows]      | required | lenslets across (per row) and down, 1-4096 each       |
// | fill_factor  | fraction          | 1        | each lenslet's clear aperture over its cell; rays between apertures are lost |
// | lattice      | square, hexagonal | square   | hexagonal: rows sqrt(3)/2 pitch apart, every other one shifted by half a pitch |
// | gap          | length            | see thin_lens | path length from the element before it          |
// | next         | name              | required | the next element away from the eye                   |
#include <cmath>

#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"

namespace layerlab {
namespace {

class LensArray final : public LensElement {
 public:
  LensArray(double f, LensArraySpec array) : f_(f), array_(array) {}
  double focal_length() const override { return f_; }
  std::optional<double> clear_aperture() const override { return std::nullopt; }
  const LensArraySpec* lens_array() const override { return &array_; }

 private:
  double f_;
  LensArraySpec array_;
};

std::unique_ptr<Element> MakeLensArray(Params& p) {
  const double f = p.quantity("focal_length", Dimension::kLength);
  if (f == 0) p.fail("focal_length", "a lenslet needs a nonzero focal length (0 would be infinite power)");
  p.require_range("focal_length", std::abs(f), 1e-6, 1.0, false, false);
  LensArraySpec a;
  a.pitch_m = p.quantity("pitch", Dimension::kLength);
  p.require_range("pitch", a.pitch_m, 1e-6, 0.1, false, false);
  const auto count = p.integer_pair("count", 1, 4096);
  a.cols = static_cast<int>(count[0]), a.rows = static_cast<int>(count[1]);
  a.fill = p.quantity("fill_factor", Dimension::kFraction, 1.0);
  p.require_range("fill_factor", a.fill, 0.0, 1.0, true, false);  // 0: lenslets of no aperture pass no light
  a.hexagonal = p.choice("lattice", {"square", "hexagonal"}, "square") == "hexagonal";
  return std::make_unique<LensArray>(f, a);
}

}  // namespace

ElementType LensArrayType() {
  return {"lens_array", ElementKind::kLens, "microlens array (integral imaging)", MakeLensArray};
}

}  // namespace layerlab
