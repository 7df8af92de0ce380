// layerlab detect CAPTURES_DIR --scene SCENE.json --out MEASUREMENTS.json:
// the photographs of a capture plan turned into the measurements `layerlab
// fit` reads (calibration/photo_detection.h; needs OpenCV). Each photograph
// that fails is reported with its reason, and the rest go on.
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/calibration/capture_plan.h"
#include "layerlab/calibration/measurements.h"
#include "layerlab/calibration/photo_detection.h"
#include "layerlab/calibration/photo_files.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/scene.h"

namespace layerlab::app {

void AddDetectCommand(CLI::App& app) {
  struct Options {
    std::string captures, scene, out, camera, photo_format = "auto";
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "detect", "Find the calibration patterns in photographs and write the measurements fit reads (OpenCV)");
  cmd->add_option("captures", o->captures, "Folder with captures.json and the photographs")->required();
  cmd->add_option("--scene", o->scene, "Scene file as designed (JSON)")->required();
  cmd->add_option("--out", o->out, "Measurements file to write (layerlab-measurements/1)")->required();
  cmd->add_option("--camera", o->camera, "The camera's intrinsics (JSON; default: the plan's \"camera\")");
  cmd->add_option(
      "--photo-format", o->photo_format,
      "Which file a photograph is read from: exr or png (x.exr or x.png where the plan names x.*), or "
      "auto (default: the plan's name, else the other of .exr and .png); each file is decoded by its content");
  cmd->callback([o] {
    const std::optional<PhotoFormat> format = PhotoFormatFromString(o->photo_format);
    if (!format) throw Error("--photo-format \"" + o->photo_format + "\": expected auto, exr or png");
    const std::string plan_file = (std::filesystem::path(o->captures) / "captures.json").string();
    std::vector<NamedInput> inputs = {{o->captures, "the captures folder"}, {o->scene, "the scene"}};
    if (!o->camera.empty()) inputs.push_back({o->camera, "the camera file"});
    RefuseOutputOverlappingInputs(o->out, inputs);
    const CapturePlan plan = ReadCapturePlanFile(plan_file);
    const DisplaySystem designed = Compile(LoadScene(o->scene));
    std::optional<CameraIntrinsics> camera;
    if (!o->camera.empty()) camera = ReadCameraIntrinsicsFile(o->camera);
    const Detection d = DetectCaptures(o->captures, plan, designed, camera, {}, *format);
    for (const std::string& note : d.notes) Note("note: " + note);
    for (const std::string& warning : d.warnings) std::cerr << "warning: " << warning << "\n";
    for (const PhotoFailure& f : d.failures) std::cerr << "warning: " << f.photo << ": " << f.reason << "\n";
    if (d.corners == 0 && d.luminance_steps == 0)
      throw Error(o->captures + ": no photograph could be used (" + std::to_string(d.failures.size()) +
                  " failed, each named above); nothing was written");
    WriteFileAtomically(o->out, FormatMeasurements(d.measurements));
    std::ostringstream text;
    text << "detected " << d.corners << " corners and " << d.luminance_steps << " luminance steps in "
         << plan.captures.size() - d.failures.size() << " of " << plan.captures.size() << " photographs";
    if (!d.failures.empty()) text << " (" << d.failures.size() << " failed, named above)";
    text << "; wrote " << o->out << "\n";
    CommandResult result("detect");
    result.Text(text.str());
    result["out"] = o->out;
    result["corners"] = d.corners;
    result["luminance_steps"] = d.luminance_steps;
    result["photographs"] = plan.captures.size();
    result["failed"] = nlohmann::json::array();
    for (const PhotoFailure& f : d.failures) result["failed"].push_back({{"photo", f.photo}, {"reason", f.reason}});
    result.Print();
  });
}

}  // namespace layerlab::app
