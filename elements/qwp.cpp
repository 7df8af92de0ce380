// qwp: a quarter-wave plate: at 45 deg to a linear polarization it makes it
// circular, and a circular one linear; twice over it is a half-wave plate. A
// real plate is a quarter wave only at its design wavelength: a zero-order
// plate of order m has retardance (m + 1/4) 2 pi lambda0 / lambda
// (elements/wave_plate.h).
//
// | key               | type                       | default   | meaning                      |
// |-------------------|----------------------------|-----------|------------------------------|
// | fast_axis         | angle                      | 45 deg    | from eye-space x             |
// | design_wavelength | length                     | 550 nm    | where the retardance is pi/2 |
// | order             | integer                    | 0         | multi-order plates are more chromatic |
// | achromatic        | boolean                    | false     | retardance pi/2 at every wavelength |
// | transmittance     | fraction, [r,g,b] or table | 1         | intensity transmittance      |
// | gap               | length                     | see thin_lens | path length from the element before it |
// | next              | name                       | required  | toward the panels            |
#include "layerlab/elements/registry.h"
#include "layerlab/elements/wave_plate.h"

namespace layerlab {

ElementType QwpType() {
  return {"qwp", ElementKind::kInlineOptic, "quarter-wave plate (retarder)",
          [](Params& p) { return MakeWavePlate(p, 0.25); }};
}

}  // namespace layerlab
