#include "layerlab/metrics/ssim.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

constexpr double kSigma = 1.5;
constexpr int kRadius = 5;  // int(3.5 sigma + 0.5)
constexpr std::array<double, 5> kScaleWeights = {0.0448, 0.2856, 0.3001, 0.2363, 0.1333};

std::array<double, 2 * kRadius + 1> GaussianTaps() {
  std::array<double, 2 * kRadius + 1> taps{};
  double sum = 0;
  for (int k = -kRadius; k <= kRadius; ++k) sum += taps[k + kRadius] = std::exp(-0.5 * k * k / (kSigma * kSigma));
  for (double& t : taps) t /= sum;
  return taps;
}

// Index i reflected into [0, n): d c b a | a b c d | d c b a.
int Reflect(int i, int n) {
  for (;;) {
    if (i < 0)
      i = -i - 1;
    else if (i >= n)
      i = 2 * n - i - 1;
    else
      return i;
  }
}

// The Gaussian-weighted local mean of `p`: along the rows' direction (axis 0) first, then along each row.
std::vector<double> Blurred(const std::vector<double>& p, int width, int height) {
  static const std::array<double, 2 * kRadius + 1> taps = GaussianTaps();
  std::vector<double> down(p.size()), out(p.size());
  for (int i = 0; i < height; ++i)
    for (int j = 0; j < width; ++j) {
      double s = 0;
      for (int k = -kRadius; k <= kRadius; ++k)
        s += taps[k + kRadius] * p[static_cast<size_t>(Reflect(i + k, height)) * width + j];
      down[static_cast<size_t>(i) * width + j] = s;
    }
  for (int i = 0; i < height; ++i)
    for (int j = 0; j < width; ++j) {
      double s = 0;
      for (int k = -kRadius; k <= kRadius; ++k)
        s += taps[k + kRadius] * down[static_cast<size_t>(i) * width + Reflect(j + k, width)];
      out[static_cast<size_t>(i) * width + j] = s;
    }
  return out;
}

struct SsimTerms {
  double luminance = 0;  // mean of (2 mu_x mu_y + C1) / (mu_x^2 + mu_y^2 + C1)
  double structure = 0;  // mean of (2 s_xy + C2) / (s_x^2 + s_y^2 + C2)
  double ssim = 0;       // mean of their product
};

// The means over the image less its border; with `weight`, means weighted by it.
SsimTerms Terms(const Plane& x, const Plane& y, double data_range, const Plane* weight) {
  const int w = x.width, h = x.height;
  const size_t n = x.values.size();
  std::vector<double> xx(n), yy(n), xy(n);
  for (size_t k = 0; k < n; ++k)
    xx[k] = x.values[k] * x.values[k], yy[k] = y.values[k] * y.values[k], xy[k] = x.values[k] * y.values[k];
  const std::vector<double> ux = Blurred(x.values, w, h), uy = Blurred(y.values, w, h);
  const std::vector<double> uxx = Blurred(xx, w, h), uyy = Blurred(yy, w, h), uxy = Blurred(xy, w, h);
  const double c1 = std::pow(0.01 * data_range, 2), c2 = std::pow(0.03 * data_range, 2);
  SsimTerms sum;
  double count = 0;
  for (int i = kRadius; i < h - kRadius; ++i)
    for (int j = kRadius; j < w - kRadius; ++j) {
      const size_t k = static_cast<size_t>(i) * w + j;
      const double vx = uxx[k] - ux[k] * ux[k], vy = uyy[k] - uy[k] * uy[k], vxy = uxy[k] - ux[k] * uy[k];
      const double l = (2 * ux[k] * uy[k] + c1) / (ux[k] * ux[k] + uy[k] * uy[k] + c1);
      const double cs = (2 * vxy + c2) / (vx + vy + c2);
      const double a = weight ? weight->values[k] : 1.0;  // a x 1.0 is exact: unweighted sums keep their bits
      sum.luminance += a * l, sum.structure += a * cs, sum.ssim += a * l * cs;
      count += a;
    }
  if (!(count > 0)) throw Error("SSIM: the weights are 0 over the image less its border");
  sum.luminance /= count, sum.structure /= count, sum.ssim /= count;
  return sum;
}

