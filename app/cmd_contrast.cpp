// layerlab contrast SCENE... --out DIR: normalized contrast against
// accommodation for each display (the paper's Fig. 5).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "layerlab/analysis/contrast.h"
#include "layerlab/analysis/report_parts.h"
#include "layerlab/app/command_line.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/number_list.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/framework/warnings.h"
#include "layerlab/retina/retina.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/system_report.h"

namespace layerlab::app {
namespace {

struct ContrastCommandOptions {
  std::vector<std::string> scenes;
  std::string out, depths = "0.7,1.3,1.9", frequencies = "2,4", accommodation = "0,2.6,0.05";
  std::string reference = "sampled", grating = "angle", resolution = "0.01", field = "20";
  int strip_rows = 24;
  bool no_peak_uncertainty = false;
};

// The options read and checked, before anything is loaded.
ContrastOptions ReadContrastOptions(const ContrastCommandOptions& o) {
  ContrastOptions options;
  options.target_diopters = ParseNumberList(o.depths, "--depths", kDiopters, true);
  options.frequencies = ParseNumberList(o.frequencies, "--frequencies", kCyclesPerDegree);
  const std::vector<double> range = ParseRangeBounds(o.accommodation, "--accommodation", kDiopters);
  options.accommodation_min = range[0];
  options.accommodation_max = range[1];
  options.accommodation_step = range[2];
  options.retina_resolution = ParseOptionValue(o.resolution, "--retina-resolution", kDegrees);
  options.retina_field = ParseOptionValue(o.field, "--retina-field", kDegrees);
  options.strip_rows = o.strip_rows;
  options.reference = o.reference == "sampled" ? ContrastReference::kSampledTarget : ContrastReference::kContinuous;
  options.grating = o.grating == "angle" ? GratingSpacing::kVisualAngle : GratingSpacing::kPlane;
  options.peak_uncertainty = !o.no_peak_uncertainty;
  CheckRetinaSampling(options.retina_field, 3 * options.retina_resolution, options.retina_resolution, "--retina-field",
                      "--retina-resolution");
  if (o.strip_rows < 1) throw Error("--strip-rows must be positive");
  for (double f : options.frequencies)
    if (!(f > 0)) throw Error("--frequencies: a frequency must be above 0 cpd");
  for (double d : options.target_diopters)
    if (!(d > 0)) throw Error("--depths: a target depth must be above 0 D");
  options.show_progress = true;
  return options;
}

void RunContrastCommand(const ContrastCommandOptions& o) {
  const ContrastOptions options = ReadContrastOptions(o);
  std::vector<ContrastDisplay> displays;
  for (const std::string& file : o.scenes) displays.push_back(LoadContrastDisplay(file));
  std::vector<std::string> warnings;
  for (const ContrastDisplay& d : displays)
    for (const std::string& w : d.system.warnings) warnings.push_back(d.name + ": " + w);
  for (const std::string& w : ContrastWarnings(displays, options)) warnings.push_back(w);
  SayWarnings(warnings);
  std::vector<NamedInput> inputs;
  for (const std::string& file : o.scenes) inputs.push_back({file, "a scene"});
  StagedOutput stage(o.out, "contrast", {"contrast.csv", "peaks.txt", "contrast.svg", "index.html", "report.json"},
                     inputs);
  auto start = std::chrono::steady_clock::now();
  std::vector<ContrastCurve> curves = RunContrast(displays, options);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const std::string peaks = PeakTable(curves);
  try {
    RunReportPage page = CommandPage("contrast", "", "", "", CommandLine());
    page.steps = {{"contrast sweep (" + std::to_string(curves.size()) + " curves)", seconds}};
    AddContrastToPage(curves, stage.staging(), "", &page);
    page.warnings = warnings;
    WriteReportPage(page, stage.staging());
    WriteFileAtomically(stage.staging() + "/report.json",
                        nlohmann::json{{"command", "contrast"}, {"warnings", warnings}}.dump(2) + "\n");
  } catch (const Error& e) {
    throw stage.Explain(e);
  }
  stage.Commit();
  std::cout << peaks;
  std::printf("sweep of %zu curves in %.2f s; wrote %s/{index.html,contrast.csv,peaks.txt,contrast.svg,report.json}\n",
              curves.size(), seconds, o.out.c_str());
}

}  // namespace

void AddContrastCommand(CLI::App& app) {
  auto o = std::make_shared<ContrastCommandOptions>();
  CLI::App* cmd = app.add_subcommand("contrast", "Normalized contrast against accommodation (Fig. 5)");
  cmd->add_option("scenes", o->scenes, "Display scene files (JSON)")->required();
  cmd->add_option("--out", o->out, "Output folder")->required();
  // The defaults are ContrastCommandOptions' own, quoted in the help from there.
  const auto with_default = [](const std::string& help, const std::string& value) {
    return help + " (default " + value + ")";
  };
  cmd->add_option(
      "--depths", o->depths,
      with_default("Target depths, comma-separated: D, or with units: \"0.7 D,1.3 D\", \"2 m\"", o->depths));
  cmd->add_option("--frequencies", o->frequencies, with_default("Frequencies, comma-separated: cpd", o->frequencies));
  cmd->add_option("--accommodation", o->accommodation,
                  with_default("first,last,step: D, or with units: \"0 D,2.6 D,0.05 D\"", o->accommodation));
  cmd->add_option("--retina-resolution", o->resolution,
                  with_default("Retinal sample size: degrees or \"0.6 arcmin\"", o->resolution));
  cmd->add_option("--retina-field", o->field, with_default("Retinal field width: degrees", o->field));
  cmd->add_option("--strip-rows", o->strip_rows,
                  with_default("Light-field rows around the axis", std::to_string(o->strip_rows)));
  cmd->add_option("--reference", o->reference,
                  "Normalize by natural viewing of the sampled target light field (sampled, default) or of the "
                  "continuous plane (continuous, the convention before issue 19)")
      ->check(CLI::IsMember({"sampled", "continuous"}));
  cmd->add_option("--grating", o->grating,
                  "Grating uniform in visual angle (angle, default) or in meters on the plane (plane, before issue 19)")
      ->check(CLI::IsMember({"angle", "plane"}));
  cmd->add_flag("--no-peak-uncertainty", o->no_peak_uncertainty,
                "Skip the second sweep on a retina moved by half a sample (the peaks' uncertainty)");
  cmd->callback([o] { RunContrastCommand(*o); });
}

}  // namespace layerlab::app
