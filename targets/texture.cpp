#include "layerlab/targets/texture.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>

#include "layerlab/framework/error.h"
#include "layerlab/framework/random.h"
#include "layerlab/targets/fast_cos.h"
#include "layerlab/targets/length_or_angle.h"
#include "layerlab/targets/png_image.h"

namespace layerlab {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

std::string Number(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

class ConstantTexture final : public Texture {
 public:
  explicit ConstantTexture(const Rgb& color) : color_(color) {}
  Rgb Evaluate(double, double) const override { return color_; }
  std::string Describe() const override {
    return "constant (" + Number(color_[0]) + ", " + Number(color_[1]) + ", " + Number(color_[2]) + ")";
  }

 private:
  Rgb color_;
};

class GratingTexture final : public Texture {
 public:
  explicit GratingTexture(const GratingSpec& spec)
      : spec_(spec),
        k_(kTwoPi * spec.cycles_per_meter),
        cos_(std::cos(spec.orientation_rad)),
        sin_(std::sin(spec.orientation_rad)) {}
  Rgb Evaluate(double s, double t) const override {
    double w = s * cos_ + t * sin_;  // along the wave vector
    // Uniform in visual angle: z atan(w / z) is w at the line of sight and
    // grows as the angle, not as its tangent.
    if (spec_.angle_depth_m > 0) w = spec_.angle_depth_m * std::atan(w / spec_.angle_depth_m);
    double value = spec_.mean * (1.0 + spec_.contrast * std::cos(k_ * w + spec_.phase_rad));
    return {value, value, value};
  }
  std::string Describe() const override { return spec_.description; }
  // w = s cos + t sin is s + (+-0) = s for every finite t when sin is 0 (and
  // where s is +-0, cos(k w + phase) is the same for either sign).
  bool ConstantAlongT() const override { return sin_ == 0.0; }

 private:
  GratingSpec spec_;
  double k_, cos_, sin_;  // rad per meter; the wave vector's direction
};

class CheckerboardTexture final : public Texture {
 public:
  CheckerboardTexture(double period, const Rgb& low, const Rgb& high) : period_(period), low_(low), high_(high) {}
  Rgb Evaluate(double s, double t) const override {
    double half = period_ / 2;
    long long parity = static_cast<long long>(std::floor(s / half)) + static_cast<long long>(std::floor(t / half));
    return (parity & 1) ? high_ : low_;
  }
  std::string Describe() const override { return "checkerboard, period " + Number(period_ * 1e3) + " mm"; }

 private:
  double period_;
  Rgb low_, high_;
};

class NoiseTexture final : public Texture {
 public:
  NoiseTexture(double f_min, double f_max, int components, uint64_t seed, double contrast, double mean)
      : f_min_(f_min), f_max_(f_max) {
    SplitMix64 random(seed);
    // Unit variance: each cosine of amplitude a contributes a^2 / 2.
    const double amplitude = std::sqrt(2.0 / components);
    waves_.mean = mean;
    waves_.gain = contrast * amplitude;
    for (int k = 0; k < components; ++k) {
      double f = f_min + (f_max - f_min) * random.uniform();
      double orientation = std::numbers::pi * random.uniform();
      double phase = kTwoPi * random.uniform();
      waves_.kx.push_back(kTwoPi * f * std::cos(orientation));
      waves_.ky.push_back(kTwoPi * f * std::sin(orientation));
      waves_.phase.push_back(phase);
    }
  }
  Rgb Evaluate(double s, double t) const override {
    double value = waves_.Evaluate(s, t);
    return {value, value, value};
  }
  std::string Describe() const override {
    return "noise " + std::to_string(waves_.kx.size()) + " components, " + Number(f_min_) + " to " + Number(f_max_) +
           " cycles/m";
  }
  const PlaneWaves* plane_waves() const override { return &waves_; }

 private:
  double f_min_, f_max_;
  PlaneWaves waves_;
};

class ImageTexture final : public Texture {
 public:
  ImageTexture(Image image, std::array<double, 2> size, TextureWrap wrap, std::string description)
      : image_(std::move(image)), size_(size), wrap_(wrap), description_(std::move(description)) {}

  // Bilinear between pixel centers.
  Rgb Evaluate(double s, double t) const override {
    double x = (s / size_[0] + 0.5) * image_.width - 0.5;
    double y = (0.5 - t / size_[1]) * image_.height - 0.5;
    double x0 = std::floor(x), y0 = std::floor(y);
    double fx = x - x0, fy = y - y0;
    Rgb out{0, 0, 0};
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        double w = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
        if (w == 0) continue;
        int col = Index(static_cast<long long>(x0) + dx, image_.width);
        int row = Index(static_cast<long long>(y0) + dy, image_.height);
        for (int c = 0; c < 3; ++c) out[c] += w * image_.at(row, col, c);
      }
    return out;
  }
  std::string Describe() const override { return description_; }

 private:
  int Index(long long i, int n) const {
    if (wrap_ == TextureWrap::kRepeat) return static_cast<int>(((i % n) + n) % n);
    return static_cast<int>(std::clamp<long long>(i, 0, n - 1));
  }

  Image image_;
  std::array<double, 2> size_;
  TextureWrap wrap_;
  std::string description_;
};

Image LoadImage(Params& p, const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".exr") return ReadExr(path, {"R", "G", "B"});
  if (extension == ".png") return ReadPngLinear(path);
  p.fail("file", "unknown image format \"" + extension + "\"; expected .exr or .png");
}

