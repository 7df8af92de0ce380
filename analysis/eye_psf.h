// `layerlab psf`: the eye's point-spread function and modulation transfer by
// its pupil function (eye/pupil_function.h) at a set of vergence errors, per
// channel, beside what the geometric path computes (the pupil samples' rays
// times the diffraction-limited MTF, diffraction "mtf"): where the two
// differ, the retinal images need diffraction "wave" (docs/eye-model.md).
#pragma once

#include <string>
#include <vector>

#include "layerlab/elements/element.h"
#include "layerlab/framework/exr_image.h"

namespace layerlab {

struct EyePsfOptions {
  std::vector<double> vergence_diopters = {0, 0.1, 0.25, 0.5, 1.0};  // D: object vergence minus focus
  std::vector<double> frequencies_cpd = {2, 5, 10, 20, 30, 60};
  int psf_size = 255;  // samples per side of each PSF image
  // rad per PSF sample; 0: half the aliasing limit lambda / (2 D) of the shortest wavelength.
  double psf_spacing_rad = 0;
};

// One frequency along x of one channel at one vergence error. The retina's is measured on a 1 deg strip
// sampled at a quarter of the highest frequency's period (at most 0.01 deg), over its middle half.
struct EyeMtfRow {
  int channel = 0;
  double wavelength_m = 0, vergence_diopters = 0, frequency_cpd = 0;
  double wave = 0;       // Re OTF of the pupil function (signed: a phase reversal is negative)
  double retina = 0;     // Re OTF the wave-optics retina gives a cosine grating on a plane (retina/eye_optics.h)
  double geometric = 0;  // Re of the pupil samples' ray MTF times the diffraction-limited MTF
};

// Every channel x vergence x frequency; refuses a pinhole pupil and bad values, naming them.
std::vector<EyeMtfRow> EyeMtfTable(const EyeModel& eye, const EyePsfOptions& o);

// The PSF at one vergence error: per channel its density per sr at that channel's wavelength.
Image EyePsfImage(const EyeModel& eye, const EyePsfOptions& o, double vergence_diopters);

// mtf.csv, mtf.svg (green channel: wave solid, geometric dashed, one colour per vergence) and, per
// vergence, psf_<V>D.exr and a PNG scaled to its peak, into `folder` (which exists).
void WriteEyePsf(const EyeModel& eye, const EyePsfOptions& o, const std::string& folder);

}  // namespace layerlab
