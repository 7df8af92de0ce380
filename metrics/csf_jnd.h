// A contrast-sensitivity-weighted difference of two luminance images, in
// just-noticeable differences (JND): the difference's contrast against the
// reference's mean luminance L,
//   dC(x) = (Y_test(x) - Y_ref(x)) / L,
// filtered by Barten's contrast sensitivity S(f; L, field) (eye/barten_csf.h)
// at each spatial frequency f of the image, taken as one period of a periodic
// field (FFT),
//   J = F^-1{ S(|f|) F{dC} },
// so that a grating of contrast c at f becomes a grating of amplitude
// c S(f) = c / threshold; then pooled over the pixels by a Minkowski mean
// of exponent beta, scaled so that a full-field grating at its threshold
// scores exactly 1:
//   JND = (mean_x |J(x)|^beta)^(1/beta) / (mean over a period of |sin|^beta)^(1/beta).
// A single grating below its threshold scores below 1 (several, or a
// pattern that is not a grating, may pool above it); a uniform change of
// luminance (f = 0) scores 0, as the CSF has it. The field in Barten's model
// is the image's own extent.
#pragma once

#include "layerlab/metrics/ssim.h"

namespace layerlab {

struct CsfJndOptions {
  double pixel_deg = 1.0 / 60;    // the images' sampling: degrees per pixel, both axes
  double minkowski_exponent = 4;  // beta, >= 1 (beta = 4 is a common choice for spatial pooling)
  // Pooled by a Minkowski mean weighted by this (foveal_weight.h): (sum w |J|^beta / sum w)^(1/beta); null: uniform.
  const Plane* weight = nullptr;
};

// Y in cd/m2 (linear luminance). Throws layerlab::Error naming what is wrong:
// sizes that differ, an empty image, a pixel pitch or a reference mean not
// above 0, a Minkowski exponent below 1, a value negative or not finite.
double CsfJnd(const Plane& reference_cd_m2, const Plane& test_cd_m2, const CsfJndOptions& options = {});

}  // namespace layerlab
