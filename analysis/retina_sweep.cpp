#include "analysis/retina_sweep.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "framework/atomic_file.h"
#include "framework/error.h"
#include "framework/exr_image.h"
#include "framework/png_writer.h"
#include "framework/polarization.h"

namespace layerlab {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

double MeanLuminance(const Image& image) {
  double sum = 0;
  for (size_t k = 0; k < image.pixels.size(); ++k) sum += kLuminanceWeights[k % 3] * image.pixels[k];
  return sum / (double(image.width) * image.height);
}

}  // namespace

std::string RetinaStateName(double diopters) {
  char name[32];
  std::snprintf(name, sizeof name, "%.2fD", diopters);
  return name;
}

std::vector<RetinaStateResult> WriteRetinaSweep(
    const DisplayModel& model, const Patterns& t, const SceneRadiance& natural, const RetinaSweepOptions& o,
    const std::string& folder, const std::function<void(size_t, size_t, const RetinaStateResult&)>& progress) {
  const DisplaySystem& system = model.system();
  if (o.states.empty()) throw Error("retina: no accommodation state given");
  if (!(o.resolution > 0) || !(o.resolution < 10)) throw Error("retina: the resolution must lie in (0, 10) deg");
  const double field_x = o.field_x > 0 ? o.field_x * kDeg : system.fov_x;
  const double field_y = o.field_y > 0 ? o.field_y * kDeg : system.fov_y;
  const RetinaGrid grid = MakeRetinaGrid(field_x, field_y, o.resolution * kDeg);
  const std::vector<PupilPoint> pupil = PupilSamples(system.eye);

  namespace fs = std::filesystem;
  const fs::path out = folder;
  fs::create_directories(out / "display");
  if (natural) fs::create_directories(out / "natural");
  std::string csv = "accommodation_D,display_mean_cd_m2,natural_mean_cd_m2,display_clipped_in_png,seconds\n";
  const double white = model.white_luminance();
  std::vector<RetinaStateResult> results;
  for (double state : o.states) {
    auto start = std::chrono::steady_clock::now();
    RetinaStateResult r;
    r.diopters = state;
    r.name = RetinaStateName(state);
    const auto focus = ChannelAccommodation(system.eye, state);
    Image display = RetinaOfDisplay(model, t, grid, pupil, focus);
    WriteExr((out / "display" / (r.name + ".exr")).string(), display);
    r.display_clipped_in_png =
        WriteSrgbPng((out / "display" / (r.name + ".png")).string(), grid.cols, grid.rows, display.pixels);
    r.display_mean_cd_m2 = MeanLuminance(display) * white;
    r.natural_mean_cd_m2 = NAN;
    if (natural) {
      Image seen = RetinaOfScene(natural, grid, pupil, focus);
      WriteExr((out / "natural" / (r.name + ".exr")).string(), seen);
      WriteSrgbPng((out / "natural" / (r.name + ".png")).string(), grid.cols, grid.rows, seen.pixels);
      r.natural_mean_cd_m2 = MeanLuminance(seen) * white;
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    char row[160];
    std::snprintf(row, sizeof row, "%.4f,%.6g,%.6g,%zu,%.3f\n", state, r.display_mean_cd_m2, r.natural_mean_cd_m2,
                  r.display_clipped_in_png, r.seconds);
    csv += row;
    results.push_back(r);
    if (progress) progress(results.size(), o.states.size(), r);
  }
  WriteFileAtomically((out / "retina.csv").string(), csv);
  return results;
}

}  // namespace layerlab
