// Light travelling from a panel toward the eye, per color channel, as far as
// layerlab needs it: an intensity factor and, only when a polarizing element
// lies on the path, a Jones vector (x = horizontal, y = vertical in eye space).
#pragma once

#include <array>
#include <complex>

namespace layerlab {

// Dominant wavelengths of the Rec.709 primaries, used to evaluate spectral
// efficiencies (PBS, wave plates) per color channel.
inline constexpr std::array<double, 3> kChannelWavelengths = {612e-9, 549e-9, 465e-9};
inline constexpr std::array<const char*, 3> kChannelNames = {"R", "G", "B"};
// Rec.709 luminance weights, for single-number brightness figures.
inline constexpr std::array<double, 3> kLuminanceWeights = {0.2126, 0.7152, 0.0722};

using Complex = std::complex<double>;

struct Jones {
  Complex x{1.0, 0.0};
  Complex y{0.0, 0.0};
  double intensity() const { return std::norm(x) + std::norm(y); }
};

// A 2x2 Jones matrix [[a, b], [c, d]].
struct JonesMatrix {
  Complex a, b, c, d;
  Jones operator*(const Jones& v) const { return {a * v.x + b * v.y, c * v.x + d * v.y}; }
};

// Linear polarization at `angle` radians from the x axis.
Jones LinearPolarization(double angle);
// A retarder with retardance `delta` (radians) and fast axis at `axis` radians.
JonesMatrix Retarder(double delta, double axis);

struct ChannelLight {
  bool polarized = false;
  double intensity = 1.0;  // used when not polarized
  Jones field;             // used when polarized; |field|^2 is the intensity

  double power() const { return polarized ? field.intensity() : intensity; }
  // A polarization-blind attenuation by `transmittance` (intensity).
  void attenuate(double transmittance);
};

using Light = std::array<ChannelLight, 3>;

}  // namespace layerlab
