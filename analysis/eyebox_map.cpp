#include "layerlab/analysis/eyebox_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "layerlab/analysis/retina_sweep.h"
#include "layerlab/analysis/run_option_table.h"
#include "layerlab/analysis/svg_plot.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"
#include "layerlab/retina/eye_optics.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/systems/eye_pose_limits.h"
#include "layerlab/systems/lc_response.h"
#include "layerlab/systems/source_spread.h"

namespace layerlab {
namespace {

// Grid positions along one axis: -half .. +half in `step`, through 0.
std::vector<double> Axis(double half, double step, const std::string& option) {
  if (half == 0) return {0.0};
  if (!(step > 0)) throw Error(option + ": a range needs a step above 0");
  const double count = std::floor(half / step + 1e-9);
  if (count > 50) throw Error(option + ": more than 101 positions along an axis; take a larger step");
  std::vector<double> at;
  for (int k = -int(count); k <= int(count); ++k) at.push_back(k * step);
  return at;
}

struct PoseGrid {
  std::vector<double> xs, ys;  // ys from the top
  double step = 0;
};

PoseGrid GridOf(const std::array<double, 2>& half, double step, const std::string& option) {
  PoseGrid g{Axis(half[0], step, option), Axis(half[1], step, option), step};
  std::reverse(g.ys.begin(), g.ys.end());
  return g;
}

// The retinal image's PSNR against the target's (peak 1), summed in double.
double RetinalPsnr(const Image& display, const Image& natural) {
  double sum = 0;
  for (size_t k = 0; k < display.pixels.size(); ++k) {
    const double d = double(display.pixels[k]) - double(natural.pixels[k]);
    sum += d * d;
  }
  return PsnrDb(sum, display.pixels.size());
}

struct PoseJob {
  EyePose pose;
  bool gaze;
};

// The poses of both grids, each checked before anything is computed. A light
// field holds the target's rays only across its eyebox; a traced target has them all.
std::vector<PoseJob> PosesToMap(const DisplaySystem& system, const SceneRadiance& natural, const EyeboxMapOptions& o,
                                PoseGrid* pupil_grid, PoseGrid* gaze_grid) {
  *pupil_grid = GridOf(o.pupil_half_range_m, o.pupil_step_m, "--eyebox-range");
  const bool with_gaze = o.gaze_half_range_rad[0] > 0 || o.gaze_half_range_rad[1] > 0;
  *gaze_grid = with_gaze ? GridOf(o.gaze_half_range_rad, o.gaze_step_rad, "--gaze-range") : PoseGrid{};
  const bool light_field = natural.target<LightFieldRays>() != nullptr;
  std::vector<PoseJob> jobs;
  EyePose base;
  base.rotation_radius_m = system.eye.pose.rotation_radius_m;
  for (double y : pupil_grid->ys)
    for (double x : pupil_grid->xs) {
      EyePose p = base;
      p.pupil_offset_m = {x, y};
      jobs.push_back({p, false});
    }
  for (double y : gaze_grid->ys)
    for (double x : gaze_grid->xs) {
      EyePose p = base;
      p.gaze_rad = {x, y};
      jobs.push_back({p, true});
    }
  for (const PoseJob& job : jobs) {
    EyeModel eye = system.eye;
    eye.pose = job.pose;
    const std::string option = job.gaze ? "--gaze-range" : "--eyebox-range";
    const std::string where = job.gaze ? "at a gaze of " + FormatFixed(job.pose.gaze_rad[0] * kDegreesPerRadian, 2) +
                                             ", " + FormatFixed(job.pose.gaze_rad[1] * kDegreesPerRadian, 2) + " deg"
                                       : "at a pupil offset of " + FormatFixed(job.pose.pupil_offset_m[0] * 1e3, 3) +
                                             ", " + FormatFixed(job.pose.pupil_offset_m[1] * 1e3, 3) + " mm";
    if (const std::string beyond = PupilBeyondEyebox(eye); !beyond.empty() && light_field)
      throw Error(option + ": " + where + " " + beyond + " (a target scene is traced from any pupil)");
    if (const std::string beyond = GazeBeyondField(system, job.pose); !beyond.empty())
      throw Error(option + ": " + where + ": " + beyond);
  }
  return jobs;
}

}  // namespace

std::array<double, 2> EyeboxGrid::within(double quality_db) const {
  std::array<double, 2> extent{0, 0};
  const double floor_db = centre().psnr_db - quality_db;
  auto ok = [&](int i, int j) { return poses[size_t(i) * cols + j].psnr_db >= floor_db; };
  int lo = cols / 2, hi = cols / 2;
  while (lo > 0 && ok(rows / 2, lo - 1)) --lo;
  while (hi < cols - 1 && ok(rows / 2, hi + 1)) ++hi;
  extent[0] = (hi - lo) * step;
  lo = hi = rows / 2;
  while (lo > 0 && ok(lo - 1, cols / 2)) --lo;
  while (hi < rows - 1 && ok(hi + 1, cols / 2)) ++hi;
  extent[1] = (hi - lo) * step;
  return extent;
}

std::array<bool, 2> EyeboxGrid::within_reaches_edge(double quality_db) const {
  const std::array<double, 2> extent = within(quality_db);
  return {extent[0] >= (cols - 1) * step * (1 - 1e-12), extent[1] >= (rows - 1) * step * (1 - 1e-12)};
}

EyeboxMap MapEyebox(const DisplayModel& model, const Patterns& t, const SceneRadiance& natural,
                    const EyeboxMapOptions& o, const std::function<void(size_t, size_t)>& progress) {
  const DisplaySystem& system = model.system();
  if (!natural) throw Error("eyebox: a map compares the display with its target: give a target");
  if (!(o.quality_db > 0) || !std::isfinite(o.quality_db)) throw Error("--quality: give a PSNR drop above 0 dB");
  for (double h : o.pupil_half_range_m)
    if (!(h >= 0) || h > kMaxPupilOffset) throw Error("--eyebox-range: each half range must lie in 0 to 50 mm");
  for (double h : o.gaze_half_range_rad)
    if (!(h >= 0) || h > kMaxGaze) throw Error("--gaze-range: each half range must lie in 0 to 50 deg");
  PoseGrid pupil_grid, gaze_grid;
  const std::vector<PoseJob> jobs = PosesToMap(system, natural, o, &pupil_grid, &gaze_grid);

  const RetinaRunOptionEntry& resolution = RetinaRunOption("resolution");
  if (!resolution.range.Contains(o.resolution_deg))
    throw Error("eyebox: " + OptionViolation("resolution", o.resolution_deg, resolution.Constraint()));
  const double sample_rad = o.resolution_deg * kRadiansPerDegree;
  const RetinaGrid pupil_retina =
      MakeRetinaGrid(o.field_deg[0] > 0 ? o.field_deg[0] * kRadiansPerDegree : system.fov_x_rad,
                     o.field_deg[1] > 0 ? o.field_deg[1] * kRadiansPerDegree : system.fov_y_rad, sample_rad);
  const RetinaGrid gaze_retina =
      MakeRetinaGrid(o.gaze_field_deg[0] * kRadiansPerDegree, o.gaze_field_deg[1] * kRadiansPerDegree, sample_rad);

  Patterns white;
  for (const LayerPattern& p : t) white.emplace_back(p.cols, p.rows, 1.0f);
  for (size_t k = 0; k < white.size(); ++k) {  // a fixed emission as it is, LEDs at full at their sites
    if (system.layers[k].panel.emitter && system.layers[k].panel.fixed_pattern)
      white[k].rgb = *system.layers[k].panel.fixed_pattern;
    KeepEmitterSites(system.layers[k], &white[k].rgb);
  }
  const double luminance = model.white_luminance();
  // What the panels show over a frame (their response), each instant through the panels' diffraction.
  const std::vector<ShownInstant> shown = SeenOverTime(system, t), shown_white = SeenOverTime(system, white);
  EyeboxMap map;
  map.quality_db = o.quality_db;
  map.pupil = {int(pupil_grid.xs.size()), int(pupil_grid.ys.size()), pupil_grid.step, {}};
  map.gaze = {int(gaze_grid.xs.size()), int(gaze_grid.ys.size()), gaze_grid.step, {}};
  std::vector<double> white_means;
  RetinaWorkspace workspace;
  for (size_t n = 0; n < jobs.size(); ++n) {
    EyeModel eye = system.eye;
    eye.pose = jobs[n].pose;
    const RetinaGrid grid = jobs[n].gaze ? CenteredOnGaze(gaze_retina, eye.pose) : pupil_retina;
    const std::vector<PupilPoint> pupil = PupilSamples(eye);
    const auto focus = ChannelAccommodation(eye, o.accommodation_diopters);
    const EyeOptics optics(eye, pupil, grid);
    std::vector<Image> displays, lits, seens;
    for (size_t k = 0; k < optics.groups(); ++k) {
      const DisplayRetinaTables tables(model, optics.traced(), optics.group(k), focus);
      displays.push_back(RetinaOfDisplay(model, shown, tables, &workspace));
      lits.push_back(RetinaOfDisplay(model, shown_white, tables, &workspace));
      seens.push_back(RetinaOfScene(natural, optics.traced(), optics.group(k), focus));
    }
    const Image display = optics.Combine(displays), lit = optics.Combine(lits), seen = optics.Combine(seens);
    EyeboxPoseResult r;
    r.pose = eye.pose;
    r.psnr_db = RetinalPsnr(display, seen);
    r.display_mean_cd_m2 = MeanLuminance(display) * luminance;
    r.natural_mean_cd_m2 = MeanLuminance(seen) * luminance;
    white_means.push_back(MeanLuminance(lit));
    (jobs[n].gaze ? map.gaze : map.pupil).poses.push_back(r);
    if (progress) progress(n + 1, jobs.size());
  }
  size_t first = 0;
  for (EyeboxGrid* g : {&map.pupil, &map.gaze}) {
    if (g->poses.empty()) continue;
    const size_t centre = g->centre_index();
    const double brightness = g->poses[centre].display_mean_cd_m2, lit = white_means[first + centre];
    for (size_t k = 0; k < g->poses.size(); ++k) {
      g->poses[k].brightness_ratio = g->poses[k].display_mean_cd_m2 / brightness;
      g->poses[k].vignetting = 1 - white_means[first + k] / lit;
    }
    first += g->poses.size();
  }
  return map;
}

void WriteEyeboxMap(const EyeboxMap& map, const std::string& folder) {
  std::string csv =
      "pupil_x_mm,pupil_y_mm,gaze_x_deg,gaze_y_deg,psnr_db,display_mean_cd_m2,natural_mean_cd_m2,brightness_ratio,"
      "vignetting\n";
  for (const EyeboxGrid* g : {&map.pupil, &map.gaze})
    for (const EyeboxPoseResult& r : g->poses) {
      char row[256];
      std::snprintf(row, sizeof row, "%.4f,%.4f,%.4f,%.4f,%.4f,%.6g,%.6g,%.6f,%.6f\n", r.pose.pupil_offset_m[0] * 1e3,
                    r.pose.pupil_offset_m[1] * 1e3, r.pose.gaze_rad[0] * kDegreesPerRadian,
                    r.pose.gaze_rad[1] * kDegreesPerRadian, r.psnr_db, r.display_mean_cd_m2, r.natural_mean_cd_m2,
                    r.brightness_ratio, r.vignetting);
      csv += row;
    }
  const std::filesystem::path out = folder;
  WriteFileAtomically((out / "eyebox.csv").string(), csv);

  // Per grid: PSNR and brightness against x, one line per row of the grid.
  const char* colors[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};
  std::vector<PlotPanel> panels;
  for (const EyeboxGrid* g : {&map.pupil, &map.gaze}) {
    if (g->poses.empty()) continue;
    const bool gaze = g == &map.gaze;
    const double unit = gaze ? kDegreesPerRadian : 1e3;
    PlotPanel psnr{gaze ? "over the gaze (pupil turning about its centre of rotation)" : "over the eyebox (gaze ahead)",
                   gaze ? "gaze right (deg)" : "pupil offset x (mm)",
                   "retinal PSNR (dB)",
                   0,
                   1,
                   0,
                   1,
                   {},
                   {},
                   {}};
    PlotPanel bright{gaze ? "brightness over the gaze" : "brightness over the eyebox",
                     psnr.x_label,
                     "display mean / centre's",
                     0,
                     1,
                     0,
                     1,
                     {},
                     {},
                     {}};
    double lo = INFINITY, hi = -INFINITY, blo = INFINITY, bhi = -INFINITY;
    for (int i = 0; i < g->rows; ++i) {
      const EyeboxPoseResult& first = g->poses[size_t(i) * g->cols];
      const double y = gaze ? first.pose.gaze_rad[1] : first.pose.pupil_offset_m[1];
      const std::string label = (gaze ? "up " : "y ") + FormatFixed(y * unit, 2) + (gaze ? " deg" : " mm");
      PlotLine line{label, colors[i % 8], i > 7, {}, {}}, b{label, colors[i % 8], i > 7, {}, {}};
      for (int j = 0; j < g->cols; ++j) {
        const EyeboxPoseResult& r = g->poses[size_t(i) * g->cols + j];
        const double x = (gaze ? r.pose.gaze_rad[0] : r.pose.pupil_offset_m[0]) * unit;
        if (std::isfinite(r.psnr_db)) {
          line.x.push_back(x), line.y.push_back(r.psnr_db);
          lo = std::min(lo, r.psnr_db), hi = std::max(hi, r.psnr_db);
        }
        b.x.push_back(x), b.y.push_back(r.brightness_ratio);
        blo = std::min(blo, r.brightness_ratio), bhi = std::max(bhi, r.brightness_ratio);
      }
      psnr.lines.push_back(line), bright.lines.push_back(b);
    }
    const double x_half = 0.5 * (g->cols - 1) * g->step * unit;
    for (PlotPanel* p : {&psnr, &bright}) p->x_min = -x_half, p->x_max = x_half > 0 ? x_half : 1;
    psnr.y_min = std::isfinite(lo) ? std::floor(lo - 1) : 0, psnr.y_max = std::isfinite(hi) ? std::ceil(hi + 1) : 1;
    bright.y_min = std::min(0.9, std::floor(blo * 20) / 20), bright.y_max = std::max(1.1, std::ceil(bhi * 20) / 20);
    panels.push_back(psnr), panels.push_back(bright);
  }
  WriteFileAtomically((out / "eyebox.svg").string(), RenderSvg(panels, 2, "The display across the eyebox"));
}

void WritePupilSwim(const std::vector<LayerSwim>& swim, const std::string& folder) {
  constexpr double kArcmin = 60 * kDegreesPerRadian;
  std::string csv = "layer,field_x_deg,field_y_deg,pupil_x_mm,pupil_y_mm,swim_x_arcmin,swim_y_arcmin\n";
  const char* colors[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd"};
  std::vector<PlotPanel> panels;
  for (const LayerSwim& layer : swim) {
    PlotPanel panel{"layer " + layer.layer, "pupil offset x (mm)", "swim x (arcmin)", 0, 1, -1, 1, {}, {}, {}};
    std::vector<double> fields;  // the field points on the midline, in order
    double lo = -0.1, hi = 0.1, reach = 0;
    for (const SwimSample& s : layer.samples) {
      char row[256];
      std::snprintf(row, sizeof row, "%s,%.4f,%.4f,%.4f,%.4f,%.5f,%.5f\n", layer.layer.c_str(),
                    std::atan(s.field_tan[0]) * kDegreesPerRadian, std::atan(s.field_tan[1]) * kDegreesPerRadian,
                    s.pupil_m[0] * 1e3, s.pupil_m[1] * 1e3, s.swim[0] * kArcmin, s.swim[1] * kArcmin);
      csv += row;
      if (s.pupil_m[1] != 0 || s.field_tan[1] != layer.samples.front().field_tan[1]) continue;
      size_t f = 0;
      while (f < fields.size() && fields[f] != s.field_tan[0]) ++f;
      if (f == fields.size()) {
        fields.push_back(s.field_tan[0]);
        panel.lines.push_back({"field " + FormatFixed(std::atan(s.field_tan[0]) * kDegreesPerRadian, 1) + " deg",
                               colors[f % 5],
                               false,
                               {0.0},
                               {0.0}});
      }
      panel.lines[f].x.push_back(s.pupil_m[0] * 1e3), panel.lines[f].y.push_back(s.swim[0] * kArcmin);
      if (std::isfinite(s.swim[0])) lo = std::min(lo, s.swim[0] * kArcmin), hi = std::max(hi, s.swim[0] * kArcmin);
      reach = std::max(reach, std::abs(s.pupil_m[0] * 1e3));
    }
    for (PlotLine& line : panel.lines) {  // in order of the pupil offset
      std::vector<size_t> order(line.x.size());
      for (size_t k = 0; k < order.size(); ++k) order[k] = k;
      std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return line.x[a] < line.x[b]; });
      PlotLine sorted = line;
      for (size_t k = 0; k < order.size(); ++k) sorted.x[k] = line.x[order[k]], sorted.y[k] = line.y[order[k]];
      line = sorted;
    }
    panel.x_min = -std::max(reach, 1e-3), panel.x_max = std::max(reach, 1e-3);
    panel.y_min = std::floor(lo * 10) / 10, panel.y_max = std::ceil(hi * 10) / 10;
    panels.push_back(panel);
  }
  const std::filesystem::path out = folder;
  WriteFileAtomically((out / "swim.csv").string(), csv);
  WriteFileAtomically((out / "swim.svg").string(), RenderSvg(panels, 2, "Pupil swim: apparent motion beyond parallax"));
}

}  // namespace layerlab
