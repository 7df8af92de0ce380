// hwp: a half-wave plate, rotating linear polarization by twice the angle
// between it and the fast axis. A real plate is a half wave only at its design
// wavelength: a zero-order plate of order m has retardance
// (2m + 1) pi lambda0 / lambda (elements/wave_plate.h).
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
#include "layerlab/elements/registry.h"
#include "layerlab/elements/wave_plate.h"

namespace layerlab {

ElementType HwpType() {
  return {"hwp", ElementKind::kInlineOptic, "half-wave plate (retarder)",
          [](Params& p) { return MakeWavePlate(p, 0.5); }};
}

}  // namespace layerlab
