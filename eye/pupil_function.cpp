#include "layerlab/eye/pupil_function.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "layerlab/eye/spectral_filter.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"

namespace layerlab {

PupilOptics PupilOpticsOf(const EyeModel& eye, double wavelength_m) {
  PupilOptics p;
  p.shape = eye.pupil_shape;
  p.diameter_m = eye.pupil_diameter_m;
  p.wavelength_m = wavelength_m;
  p.wavefront = eye.wavefront;
  p.stiles_crawford_rho_per_mm2 = eye.stiles_crawford_rho_per_mm2;
  return p;
}

std::complex<double> PupilFunctionAt(const PupilOptics& p, double x, double y) {
  const double half = 0.5 * p.diameter_m, r2 = x * x + y * y;
  const bool inside = p.shape == PupilShape::kRound ? r2 <= half * half : std::abs(x) <= half && std::abs(y) <= half;
  if (!inside) return 0;
  const double amplitude =
      p.stiles_crawford_rho_per_mm2 > 0 ? std::pow(10.0, -0.5 * p.stiles_crawford_rho_per_mm2 * r2 * 1e6) : 1.0;
  double path = 0.5 * p.vergence_diopters * r2;
  if (!p.wavefront.empty()) path -= WavefrontAt(p.wavefront, x, y);
  return std::polar(amplitude, 2 * std::numbers::pi / p.wavelength_m * path);
}

double PupilPhaseSlope(const PupilOptics& p) {
  const double reach = p.shape == PupilShape::kRound ? 0.5 * p.diameter_m : 0.5 * std::sqrt(2.0) * p.diameter_m;
  double slope = 0;
  if (!p.wavefront.empty()) {
    const int n = 33;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double x = (j - 0.5 * (n - 1)) / (n - 1) * p.diameter_m, y = (i - 0.5 * (n - 1)) / (n - 1) * p.diameter_m;
        if (PupilFunctionAt(p, x, y) == 0.0) continue;
        const WavefrontSlope g = WavefrontSlopeAt(p.wavefront, x, y);
        slope = std::max(slope, std::hypot(g.x - p.vergence_diopters * x, g.y - p.vergence_diopters * y));
      }
  }
  return std::max(slope, std::abs(p.vergence_diopters) * reach);
}

std::complex<double> PupilOtf(const PupilOptics& p, double fx, double fy, int samples) {
  if (!(p.diameter_m > 0)) throw Error("an OTF needs a pupil larger than a pinhole");
  if (samples < 2) throw Error("an OTF needs at least 2 x 2 pupil cells");
  const double sx = p.wavelength_m * fx, sy = p.wavelength_m * fy, cell = p.diameter_m / samples;
  const double half = 0.5 * p.diameter_m;
  std::complex<double> overlap = 0;
  double energy = 0;
  for (int i = 0; i < samples; ++i)
    for (int j = 0; j < samples; ++j)
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
          const double x = -half + (j + 0.25 + 0.5 * b) * cell, y = -half + (i + 0.25 + 0.5 * a) * cell;
          energy += std::norm(PupilFunctionAt(p, x, y));
          if (std::abs(x) + 0.5 * std::abs(sx) > half || std::abs(y) + 0.5 * std::abs(sy) > half) continue;
          overlap += PupilFunctionAt(p, x + 0.5 * sx, y + 0.5 * sy) *
                     std::conj(PupilFunctionAt(p, x - 0.5 * sx, y - 0.5 * sy));
        }
  return overlap / energy;
}

double PsfSpacingLimit(const PupilOptics& p) { return p.wavelength_m / (2 * p.diameter_m); }

double PupilEnergy(const PupilOptics& p) {
  const double half = 0.5 * p.diameter_m;
  const double rho = p.stiles_crawford_rho_per_mm2 * 1e6 * std::log(10.0);  // 10^(-rho r^2) = exp(-rho' r^2), r in m
  if (p.shape == PupilShape::kRound)
    return rho > 0 ? std::numbers::pi * (1 - std::exp(-rho * half * half)) / rho : std::numbers::pi * half * half;
  const double side = rho > 0 ? std::sqrt(std::numbers::pi / rho) * std::erf(half * std::sqrt(rho)) : 2 * half;
  return side * side;
}

std::complex<double> PupilCellMean(const PupilOptics& p, double x, double y, double cell, int sub) {
  std::complex<double> sum = 0;
  for (int a = 0; a < sub; ++a)
    for (int b = 0; b < sub; ++b)
      sum += PupilFunctionAt(p, x + ((b + 0.5) / sub - 0.5) * cell, y + ((a + 0.5) / sub - 0.5) * cell);
  return sum / double(sub * sub);
}