void Check(const Plane& x, const Plane& y, double data_range, int min_side, const char* metric) {
  const std::string m = metric;
  if (x.width != y.width || x.height != y.height)
    throw Error(m + ": the images differ in size (" + std::to_string(x.width) + " x " + std::to_string(x.height) +
                " and " + std::to_string(y.width) + " x " + std::to_string(y.height) + ")");
  if (x.width < min_side || x.height < min_side)
    throw Error(m + ": " + std::to_string(x.width) + " x " + std::to_string(x.height) + " pixels; it needs at least " +
                std::to_string(min_side) + " on each side");
  if (x.values.size() != static_cast<size_t>(x.width) * x.height || y.values.size() != x.values.size())
    throw Error(m + ": an image's values do not match its size");
  if (!(data_range > 0) || !std::isfinite(data_range))
    throw Error(m + ": data range " + std::to_string(data_range) + ": must be above 0");
  for (const Plane* p : {&x, &y})
    for (double v : p->values)
      if (!std::isfinite(v)) throw Error(m + ": an image holds a value that is not finite");
}

// The 2 x 2 mean, every second pixel.
Plane Halved(const Plane& p) {
  Plane out{p.width / 2, p.height / 2, {}};
  out.values.resize(static_cast<size_t>(out.width) * out.height);
  for (int i = 0; i < out.height; ++i)
    for (int j = 0; j < out.width; ++j)
      out.values[static_cast<size_t>(i) * out.width + j] =
          0.25 * (p.at(2 * i, 2 * j) + p.at(2 * i + 1, 2 * j) + p.at(2 * i, 2 * j + 1) + p.at(2 * i + 1, 2 * j + 1));
  return out;
}

}  // namespace

double Ssim(const Plane& x, const Plane& y, double data_range, const Plane* weight) {
  Check(x, y, data_range, 2 * kRadius + 1, "SSIM");
  CheckWeight(x, weight, "SSIM");
  return Terms(x, y, data_range, weight).ssim;
}

double MsSsim(const Plane& x, const Plane& y, double data_range, const Plane* weight) {
  Check(x, y, data_range, kMsSsimMinSide, "MS-SSIM");
  CheckWeight(x, weight, "MS-SSIM");
  Plane a = x, b = y, w = weight ? *weight : Plane{};
  double product = 1;
  for (size_t j = 0; j < kScaleWeights.size(); ++j) {
    const SsimTerms t = Terms(a, b, data_range, weight ? &w : nullptr);
    product *= std::pow(std::max(t.structure, 0.0), kScaleWeights[j]);
    if (j + 1 == kScaleWeights.size())
      product *= std::pow(std::max(t.luminance, 0.0), kScaleWeights[j]);
    else
      a = Halved(a), b = Halved(b), w = weight ? Halved(w) : w;
  }
  return product;
}

void CheckWeight(const Plane& image, const Plane* weight, const char* metric) {
  if (!weight) return;
  const std::string m = metric;
  if (weight->width != image.width || weight->height != image.height || weight->values.size() != image.values.size())
    throw Error(m + ": the weight is not of the image's size");
  double sum = 0;
  for (double v : weight->values) {
    if (!(v >= 0) || !std::isfinite(v)) throw Error(m + ": a weight that is negative or not finite");
    sum += v;
  }
  if (!(sum > 0)) throw Error(m + ": the weights are all 0");
}

Plane EncodedLuminance(const Image& image) {
  if (image.channels.size() != 3) throw Error("luminance: the image is not RGB");
  Plane out{image.width, image.height, {}};
  out.values.resize(static_cast<size_t>(image.width) * image.height);
  for (size_t k = 0; k < out.values.size(); ++k) {
    for (int c = 0; c < 3; ++c)
      if (!(image.pixels[3 * k + c] >= 0) || !std::isfinite(image.pixels[3 * k + c]))
        throw Error("luminance: pixel (" + std::to_string(k / image.width) + ", " + std::to_string(k % image.width) +
                    ") holds a negative or undefined value");
    out.values[k] = 0.2126 * image.pixels[3 * k] + 0.7152 * image.pixels[3 * k + 1] + 0.0722 * image.pixels[3 * k + 2];
  }
  EncodeLuminance(&out);
  return out;
}

void EncodeLuminance(Plane* linear) {
  for (double& y : linear->values) y = y <= 0.0031308 ? 12.92 * y : 1.055 * std::pow(y, 1 / 2.4) - 0.055;
}

}  // namespace layerlab
