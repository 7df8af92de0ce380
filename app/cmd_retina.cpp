// layerlab retina SCENE.json --patterns DIR --accommodation 0.4,1.0,1.6,2.2 --out DIR:
// what the eye sees of the display at each accommodation state, and of the
// target itself (natural viewing) when one is given, as EXR (linear,
// display-relative) and PNG (sRGB, 1 = the brightest branch's full white).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "app/commands.h"
#include "app/number_list.h"
#include "framework/atomic_file.h"
#include "framework/error.h"
#include "framework/lightfield_io.h"
#include "framework/png_writer.h"
#include "framework/polarization.h"
#include "solvers/solution_writer.h"
#include "solvers/solve_config.h"
#include "systems/compile.h"
#include "systems/lightfield_radiance.h"
#include "systems/retina.h"
#if LAYERLAB_WITH_EMBREE
#include "systems/target/target_scene.h"
#include "systems/target/target_tracer.h"
#endif

namespace layerlab::app {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180;

double MeanLuminance(const Image& image) {
  double sum = 0;
  for (size_t k = 0; k < image.pixels.size(); ++k) sum += kLuminanceWeights[k % 3] * image.pixels[k];
  return sum / (double(image.width) * image.height);
}

std::string StateName(double diopters) {
  char name[32];
  std::snprintf(name, sizeof name, "%.2fD", diopters);
  return name;
}

}  // namespace

void AddRetinaCommand(CLI::App& app) {
  struct Options {
    std::string scene, patterns, target, target_scene, out, sampling;
    std::string accommodation = "0.4,1.0,1.6,2.2", focal_stack, field;
    double resolution = 0.05;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("retina", "Retinal images of the display (and of the target) over accommodation");
  cmd->add_option("scene", o->scene, "Display scene file (JSON)")->required();
  cmd->add_option("--patterns", o->patterns, "Output folder of `layerlab solve` (its patterns/)")->required();
  cmd->add_option("--accommodation", o->accommodation, "States in D, comma-separated (default 0.4,1.0,1.6,2.2)");
  cmd->add_option("--focal-stack", o->focal_stack, "Also first,last,step in D, e.g. 0,2.6,0.1");
  cmd->add_option("--target", o->target, "Light-field folder: natural viewing of it");
#if LAYERLAB_WITH_EMBREE
  cmd->add_option("--target-scene", o->target_scene, "Target scene (JSON): natural viewing traced with Embree");
#endif
  cmd->add_option("--resolution", o->resolution, "Retinal sample size in degrees (default 0.05)");
  cmd->add_option("--field", o->field, "Retinal field W,H in degrees (default: the display's field of view)");
  cmd->add_option("--sampling", o->sampling, "Layer sampling: nearest or bilinear (default: the scene's solve section)");
  cmd->add_option("--out", o->out, "Output folder")->required();
  cmd->callback([o] {
    // Everything is read and checked before anything is written.
    Scene scene = LoadScene(o->scene);
    DisplaySystem system = Compile(scene);
    SolveConfig config = ReadSolveConfig(scene, system);
    if (!o->sampling.empty()) config.sampling = SamplingFromString(o->sampling);
    if (!o->target.empty() && !o->target_scene.empty()) throw Error("give --target or --target-scene, not both");

    std::vector<double> states = ParseNumberList(o->accommodation, "--accommodation");
    if (!o->focal_stack.empty())
      for (double d : ParseRange(o->focal_stack, "--focal-stack")) states.push_back(d);
    std::sort(states.begin(), states.end());
    states.erase(std::unique(states.begin(), states.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }),
                 states.end());

    if (!(o->resolution > 0) || !(o->resolution < 10)) throw Error("--resolution: give degrees in (0, 10)");
    double field_x = system.fov_x, field_y = system.fov_y;
    if (!o->field.empty()) {
      std::vector<double> f = ParseNumberList(o->field, "--field");
      if (f.size() != 2 || !(f[0] > 0) || !(f[1] > 0) || f[0] >= 170 || f[1] >= 170)
        throw Error("--field: give W,H in degrees, each in (0, 170)");
      field_x = f[0] * kDeg, field_y = f[1] * kDeg;
    }
    const RetinaGrid grid = MakeRetinaGrid(field_x, field_y, o->resolution * kDeg);
    const std::vector<PupilPoint> pupil = PupilSamples(system.eye);

    std::optional<LightField> target_lf;
    if (!o->target.empty()) target_lf = ReadLightField(o->target, {.load_depth = false});
    const LightFieldGeometry g = target_lf ? target_lf->geometry : DisplayLightFieldGeometry(system);
    DisplayModel model(system, g, config.sampling);
    const Patterns t = ReadPatterns(model, o->patterns);

    SceneRadiance natural;
    if (target_lf) natural = LightFieldRadiance(*target_lf);
#if LAYERLAB_WITH_EMBREE
    std::optional<TargetScene> target_scene;
    std::unique_ptr<TargetTracer> tracer;
    if (!o->target_scene.empty()) {
      target_scene = LoadTarget(o->target_scene);
      tracer = std::make_unique<TargetTracer>(*target_scene);
      natural = [&tracer](const PupilPoint& u, double dx, double dy) {
        return tracer->TraceDirection(u.x, u.y, dx, dy).color;
      };
    }
#endif

    namespace fs = std::filesystem;
    fs::create_directories(fs::path(o->out) / "display");
    if (natural) fs::create_directories(fs::path(o->out) / "natural");
    std::fprintf(stderr, "retina: %d x %d samples of %.3f deg, %zu pupil points, %zu accommodation states\n", grid.cols,
                 grid.rows, o->resolution, pupil.size(), states.size());
    std::string csv = "accommodation_D,display_mean_cd_m2,natural_mean_cd_m2,display_clipped_in_png,seconds\n";
    const double white = model.white_luminance();
    for (size_t s = 0; s < states.size(); ++s) {
      auto start = std::chrono::steady_clock::now();
      const auto focus = ChannelAccommodation(system.eye, states[s]);
      const std::string name = StateName(states[s]);
      Image display = RetinaOfDisplay(model, t, grid, pupil, focus);
      WriteExr((fs::path(o->out) / "display" / (name + ".exr")).string(), display);
      size_t clipped =
          WriteSrgbPng((fs::path(o->out) / "display" / (name + ".png")).string(), grid.cols, grid.rows, display.pixels);
      double natural_mean = NAN;
      if (natural) {
        Image seen = RetinaOfScene(natural, grid, pupil, focus);
        WriteExr((fs::path(o->out) / "natural" / (name + ".exr")).string(), seen);
        WriteSrgbPng((fs::path(o->out) / "natural" / (name + ".png")).string(), grid.cols, grid.rows, seen.pixels);
        natural_mean = MeanLuminance(seen) * white;
      }
      double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      char row[160];
      std::snprintf(row, sizeof row, "%.4f,%.6g,%.6g,%zu,%.3f\n", states[s], MeanLuminance(display) * white,
                    natural_mean, clipped, seconds);
      csv += row;
      std::fprintf(stderr, "retina: %zu/%zu  %s  %.2f s\n", s + 1, states.size(), name.c_str(), seconds);
    }
    WriteFileAtomically((fs::path(o->out) / "retina.csv").string(), csv);
    std::printf("wrote %s/{display%s,retina.csv}: %zu states; values are display-relative (1 = %.4g cd/m2)\n",
                o->out.c_str(), natural ? ",natural" : "", states.size(), white);
  });
}

}  // namespace layerlab::app