// A non-negative number ("mean" may exceed 1: linear light is not capped).
double NonNegative(Params& p, const std::string& key, double fallback) {
  double x = p.quantity(key, Dimension::kFraction, fallback);
  p.require_range(key, x, 0.0, 1e6, false, false);
  return x;
}

double Fraction(Params& p, const std::string& key, double fallback) {
  double x = p.quantity(key, Dimension::kFraction, fallback);
  p.require_range(key, x, 0.0, 1.0, false, false);
  return x;
}

}  // namespace

double PlaneWaves::Evaluate(double s, double t) const {
  double sum = 0;
  const double *kx_k = kx.data(), *ky_k = ky.data(), *phase_k = phase.data();
  const size_t n = kx.size();
#pragma omp simd reduction(+ : sum)
  for (size_t k = 0; k < n; ++k) sum += FastCos(kx_k[k] * s + ky_k[k] * t + phase_k[k]);
  return Clamped(sum);
}

std::unique_ptr<Texture> MakeConstantTexture(const Rgb& color) { return std::make_unique<ConstantTexture>(color); }

std::unique_ptr<Texture> MakeGratingTexture(const GratingSpec& spec) { return std::make_unique<GratingTexture>(spec); }

std::unique_ptr<Texture> MakeCheckerboardTexture(double period, const Rgb& low, const Rgb& high) {
  return std::make_unique<CheckerboardTexture>(period, low, high);
}

std::unique_ptr<Texture> MakeNoiseTexture(double min_frequency, double max_frequency, int components, uint64_t seed,
                                          double contrast, double mean) {
  return std::make_unique<NoiseTexture>(min_frequency, max_frequency, components, seed, contrast, mean);
}

std::unique_ptr<Texture> MakeImageTexture(Image image, std::array<double, 2> size, TextureWrap wrap,
                                          const std::string& description) {
  return std::make_unique<ImageTexture>(std::move(image), size, wrap, description);
}

std::unique_ptr<Texture> ParseTexture(Params& p, const TextureFrame& frame) {
  p.string("type");  // required
  std::string type = p.choice("type", {"constant", "grating", "checkerboard", "noise", "image"}, "");
  const double z = frame.reference_depth_m;
  std::unique_ptr<Texture> texture;
  if (type == "constant") {
    texture = MakeConstantTexture(p.fraction_rgb("color"));
  } else if (type == "grating") {
    GratingSpec g;
    double cpd = p.quantity("frequency", Dimension::kAngularFrequency);
    p.require_range("frequency", cpd, 0.0, 1000.0, false, false);
    g.cycles_per_meter = CyclesPerMeter(cpd, z);
    g.phase_rad = p.quantity("phase", Dimension::kAngle, 0.0);
    g.orientation_rad = p.quantity("orientation", Dimension::kAngle, 0.0);
    g.contrast = Fraction(p, "contrast", 1.0);
    g.mean = NonNegative(p, "mean", 0.5);
    bool in_angle = p.choice("uniform", {"plane", "angle"}, "plane") == "angle";
    if (in_angle) g.angle_depth_m = z;
    g.description = "grating " + Number(cpd) + " cpd" + (in_angle ? " in visual angle" : "");
    texture = MakeGratingTexture(g);
  } else if (type == "checkerboard") {
    double period = LengthOrAngle(p, "period", z);
    texture = MakeCheckerboardTexture(period, p.fraction_rgb("low", 0.0), p.fraction_rgb("high", 1.0));
  } else if (type == "noise") {
    const nlohmann::json& band = p.raw("band");
    if (!band.is_array() || band.size() != 2)
      p.fail("band", "expected two frequencies [\"1 cpd\", \"4 cpd\"], got " + band.dump());
    Params ends(nlohmann::json{{"0", band[0]}, {"1", band[1]}}, p.where("band"));
    double lo = ends.quantity("0", Dimension::kAngularFrequency);
    double hi = ends.quantity("1", Dimension::kAngularFrequency);
    ends.require_range("0", lo, 0.0, 1000.0, false, false);
    ends.require_range("1", hi, lo, 1000.0, false, false);
    int components = static_cast<int>(p.integer("components", 1, 4096, 64));
    uint64_t seed = static_cast<uint64_t>(p.integer("seed", 0, INT64_MAX, 1));
    double contrast = Fraction(p, "contrast", 0.3);
    double mean = NonNegative(p, "mean", 0.5);
    texture = MakeNoiseTexture(CyclesPerMeter(lo, z), CyclesPerMeter(hi, z), components, seed, contrast, mean);
  } else {
    std::string file = p.string("file");
    std::string path = (std::filesystem::path(frame.base_dir) / file).string();
    std::array<double, 2> size = p.has("size") ? LengthOrAnglePair(p, "size", z) : frame.default_size_m;
    p.mark_read("size");
    TextureWrap wrap =
        p.choice("wrap", {"clamp", "repeat"}, "clamp") == "clamp" ? TextureWrap::kClamp : TextureWrap::kRepeat;
    Image image = LoadImage(p, path);
    if (frame.files_read) frame.files_read->push_back(path);
    texture = MakeImageTexture(std::move(image), size, wrap, "image " + file);
  }
  p.check_all_read();
  return texture;
}

}  // namespace layerlab
