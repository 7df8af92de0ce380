// layerlab psf SCENE.json --out DIR: the scene eye's PSF and OTF by its
// pupil function beside the geometric path's (analysis/eye_psf.h).
#include <algorithm>
#include <cstdio>
#include <memory>

#include "layerlab/analysis/eye_psf.h"
#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/number_list.h"
#include "layerlab/eye/eye_description.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/framework/units.h"
#include "layerlab/systems/compile.h"

namespace layerlab::app {
namespace {

struct PsfCommandOptions {
  std::string scene, out, vergence, frequencies, spacing;
  int size = 255;
};

// Comma-separated vergence errors of either sign, each as ParseOptionValue reads its size.
std::vector<double> SignedDiopters(const std::string& text) {
  std::vector<double> values;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find(',', start), text.size());
    std::string item = text.substr(start, end - start);
    const size_t first = item.find_first_not_of(' ');
    const bool negative = first != std::string::npos && item[first] == '-';
    if (negative) item.erase(first, 1);
    const double size = ParseOptionValue(item, "--vergence", kDiopters);
    values.push_back(negative ? -size : size);
    start = end + 1;
  }
  return values;
}

void RunPsfCommand(const PsfCommandOptions& o) {
  EyePsfOptions options;
  if (!o.vergence.empty()) options.vergence_diopters = SignedDiopters(o.vergence);
  if (!o.frequencies.empty())
    options.frequencies_cpd = ParseNumberList(o.frequencies, "--frequencies", kCyclesPerDegree);
  if (!o.spacing.empty())
    options.psf_spacing_rad = ParseOptionValue(o.spacing, "--resolution", kDegrees) * kRadiansPerDegree;
  options.psf_size = o.size;
  const DisplaySystem system = Compile(LoadScene(o.scene));
  std::vector<std::string> written = {"mtf.csv", "mtf.svg"};
  for (double v : options.vergence_diopters) {
    char stem[64];
    std::snprintf(stem, sizeof stem, "psf_%.2fD", v);
    written.push_back(std::string(stem) + ".exr"), written.push_back(std::string(stem) + ".png");
  }
  StagedOutput stage(o.out, "psf", written, {{o.scene, "a scene"}});
  try {
    WriteEyePsf(system.eye, options, stage.staging());
  } catch (const Error& e) {
    throw stage.Explain(e);
  }
  stage.Commit();
  CommandResult result("psf");
  result.Text(EyeModelLine(system.eye) + "\nwrote " + o.out + "/{mtf.csv,mtf.svg,psf_*.exr,psf_*.png}\n");
  result["out"] = o.out;
  result["eye"] = EyeModelLine(system.eye);
  result["files"] = written;
  result.Print();
}

}  // namespace

void AddPsfCommand(CLI::App& app) {
  auto o = std::make_shared<PsfCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "psf", "The scene eye's PSF and OTF by its pupil function, beside its rays times the diffraction MTF");
  cmd->add_option("scene", o->scene, "Scene file (JSON): its eye")->required();
  cmd->add_option("--out", o->out, "Output folder")->required();
  cmd->add_option("--vergence", o->vergence,
                  "Vergence errors (object minus focus), comma-separated: D (default 0,0.1,0.25,0.5,1)");
  cmd->add_option("--frequencies", o->frequencies,
                  "Frequencies along x, comma-separated: cpd (default 2,5,10,20,30,60)");
  cmd->add_option("--resolution", o->spacing,
                  "PSF sample size: degrees or \"0.1 arcmin\" (default: half the aliasing limit lambda / (2 D) of "
                  "the bluest channel)");
  cmd->add_option("--size", o->size, "PSF samples per side (default 255)");
  cmd->callback([o] { RunPsfCommand(*o); });
}

}  // namespace layerlab::app
