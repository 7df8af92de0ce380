// layerlab contrast SCENE... --out DIR: normalized contrast against
// accommodation for each display (the paper's Fig. 5).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "layerlab/analysis/contrast.h"
#include "layerlab/analysis/contrast_option_table.h"
#include "layerlab/analysis/report_parts.h"
#include "layerlab/app/command_line.h"
#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/number_list.h"
#include "layerlab/app/optics_options.h"
#include "layerlab/app/option_flags.h"
#include "layerlab/app/pose_option.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/framework/warnings.h"
#include "layerlab/retina/retina.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/system_report.h"

namespace layerlab::app {
namespace {

// The sweep's options are the contrast option table's (analysis/contrast_option_table.h).
struct ContrastCommandOptions {
  std::vector<std::string> scenes;
  std::string out, accommodation, factorized_for;
  OpticsOptions optics;
  OptionFlags flags;
  PoseOption pose;
};

// --accommodation's states as the sweep's FROM, TO and STEP: a range, or states evenly spaced (as
// `retina --accommodation` takes them).
std::array<double, 3> EvenSweep(const std::string& text, const std::string& option) {
  if (text.find(':') != std::string::npos && text.find(',') == std::string::npos) {
    const std::vector<double> r = ParseRangeBounds(text, option, kDiopters);
    return {r[0], r[1], r[2]};
  }
  std::vector<double> states = ParseStates(text, option, kDiopters);
  std::sort(states.begin(), states.end());
  const double step = states.size() > 1 ? states[1] - states[0] : 0;
  bool even = states.size() > 2 && step > 0;
  for (size_t k = 1; even && k < states.size(); ++k) even = std::abs(states[k] - states[k - 1] - step) <= 1e-6 * step;
  if (!even)
    throw Error(option + ": \"" + text + "\": the sweep takes a range FROM:TO:STEP (e.g. 0:2.6:0.05) or three or " +
                "more evenly spaced states");
  return {states.front(), states.back(), step};
}

// The options read and checked, before anything is loaded.
ContrastOptions ReadContrastOptions(const ContrastCommandOptions& o) {
  ContrastOptions options;
  ApplyOptionFlags(o.flags, ContrastOptionTable(), options);
  if (!o.accommodation.empty()) {
    const std::array<double, 3> range = EvenSweep(o.accommodation, FindContrastOption("accommodation")->cli_flag);
    options.accommodation_min_diopters = range[0];
    options.accommodation_max_diopters = range[1];
    options.accommodation_step_diopters = range[2];
  }
  CheckRetinaSampling(options.retina_field_deg, 3 * options.retina_resolution_deg, options.retina_resolution_deg,
                      FindContrastOption("retina_field")->cli_flag, FindContrastOption("retina_resolution")->cli_flag);
  if (std::string why; !options.IsValid(&why)) throw Error(NameTheFlag(ContrastOptionTable(), why));
  options.show_progress = true;
  return options;
}

void RunContrastCommand(const ContrastCommandOptions& o) {
  const ContrastOptions options = ReadContrastOptions(o);
  std::vector<ContrastDisplay> displays;
  std::vector<std::string> warnings;
  for (const std::string& file : o.scenes) {
    displays.push_back(LoadContrastDisplay(file));
    ApplyOpticsOptions(o.optics, &displays.back().system);
    // The eye moved and turned as the command line says: each display's retina is seen from there.
    if (const std::string warning = ApplyPoseOption(o.pose, &displays.back().system); !warning.empty())
      warnings.push_back(displays.back().name + ": " + warning);
  }
  std::optional<ContrastDisplay> foreign;
  if (!o.factorized_for.empty()) foreign = LoadContrastDisplay(o.factorized_for);
  const ContrastDisplay* factorized_for = foreign ? &*foreign : nullptr;
  if (std::string why = ContrastDisplayProblem(displays, options, factorized_for); !why.empty())
    throw Error(NameTheFlag(ContrastOptionTable(), why));
  for (const ContrastDisplay& d : displays)
    for (const std::string& w : d.system.warnings) warnings.push_back(d.name + ": " + w);
  for (const std::string& w : ContrastWarnings(displays, options)) warnings.push_back(w);
  SayWarnings(warnings);
  std::vector<NamedInput> inputs;
  for (const std::string& file : o.scenes) inputs.push_back({file, "a scene"});
  if (foreign) inputs.push_back({o.factorized_for, "a scene"});
  std::vector<std::string> written = {"contrast.csv", "peaks.txt", "contrast.svg", "index.html", "report.json"};
  if (options.eyebox_range_m > 0) written.insert(written.end(), {"eyebox_peaks.csv", "eyebox_peaks.svg"});
  StagedOutput stage(o.out, "contrast", written, inputs);
  auto start = std::chrono::steady_clock::now();
  std::vector<ContrastCurve> curves = RunContrast(displays, options, factorized_for);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const std::string peaks = PeakTable(curves);
  try {
    RunReportPage page = CommandPage("contrast", JoinWords(o.scenes, ", "), "", "", CommandLine());
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
  CommandResult result("contrast");
  result.Text(peaks);
  result.Text("sweep of " + std::to_string(curves.size()) + " curves in " + FormatFixed(seconds, 2) + " s; wrote " +
              o.out + "/{index.html,contrast.csv,peaks.txt,contrast.svg,report.json" +
              (options.eyebox_range_m > 0 ? ",eyebox_peaks.csv,eyebox_peaks.svg}\n" : "}\n"));
  result["out"] = o.out;
  result["seconds"] = seconds;
  result["peaks"] = PeaksJson(curves);
  result["warnings"] = warnings;
  result.Print();
}

}  // namespace

void AddContrastCommand(CLI::App& app) {
  auto o = std::make_shared<ContrastCommandOptions>();
  CLI::App* cmd = app.add_subcommand("contrast", "Normalized contrast against accommodation (Fig. 5)");
  cmd->add_option("scenes", o->scenes, "Display scene files (JSON)")->required();
  cmd->add_option("--out", o->out, "Output folder")->required();
  AddPoseOptions(cmd, o->pose);
  AddOpticsOptions(cmd, o->optics);
  AddOptionFlags(cmd, ContrastOptionTable(), o->flags, /*with_default=*/true);
  const ContrastOptionEntry& accommodation = *FindContrastOption("accommodation");
  cmd->add_option(accommodation.cli_flag, o->accommodation,
                  accommodation.cli_help + " (default " + accommodation.default_text + ")");
  const ContrastOptionEntry& factorized_for = *FindContrastOption("factorized_for");
  cmd->add_option(factorized_for.cli_flag, o->factorized_for, factorized_for.cli_help);
  cmd->callback([o] { RunContrastCommand(*o); });
}

}  // namespace layerlab::app