PointSpread PupilPointSpread(const PupilOptics& p, double spacing_rad, int size) {
  if (!(p.diameter_m > 0)) throw Error("a point-spread function needs a pupil larger than a pinhole");
  if (size < 1) throw Error("a point-spread function needs at least one sample");
  const double limit = PsfSpacingLimit(p);
  if (!(spacing_rad > 0) || spacing_rad > limit * (1 + 1e-12))
    throw Error("a point-spread function sampled every " + FormatGeneral(spacing_rad / kRadiansPerDegree * 3600) +
                " arcsec would alias: the OTF of a " + FormatGeneral(p.diameter_m * 1e3) + " mm pupil at " +
                FormatGeneral(p.wavelength_m * 1e9) + " nm reaches D / lambda; sample at most every lambda / (2 D) = " +
                FormatGeneral(limit / kRadiansPerDegree * 3600) + " arcsec");
  const double across = 64 * p.wavelength_m / (p.diameter_m * spacing_rad);
  const double phase = 4 * PupilPhaseSlope(p) / spacing_rad;
  const double wanted = std::max({4.0 * size, across, phase});
  if (wanted > 8192)
    throw Error(
        "a point-spread function would need " + FormatGeneral(wanted) +
        " samples per side (at most 8192): the pupil's phase is too steep or the field too wide for this sampling");
  const int n = FastFftSize(static_cast<int>(std::ceil(wanted)));
  const double du = p.wavelength_m / (n * spacing_rad);
  // P's mean over each cell at signed index J (u = J du), stored at J mod n; +y with the row index.
  std::vector<std::complex<double>> field(size_t(n) * n);
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix) {
      const int jy = iy < n / 2 ? iy : iy - n, jx = ix < n / 2 ? ix : ix - n;
      field[size_t(iy) * n + ix] = PupilCellMean(p, jx * du, jy * du, du, 4);
    }
  // exp(+i k u.a) with u = J du, a = M spacing: exp(+2 pi i J M / n), the inverse transform.
  Fft2d(&field, n, n, true);
  PointSpread psf{size, spacing_rad, std::vector<double>(size_t(size) * size)};
  const double scale = std::pow(du, 4) / (p.wavelength_m * p.wavelength_m * PupilEnergy(p));
  for (int r = 0; r < size; ++r)
    for (int c = 0; c < size; ++c) {
      const int my = size / 2 - r, mx = c - size / 2;
      const int iy = ((my % n) + n) % n, ix = ((mx % n) + n) % n;
      psf.density[size_t(r) * size + c] = std::norm(field[size_t(iy) * n + ix]) * scale;
    }
  return psf;
}

}  // namespace layerlab

namespace layerlab {

std::complex<double> OtfLattice::at(int part, double fx, double fy) const {
  const double qx = fx / step_cycles_per_rad, qy = fy / step_cycles_per_rad;
  const int x0 = static_cast<int>(std::floor(qx)), y0 = static_cast<int>(std::floor(qy));
  if (x0 < -reach || y0 < -reach || x0 + 1 > reach || y0 + 1 > reach) return 0;
  const double tx = qx - x0, ty = qy - y0;
  return (1 - ty) * ((1 - tx) * value(part, x0, y0) + tx * value(part, x0 + 1, y0)) +
         ty * ((1 - tx) * value(part, x0, y0 + 1) + tx * value(part, x0 + 1, y0 + 1));
}

OtfLattice PupilOtfLattice(const PupilOptics& p, int n, int reach, int parts,
                           const std::vector<std::vector<MidpointShare>>& shares, const std::vector<PupilTilt>& tilts) {
  if (!(p.diameter_m > 0)) throw Error("an OTF needs a pupil larger than a pinhole");
  const int q = 2 * n - 1;
  if (n < 2 || reach < 0 || parts < 1 || shares.size() != size_t(q) * q)
    throw Error("an OTF lattice needs n >= 2, reach >= 0 and the shares of every midpoint");
  for (const std::vector<MidpointShare>& of : shares)
    for (const MidpointShare& share : of)
      if (share.part < 0 || share.part >= parts || share.tilt < -1 || share.tilt >= int(tilts.size()))
        throw Error("an OTF lattice's share names a part or a tilt it does not have");
  const double h = p.diameter_m / n;
  // P per cell, row 0 at the top (+y).
  std::vector<std::complex<double>> cell(size_t(n) * n);
  double energy = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const std::complex<double> mean =
          PupilCellMean(p, -0.5 * p.diameter_m + (j + 0.5) * h, 0.5 * p.diameter_m - (i + 0.5) * h, h, 2);
      cell[size_t(i) * n + j] = mean;
      energy += std::norm(mean);
    }
  const int side = 2 * reach + 1;
  OtfLattice lattice{reach, parts, h / p.wavelength_m, std::vector<std::complex<double>>(size_t(parts) * side * side)};
  const double k_h = 2 * std::numbers::pi / p.wavelength_m * h;
#pragma omp parallel for schedule(dynamic)
  for (int index = 0; index < side * side; ++index) {
    const int mx = index % side - reach, my = index / side - reach;  // my toward +y: rows toward the top
    if (std::abs(mx) >= n || std::abs(my) >= n) continue;
    std::vector<std::complex<double>> sum(parts, 0.0), turn(tilts.size());
    for (size_t t = 0; t < tilts.size(); ++t) turn[t] = std::polar(1.0, k_h * (mx * tilts[t].x + my * tilts[t].y));
    // a = (ia, ja), b = a - m in columns and a + m in rows (rows count down).
    for (int ia = std::max(0, -my); ia < std::min(n, n - my); ++ia) {
      const int ib = ia + my;
      for (int ja = std::max(0, mx); ja < std::min(n, n + mx); ++ja) {
        const int jb = ja - mx;
        const std::complex<double> term = cell[size_t(ia) * n + ja] * std::conj(cell[size_t(ib) * n + jb]);
        if (term == 0.0) continue;
        for (const MidpointShare& share : shares[size_t(ia + ib) * q + ja + jb])
          sum[share.part] += share.weight * (share.tilt < 0 ? term : term * turn[share.tilt]);
      }
    }
    for (int g = 0; g < parts; ++g)
      lattice.values[(size_t(g) * side + my + reach) * side + mx + reach] = sum[g] / energy;
  }
  return lattice;
}

}  // namespace layerlab
