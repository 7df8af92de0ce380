// The eye's generalized pupil function (Goodman, Introduction to Fourier
// Optics, 6.4) and what it images: P(u) = A(u) exp(i k Phi(u)), k = 2 pi / lambda,
// u in m from the pupil's centre in its own plane (x right, y up):
//   A: 1 inside the aperture (round of diameter D, or square of side D),
//      times the Stiles-Crawford apodization 10^(-rho r^2 / 2) when rho > 0
//      (the intensity 10^(-rho r^2), r in mm; rho = 0.05 / mm^2 is the mean of
//      Applegate & Lakshminarayanan 1993, J. Opt. Soc. Am. A 10:1611);
//   Phi = V r^2 / 2 - W(u): a vergence error V in diopters (the object's
//      vergence minus the eye's focus; positive: the object nearer) and the
//      wavefront aberration W (elements/wavefront.h).
// The signs make the pupil-sampled retina's rays (retina/retina.h: a ray from
// u reads the scene at tan(a) + u V - grad W(u)) the geometric limit of the
// waves: the point-spread function at retinal angle a (tan units) is
//   PSF(a) = |integral P(u) exp(+i k u.a) du|^2 / (lambda^2 integral |P|^2),
// a density per rad^2 whose integral is 1, and the optical transfer function,
// the PSF's Fourier transform at f cycles per radian,
//   OTF(f) = integral P(u + lambda f / 2) P*(u - lambda f / 2) du / integral |P|^2
// (the autocorrelation of P; with a vergence error Hopkins' defocused OTF).
#pragma once

#include <complex>
#include <vector>

#include "layerlab/elements/element.h"
#include "layerlab/elements/wavefront.h"

namespace layerlab {

struct PupilOptics {
  PupilShape shape = PupilShape::kRound;
  double diameter_m = 0;                   // m, the round pupil's diameter or the square's side
  double wavelength_m = 555e-9;            // m
  Wavefront wavefront;                     // W; empty: aberration free
  double vergence_diopters = 0;            // V, D
  double stiles_crawford_rho_per_mm2 = 0;  // rho; 0: no apodization
};

// The eye's pupil (shape, diameter, wavefront, Stiles-Crawford) at `wavelength_m`, no vergence error.
PupilOptics PupilOpticsOf(const EyeModel& eye, double wavelength_m);

// P(x, y), 0 outside the aperture.
std::complex<double> PupilFunctionAt(const PupilOptics& p, double x_m, double y_m);

// integral |P|^2 over the pupil, m^2, in closed form (the apodized disk or square).
double PupilEnergy(const PupilOptics& p);

// P's mean over the square cell of side `cell` centred on (x, y), from sub x sub points.
std::complex<double> PupilCellMean(const PupilOptics& p, double x_m, double y_m, double cell_m, int sub);

// The largest |grad Phi| over the pupil (tan units): the phase's steepest
// slope, from the vergence error and a scan of W's slope.
double PupilPhaseSlope(const PupilOptics& p);

// The OTF at (fx, fy) cycles per radian by the autocorrelation above, a
// midpoint sum over `samples` x `samples` cells of the pupil's bounding
// square (each cell's P averaged over 2 x 2 points, for the aperture's edge).
std::complex<double> PupilOtf(const PupilOptics& p, double fx, double fy, int samples = 512);

// The PSF on `size` x `size` samples `spacing_rad` apart, row 0 at the top
// (+y), sample (size / 2, size / 2) at a = 0: |FFT(P)|^2 of P's cell means
// (4 x 4 points, so the aperture's edge cells count their share) at
// du = lambda / (N spacing) on N x N points, N >= 4 size, normalized by
// integral |P|^2 in closed form (so the PSF's sum is a check of energy, not
// its definition). The cell means filter P by a box of side du: k samples
// out the PSF is lowered by sinc^2(k / N), at most 5 % at the crop's edge. The sampling rule: the PSF does
// not alias when the OTF's support |f| <= D / lambda lies within the grid's
// Nyquist frequency, spacing <= lambda / (2 D) (a coarser spacing is refused,
// naming it); N is chosen so that P has at least 64 samples across the
// pupil and at least 4 per wave of its phase (du |grad Phi| <= lambda / 4).
struct PointSpread {
  int size = 0;
  double spacing_rad = 0;
  std::vector<double> density;  // per rad^2
  double at(int row, int col) const { return density[size_t(row) * size + col]; }
};
PointSpread PupilPointSpread(const PupilOptics& p, double spacing_rad, int size);

// The PSF's aliasing limit above: lambda / (2 D), rad.
double PsfSpacingLimit(const PupilOptics& p);

}  // namespace layerlab

namespace layerlab {

// The OTF split among parts of the pupil, on a lattice of frequencies: the
// autocorrelation above as a sum over pairs of cells a, b of an n x n grid
// over the pupil's bounding square (cell h = D / n, each cell's P its mean
// over 2 x 2 points), a - b = m for the lattice frequency f = m h / lambda,
// m in [-reach, reach]^2. The pair's term is shared among the parts that own
// its midpoint, each share times exp(+i k (m h).tilt) of its tilt (the
// slope of the phase the caller applies as a shift; tilts[share.tilt]). Midpoint
// (a + b) / 2 has half-cell index q = a + b in [0, 2n - 2]^2, at
// (-D / 2 + (q + 1) h / 2) from the centre, qy counted from the top (+y);
// shares are indexed [qy * (2n - 1) + qx], their weights summing to 1.
// Normalized by sum |P|^2, so the parts sum to the OTF and to 1 at f = 0.
struct OtfLattice {
  int reach = 0, parts = 0;
  double step_cycles_per_rad = 0;            // h / lambda
  std::vector<std::complex<double>> values;  // [part][(my + reach) (2 reach + 1) + mx + reach], my toward +y
  std::complex<double> value(int part, int mx, int my) const {
    return values[(size_t(part) * (2 * reach + 1) + (my + reach)) * (2 * reach + 1) + mx + reach];
  }
  // Bilinear between lattice points; 0 beyond the lattice.
  std::complex<double> at(int part, double fx, double fy) const;
};
struct PupilTilt {
  double x = 0, y = 0;  // tan units
};
struct MidpointShare {
  int part = 0;
  double weight = 1;
  int tilt = -1;  // into the lattice's tilts; -1: none
};
OtfLattice PupilOtfLattice(const PupilOptics& p, int n, int reach, int parts,
                           const std::vector<std::vector<MidpointShare>>& shares,
                           const std::vector<PupilTilt>& tilts = {});

}  // namespace layerlab
