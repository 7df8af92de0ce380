#include "layerlab/metrics/retinal_metrics.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>

#include "layerlab/framework/error.h"
#include "layerlab/metrics/csf_jnd.h"
#include "layerlab/metrics/foveal_weight.h"
#include "layerlab/metrics/psnr.h"
#include "layerlab/metrics/ssim.h"

namespace layerlab {
namespace {

// The image's luminance (Rec. 709 weights) times `scale`, a ringing below 0 by at most kRingingFloor taken as 0.
Plane Luminance(const Image& image, double scale, const char* which) {
  if (image.channels.size() != 3) throw Error(std::string("metrics: the ") + which + " image is not RGB");
  Plane out{image.width, image.height, std::vector<double>(size_t(image.width) * image.height)};
  for (size_t k = 0; k < out.values.size(); ++k) {
    const float* p = &image.pixels[3 * k];
    const double y = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    if (!(y >= -kRingingFloor) || !std::isfinite(y))
      throw Error(std::string("metrics: the ") + which + " image's pixel (" + std::to_string(k / image.width) + ", " +
                  std::to_string(k % image.width) + ") has a luminance of " + std::to_string(y) +
                  ", below 0 by more than the " + std::to_string(kRingingFloor) + " a transform rings");
    out.values[k] = std::max(0.0, y) * scale;
  }
  return out;
}

Plane Encoded(const Image& image, const char* which) {
  Plane p = Luminance(image, 1.0, which);
  EncodeLuminance(&p);
  return p;
}

// The viewing's foveal weight of an image, or nothing.
std::optional<Plane> Weight(const Image& image, const MetricViewing& v) {
  if (!v.foveal) return std::nullopt;
  return FovealWeight(image.width, image.height, v.pixel_deg, v.gaze_x_deg, v.gaze_y_deg);
}

double Psnr(const Image& display, const Image& reference, const MetricViewing& v) {
  const std::optional<Plane> w = Weight(display, v);
  return ImagePsnrDb(display, reference, w ? &*w : nullptr);
}
double SsimOf(const Image& display, const Image& reference, const MetricViewing& v) {
  const std::optional<Plane> w = Weight(display, v);
  return Ssim(Encoded(display, "display"), Encoded(reference, "reference"), 1.0, w ? &*w : nullptr);
}
double MsSsimOf(const Image& display, const Image& reference, const MetricViewing& v) {
  const std::optional<Plane> w = Weight(display, v);
  return MsSsim(Encoded(display, "display"), Encoded(reference, "reference"), 1.0, w ? &*w : nullptr);
}
double JndOf(const Image& display, const Image& reference, const MetricViewing& v) {
  const std::optional<Plane> w = Weight(display, v);
  return CsfJnd(Luminance(reference, v.white_cd_m2, "reference"), Luminance(display, v.white_cd_m2, "display"),
                {v.pixel_deg, v.jnd_minkowski_exponent, w ? &*w : nullptr});
}

}  // namespace

void CheckMetricSettings(const MetricSettings& s, const std::string& exponent_field, const std::string& fovea_field) {
  if (!std::isfinite(s.jnd_minkowski_exponent) || !(s.jnd_minkowski_exponent >= 1))
    throw Error(exponent_field + ": " + std::to_string(s.jnd_minkowski_exponent) +
                ": a Minkowski exponent must be 1 or more (1: the mean, 2: the RMS, large: the maximum)");
  if (s.fovea_deg && !(std::isfinite((*s.fovea_deg)[0]) && std::isfinite((*s.fovea_deg)[1])))
    throw Error(fovea_field + ": the gaze must be finite");
}

const std::vector<RetinalMetric>& RetinalMetrics() {
  static const std::vector<RetinalMetric> metrics = {
      {"psnr", "psnr_db", "dB", true, 1, "10 log10(1 / MSE) over pixels and channels, peak 1 (the display's white)",
       &Psnr},
      {"ssim", "ssim", "", true, 11, "SSIM of the sRGB-encoded luminance (Wang et al. 2004)", &SsimOf},
      {"ms_ssim", "ms_ssim", "", true, kMsSsimMinSide, "MS-SSIM of the sRGB-encoded luminance (Wang et al. 2003)",
       &MsSsimOf},
      {"jnd", "jnd", "JND", false, 1,
       "the luminance difference weighted by Barten's CSF, Minkowski-pooled (beta 4 unless set), in just-noticeable "
       "differences",
       &JndOf},
  };
  return metrics;
}

std::vector<const RetinalMetric*> ParseRetinalMetrics(const std::string& list, const std::string& what) {
  std::string known;
  for (const RetinalMetric& m : RetinalMetrics()) known += (known.empty() ? "" : ", ") + m.name;
  std::set<std::string> asked{"psnr"};
  size_t from = 0;
  while (from <= list.size() && !list.empty()) {
    const size_t comma = list.find(',', from);
    std::string name = list.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
    name.erase(0, name.find_first_not_of(' '));
    name.erase(name.find_last_not_of(' ') + 1);
    const bool found = name == "all" || std::any_of(RetinalMetrics().begin(), RetinalMetrics().end(),
                                                    [&](const RetinalMetric& m) { return m.name == name; });
    if (!found) throw Error(what + ": \"" + name + "\" is not a metric (" + known + ", or all)");
    if (name == "all")
      for (const RetinalMetric& m : RetinalMetrics()) asked.insert(m.name);
    else if (!asked.insert(name).second && name != "psnr")
      throw Error(what + ": \"" + name + "\" is named twice");
    if (comma == std::string::npos) break;
    from = comma + 1;
  }
  std::vector<const RetinalMetric*> out;
  for (const RetinalMetric& m : RetinalMetrics())
    if (asked.count(m.name)) out.push_back(&m);
  return out;
}

void CheckMetricSize(const std::vector<const RetinalMetric*>& metrics, int width, int height, const std::string& what) {
  for (const RetinalMetric* m : metrics)
    if (width < m->min_side || height < m->min_side)
      throw Error(what + ": " + m->name + " needs images of at least " + std::to_string(m->min_side) + " x " +
                  std::to_string(m->min_side) + " samples; these are " + std::to_string(width) + " x " +
                  std::to_string(height) + " (a finer resolution or a larger field)");
}

}  // namespace layerlab
