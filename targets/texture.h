// Textures: linear RGB as a function of a position (s, t), in meters, on a
// surface's texture plane (s right, t up). A plane's texture plane is the plane
// itself, centered on the plane's center; a mesh maps its texture coordinates
// (u, v) to s = (u - 0.5) * uv_size, t = (v - 0.5) * uv_size.
//
// Angular quantities (cycles per degree, periods in degrees) become lengths at
// the surface's reference depth (length_or_angle.h): linear on the plane.
//
// | type         | key          | type              | default  | meaning                                    |
// |--------------|--------------|-------------------|----------|--------------------------------------------|
// | constant     | color        | fraction or [r,g,b] | required | linear RGB                               |
// | grating      | frequency    | cpd               | required | mean * (1 + contrast * cos(2 pi f (s cos o + t sin o) + phase)) |
// |              | phase        | angle             | 0 deg    | 0: a bright bar through the center         |
// |              | orientation  | angle             | 0 deg    | of the wave vector from +s; 0 = vertical bars |
// |              | contrast     | fraction          | 1        | Michelson contrast                         |
// |              | mean         | number >= 0       | 0.5      | mean linear luminance                      |
// |              | uniform      | plane, angle      | plane    | plane: f at the line of sight, linear in meters; angle: f cpd everywhere as seen from the point z in front of the center (the phase goes as z atan(w / z), w = s cos o + t sin o) |
// | checkerboard | period       | length or angle   | required | one dark plus one bright square            |
// |              | low, high    | fraction or [r,g,b] | 0, 1   | the two colors; a low square has its corner at the origin |
// | noise        | band         | [cpd, cpd]        | required | frequencies of the components, uniform in the band |
// |              | components   | integer           | 64       | random-phase, random-orientation sinusoids |
// |              | seed         | integer           | 1        | same seed, same texture, on every machine  |
// |              | contrast     | fraction          | 0.3      | RMS contrast before clamping at 0          |
// |              | mean         | number >= 0       | 0.5      |                                            |
// | image        | file         | path              | required | .exr (channels R, G, B) or .png (sRGB, alpha over black), relative to the target file |
// |              | size         | [w, h] lengths or angles | the surface's default | what the image covers, centered |
// |              | wrap         | clamp, repeat     | clamp    | outside the image                          |
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/params.h"

namespace layerlab {

// A texture that is a sum of plane waves on its plane (the noise texture):
//   max(0, mean (1 + gain sum_k cos(kx_k s + ky_k t + phase_k))).
// A renderer may evaluate it against phases shared by many views
// (targets/plane_wave_table.h).
struct PlaneWaves {
  std::vector<double> kx, ky, phase;  // rad per meter, rad per meter, rad
  double mean = 0, gain = 0;

  double Evaluate(double s, double t) const;
  double Clamped(double sum) const { return std::max(0.0, mean * (1.0 + gain * sum)); }
};

class Texture {
 public:
  virtual ~Texture() = default;
  // Linear RGB at (s, t), meters on the texture plane.
  virtual Rgb Evaluate(double s, double t) const = 0;
  // A few words for the light field's scene text: "grating 2 cpd".
  virtual std::string Describe() const = 0;
  // True if Evaluate(s, t) gives the same bits for every finite t (a grating
  // of vertical bars): a renderer may evaluate one row and copy it.
  virtual bool ConstantAlongT() const { return false; }
  // The texture's plane waves when it is a sum of them, else nullptr.
  virtual const PlaneWaves* plane_waves() const { return nullptr; }
};

// What a texture on one surface needs to know.
struct TextureFrame {
  double reference_depth_m = 1.0;                  // m; angles become lengths here
  std::array<double, 2> default_size_m{1, 1};      // m: what an image covers unless "size" is given
  std::string base_dir;                            // image files are relative to this
  std::vector<std::string>* files_read = nullptr;  // when given, each image file read is appended
};

std::unique_ptr<Texture> ParseTexture(Params& p, const TextureFrame& frame);

// The same textures for in-process targets (frequencies already in cycles per meter).
struct GratingSpec {
  double cycles_per_meter = 0;
  double phase_rad = 0;        // rad
  double orientation_rad = 0;  // rad
  double contrast = 1;
  double mean = 0.5;
  // 0: uniform on the plane. z > 0: uniform in visual angle as seen from the
  // point z in front of the texture origin, cycles_per_meter there at the
  // line of sight (the phase along the wave vector is 2 pi k z atan(w / z)).
  double angle_depth_m = 0;  // m
  std::string description = "grating";
};
std::unique_ptr<Texture> MakeConstantTexture(const Rgb& color);
std::unique_ptr<Texture> MakeGratingTexture(const GratingSpec& spec);
std::unique_ptr<Texture> MakeCheckerboardTexture(double period, const Rgb& low, const Rgb& high);
// Frequencies in cycles per meter.
std::unique_ptr<Texture> MakeNoiseTexture(double min_frequency, double max_frequency, int components, uint64_t seed,
                                          double contrast, double mean);
enum class TextureWrap { kClamp, kRepeat };
// `image` has channels R, G, B; it covers [-w/2, w/2] x [-h/2, h/2], row 0 at +h/2.
std::unique_ptr<Texture> MakeImageTexture(Image image, std::array<double, 2> size, TextureWrap wrap,
                                          const std::string& description);

}  // namespace layerlab
