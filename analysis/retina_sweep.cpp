#include "layerlab/analysis/retina_sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <numbers>
#include <optional>

#include "layerlab/analysis/run_option_table.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/png_writer.h"
#include "layerlab/framework/polarization.h"
#include "layerlab/framework/shown_image.h"
#include "layerlab/framework/units.h"
#include "layerlab/retina/eye_optics.h"
#include "layerlab/retina/retina_workspace.h"
#include "layerlab/systems/ghosts.h"
#include "layerlab/systems/lc_response.h"
#include "layerlab/systems/world_view.h"

namespace layerlab {

double MeanLuminance(const Image& image) {
  double sum = 0;
  for (size_t k = 0; k < image.pixels.size(); ++k) sum += kLuminanceWeights[k % 3] * image.pixels[k];
  return sum / (double(image.width) * image.height);
}

namespace {

namespace fs = std::filesystem;

// One batch of states: each state's results and its images of the display and, with `natural`, of the scene.
struct RetinaBatch {
  std::vector<RetinaStateResult> r;
  std::vector<Image> display, seen;
  std::vector<Image> world;  // a see-through display's worlds, display-relative; empty: uniform or none
};

// Each state's display image against natural viewing by each metric, every (state, metric) a thread's work; its
// time added to the state's seconds.
void Score(const std::vector<const RetinalMetric*>& metrics, const MetricViewing& viewing, RetinaBatch* b) {
  const int items = static_cast<int>(b->r.size() * metrics.size());
  std::vector<double> spent(items);
  std::vector<std::exception_ptr> failed(items);
#pragma omp parallel for schedule(dynamic)
  for (int i = 0; i < items; ++i) {
    const size_t s = i / metrics.size(), k = i % metrics.size();
    const auto start = std::chrono::steady_clock::now();
    try {
      b->r[s].scores[k].second = metrics[k]->score(b->display[s], b->seen[s], viewing);
    } catch (...) {
      failed[i] = std::current_exception();
    }
    spent[i] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  for (int i = 0; i < items; ++i) {
    if (failed[i]) std::rethrow_exception(failed[i]);
    b->r[i / metrics.size()].seconds += spent[i];
  }
}

// The images of states [first, first + count), each computed in parallel within.
RetinaBatch TraceBatch(const DisplayModel& model, const std::vector<ShownInstant>& shown, const SceneRadiance& natural,
                       const SceneRadiance& world, const EyeOptics& optics, const std::vector<double>& states,
                       size_t first, size_t count, const std::vector<const RetinalMetric*>& metrics,
                       const MetricSettings& settings, RetinaWorkspace* workspace) {
  const MetricViewing viewing =
      MetricViewing::Of(optics.grid().resolution_rad / kRadiansPerDegree, model.white_luminance(), settings);
  const DisplaySystem& system = model.system();
  const double white = model.white_luminance();
  RetinaBatch b{std::vector<RetinaStateResult>(count), std::vector<Image>(count), std::vector<Image>(count), {}};
  if (world) b.world.resize(count);
  for (size_t s = 0; s < count; ++s) {
    auto start = std::chrono::steady_clock::now();
    RetinaStateResult& r = b.r[s];
    r.diopters = states[first + s];
    r.name = RetinaStateName(r.diopters);
    const auto focus = ChannelAccommodation(system.eye, r.diopters);
    b.display[s] = optics.See([&](const RetinaGrid& traced, const std::vector<PupilPoint>& group) {
      return RetinaOfDisplay(model, shown, DisplayRetinaTables(model, traced, group, focus), workspace);
    });
    r.display_mean_cd_m2 = MeanLuminance(b.display[s]) * white;
    if (world) {  // the worlds' scenes, seen as the eye focuses: cd/m^2, made display-relative
      b.world[s] = optics.See([&](const RetinaGrid& traced, const std::vector<PupilPoint>& group) {
        return RetinaOfScene(world, traced, group, focus);
      });
      for (float& v : b.world[s].pixels) v = static_cast<float>(v / white);
    }
    if (!system.worlds.empty()) {
      r.world_cd_m2 = world ? MeanLuminance(b.world[s]) * white : LuminanceOf(WorldAtEye(system));
      r.contrast_against_world = r.world_cd_m2 > 0 ? (r.display_mean_cd_m2 + r.world_cd_m2) / r.world_cd_m2
                                                   : INFINITY;  // a world the path blocks (crossed polarizers)
    }
    r.natural_mean_cd_m2 = NAN;
    for (const RetinalMetric* m : metrics) r.scores.emplace_back(m->column, NAN);
    if (natural) {
      b.seen[s] = optics.See([&](const RetinaGrid& traced, const std::vector<PupilPoint>& group) {
        return RetinaOfScene(natural, traced, group, focus);
      });
      r.natural_mean_cd_m2 = MeanLuminance(b.seen[s]) * white;
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  if (natural) Score(metrics, viewing, &b);
  return b;
}

// The batch's files, in parallel: file f of state s = f / 4 is the display's
// EXR, its PNG, the natural EXR, its PNG. Each file's seconds into `seconds`.
void WriteBatch(const fs::path& out, const RetinaGrid& grid, bool natural, ExrPixels pixels, RetinaBatch* b,
                std::vector<double>* seconds) {
  const int files = static_cast<int>(b->r.size() * 4);
  std::vector<std::exception_ptr> failed(files);
  seconds->assign(files, 0.0);
#pragma omp parallel for schedule(dynamic)
  for (int f = 0; f < files; ++f) {
    const size_t s = f / 4;
    const bool of_display = f % 4 < 2, exr = f % 2 == 0;
    if (!of_display && !natural) continue;
    auto start = std::chrono::steady_clock::now();
    try {
      const Image& image = of_display ? b->display[s] : b->seen[s];
      const fs::path stem = out / (of_display ? "display" : "natural") / b->r[s].name;
      if (exr)
        WriteExr(stem.string() + ".exr", image, ExrCompression::kNone, pixels);
      else {
        const ShownPng png = WriteShownSrgbPng(stem.string() + ".png", grid.cols, grid.rows, image.pixels,
                                               kRetinaWidthPx, PngCompression::kFast);
        if (of_display) {
          RetinaStateResult& r = b->r[s];
          r.display_clipped_in_png = png.clipped;
          r.png_width = png.width, r.png_height = png.height, r.png_factor = png.factor;
        }
      }
    } catch (...) {
      failed[f] = std::current_exception();
    }
    (*seconds)[f] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
}

// A see-through display's images with the world's light added: see_through/<state>.exr and .png.
void WriteSeeThrough(const DisplayModel& model, const fs::path& out, const RetinaGrid& grid, ExrPixels pixels,
                     const RetinaBatch& b) {
  const Rgb world = WorldAtEye(model.system());
  fs::create_directories(out / "see_through");
  for (size_t s = 0; s < b.display.size(); ++s) {
    Image seen = b.display[s];
    for (size_t i = 0; i < seen.pixels.size(); ++i)
      seen.pixels[i] +=
          b.world.empty() ? static_cast<float>(world[i % 3] / model.white_luminance()) : b.world[s].pixels[i];
    const fs::path stem = out / "see_through" / b.r[s].name;
    WriteExr(stem.string() + ".exr", seen, ExrCompression::kNone, pixels);
    WriteShownSrgbPng(stem.string() + ".png", grid.cols, grid.rows, seen.pixels, kRetinaWidthPx, PngCompression::kFast);
  }
}

}  // namespace

void CheckAccommodationStates(const std::vector<double>& states, const std::string& name) {
  if (states.empty()) throw Error(name + ": no accommodation state given");
  for (size_t k = 0; k < states.size(); ++k)
    if (!std::isfinite(states[k]) || !(states[k] >= 0))
      throw Error(name + "[" + std::to_string(k) + "]: " + FormatGeneral(states[k]) +
                  " is not a finite number of diopters >= 0");
}

std::vector<MeanScore> MeanScoresOverStates(const std::vector<RetinaStateResult>& states) {
  std::vector<MeanScore> means;
  for (size_t k = 0; !states.empty() && k < states.front().scores.size(); ++k) {
    double sum = 0;
    for (const RetinaStateResult& s : states) sum += s.scores[k].second;
    if (std::isnan(sum)) continue;  // no natural viewing
    for (const RetinalMetric& m : RetinalMetrics())
      if (m.column == states.front().scores[k].first) means.push_back({&m, sum / double(states.size())});
  }
  return means;
}

std::string RetinaStateName(double diopters) {
  char name[32];
  std::snprintf(name, sizeof name, "%.2fD", diopters);
  return name;
}

namespace {

std::vector<RetinaStateResult> TraceSweep(
    const DisplayModel& model, const Patterns& t, const SceneRadiance& natural, const RetinaSweepOptions& o,
    const std::string& folder, const std::function<void(size_t, size_t, const RetinaStateResult&)>& progress) {
  const DisplaySystem& system = model.system();
  CheckAccommodationStates(o.states_diopters, "retina: accommodation");
  const RetinaRunOptionEntry& resolution = RetinaRunOption("resolution");  // the run section's range
  if (!resolution.range.Contains(o.resolution_deg))
    throw Error("retina: " + OptionViolation("resolution", o.resolution_deg, resolution.Constraint()));
  const double field_x = o.field_x_deg > 0 ? o.field_x_deg * kRadiansPerDegree : system.fov_x_rad;
  const double field_y = o.field_y_deg > 0 ? o.field_y_deg * kRadiansPerDegree : system.fov_y_rad;
  const RetinaGrid grid =
      CenteredOnGaze(MakeRetinaGrid(field_x, field_y, o.resolution_deg * kRadiansPerDegree), system.eye.pose);
  const std::vector<PupilPoint> pupil = PupilSamples(system.eye);
  const EyeOptics optics(system.eye, pupil, grid);  // its parts of the OTF serve every state
  // What the panels show over a frame (their response), each instant through the panels' diffraction, once.
  const std::vector<ShownInstant> shown = SeenOverTime(system, t);
  const std::vector<const RetinalMetric*> metrics = o.metrics.empty() ? ParseRetinalMetrics("psnr", "") : o.metrics;
  if (natural) CheckMetricSize(metrics, grid.cols, grid.rows, "retina: metrics");

  const fs::path out = folder;
  fs::create_directories(out / "display");
  if (natural) fs::create_directories(out / "natural");
  std::string csv = "accommodation_D,display_mean_cd_m2,natural_mean_cd_m2,display_clipped_in_png,seconds";
  for (const RetinalMetric* m : metrics) csv += "," + m->column;
  const bool see_through = !system.worlds.empty();
  if (see_through) csv += ",world_cd_m2,contrast_against_world";
  csv += "\n";
  // States in batches: each state's images are computed (in parallel
  // within), then the batch's files are written in parallel. Writing, not
  // tracing, was most of a state's time (ZIP saves 5% of a float image at
  // 15 times the time of storing it; zlib's level 6 a sixth of a PNG at five times level 1's).
  const size_t batch = 4;
  std::vector<RetinaStateResult> results;
  RetinaWorkspace workspace;  // every state's display image, sized for the first (again only for one needing more)
  for (size_t first = 0; first < o.states_diopters.size(); first += batch) {
    const size_t count = std::min(batch, o.states_diopters.size() - first);
    RetinaBatch b = TraceBatch(model, shown, natural, o.world, optics, o.states_diopters, first, count, metrics,
                               o.metric_settings, &workspace);
    std::vector<double> seconds;
    WriteBatch(out, grid, bool(natural), o.exr_pixels, &b, &seconds);
    if (see_through) WriteSeeThrough(model, out, grid, o.exr_pixels, b);
    for (size_t s = 0; s < count; ++s) {
      RetinaStateResult& r = b.r[s];
      for (int f = 0; f < 4; ++f) r.seconds += seconds[s * 4 + f];
      char row[160];
      std::snprintf(row, sizeof row, "%.4f,%.6g,%.6g,%zu,%.3f", r.diopters, r.display_mean_cd_m2, r.natural_mean_cd_m2,
                    r.display_clipped_in_png, r.seconds);
      csv += row;
      for (const auto& [column, value] : r.scores) {
        std::snprintf(row, sizeof row, ",%.*f", column == "psnr_db" ? 4 : 6, value);
        csv += row;
      }
      if (see_through) {
        std::snprintf(row, sizeof row, ",%.6g,%.6g", r.world_cd_m2, r.contrast_against_world);
        csv += row;
      }
      csv += "\n";
      if (o.keep_images) r.display = std::move(b.display[s]), r.natural = std::move(b.seen[s]);
      results.push_back(std::move(r));
      if (progress) progress(results.size(), o.states_diopters.size(), results.back());
    }
  }
  WriteFileAtomically((out / "retina.csv").string(), csv);
  return results;
}

}  // namespace

std::vector<RetinaStateResult> WriteRetinaSweep(
    const DisplayModel& model, const Patterns& t, const SceneRadiance& natural, const RetinaSweepOptions& o,
    const std::string& folder, const std::function<void(size_t, size_t, const RetinaStateResult&)>& progress) {
  // A folded path's ghosts are seen with the display (systems/ghosts.h).
  std::optional<DisplayModel> ghosted;
  Patterns ghosted_patterns;
  if (!model.system().ghosts.empty()) {
    const GhostedDisplay g = WithGhosts(model.system());
    ghosted.emplace(g.system, model.geometry(), model.sampling());
    ghosted_patterns = GhostedPatterns(g, t);
  }
  return TraceSweep(ghosted ? *ghosted : model, ghosted ? ghosted_patterns : t, natural, o, folder, progress);
}

}  // namespace layerlab
