// layerlab photograph CAPTURES_DIR --scene BUILT.json --out DIR: synthetic
// photographs of a capture plan on a display as built (calibration/synthetic_photo.h),
// to try the calibration loop without a prototype (docs/calibration.md). Given
// the folder of a camera capture plan (camera-patterns), the photographs of the
// printed chessboard at the planned poses instead (calibration/synthetic_chessboard.h),
// to try camera-intrinsics without a camera.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/number_list.h"
#include "layerlab/calibration/camera_capture_plan.h"
#include "layerlab/calibration/capture_plan.h"
#include "layerlab/calibration/measurements.h"
#include "layerlab/calibration/synthetic_chessboard.h"
#include "layerlab/calibration/synthetic_photo.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/checked_count.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/scene.h"

namespace layerlab::app {

namespace {

struct PhotographOptions {
  std::string captures, scene, out, camera, aperture = "1", focus = "1";
  std::vector<int> size = {720, 400};
  double white = 0.5, full_well = 20000, read_noise = 0.001;
  int bits = 0;
  uint64_t seed = 1;
};

std::string Shown(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

// Every number before anything is read: a NaN or negative one would otherwise make photographs of nothing.
void RequirePhotographOptions(const PhotographOptions& o) {
  const int width = o.size[0], height = o.size[1];
  const std::string size = "--size " + std::to_string(width) + " " + std::to_string(height);
  if (width <= 0 || height <= 0) throw Error(size + ": the width and height must be positive");
  const size_t pixels = CheckedProduct({static_cast<size_t>(width), static_cast<size_t>(height)}, size);
  if (pixels > kMaxPhotoPixels)
    throw Error(size + ": " + std::to_string(pixels) + " pixels; the limit is " + std::to_string(kMaxPhotoPixels) +
                " (what detect reads)");
  if (!std::isfinite(o.white) || !(o.white > 0))
    throw Error("--white " + Shown(o.white) + ": full white's signal must be a finite fraction of full scale above 0");
  if (!std::isfinite(o.full_well) || o.full_well < 0)
    throw Error("--full-well " + Shown(o.full_well) +
                ": the electrons at full scale must be finite and >= 0 (0: no photon noise)");
  if (!std::isfinite(o.read_noise) || o.read_noise < 0)
    throw Error("--read-noise " + Shown(o.read_noise) +
                ": the read noise must be a finite fraction of full scale, >= 0");
  if (o.bits < 0 || o.bits > 24)
    throw Error("--bits " + std::to_string(o.bits) + ": 0 (float) or 1 to 24 bits (a float holds 24)");
}

// The settings every photograph takes from the options; the intrinsics are the caller's.
PhotoCamera CameraOfOptions(const PhotographOptions& o) {
  PhotoCamera camera;
  camera.width = o.size[0];
  camera.height = o.size[1];
  camera.aperture_m = ParseOptionValue(o.aperture, "--aperture", kMillimeters) * 1e-3;
  camera.focus_diopters = ParseOptionValue(o.focus, "--focus", kDiopters, true);
  camera.white = o.white;
  camera.full_well = o.full_well;
  camera.read_noise = o.read_noise;
  camera.bits = o.bits;
  camera.seed = o.seed;
  return camera;
}

// A display's capture plan (captures.json) on the display as built.
void PhotographDisplay(const PhotographOptions& o) {
  if (o.scene.empty())
    throw Error("--scene is required: the display as built, whose photographs " + o.captures + "/captures.json plans");
  PhotoCamera camera = CameraOfOptions(o);
  const std::string plan_file = (std::filesystem::path(o.captures) / "captures.json").string();
  CapturePlan plan = ReadCapturePlanFile(plan_file);
  const DisplaySystem built = Compile(LoadScene(o.scene));
  if (!o.camera.empty())
    camera.intrinsics = ReadCameraIntrinsicsFile(o.camera);
  else if (plan.camera)
    camera.intrinsics = *plan.camera;
  else
    throw Error(plan_file + ": the plan has no \"camera\"; give the camera's intrinsics with --camera FILE");
  plan.camera = camera.intrinsics;
  std::vector<std::string> roots = {"captures.json"};
  for (const PlannedCapture& c : plan.captures) roots.push_back(c.photo);
  StagedOutput stage(o.out, "photograph", roots, {{o.captures, "the captures folder"}, {o.scene, "the scene"}});
  const PhotoRenderer renderer(camera);
  try {
    for (size_t k = 0; k < plan.captures.size(); ++k) {
      const PlannedCapture& c = plan.captures[k];
      const std::filesystem::path photo = std::filesystem::path(stage.staging()) / c.photo;
      std::filesystem::create_directories(photo.parent_path());
      WriteExr(photo.string(), renderer.Render(built, plan, c, k), ExrCompression::kZip);
    }
    WriteFileAtomically(stage.staging() + "/captures.json", CapturePlanToJson(plan).dump(2) + "\n");
  } catch (const Error& e) {
    throw stage.Explain(e);
  }
  stage.Commit();
  CommandResult result("photograph");
  result.Text("wrote " + std::to_string(plan.captures.size()) + " photographs and captures.json to " + o.out + "\n");
  result["out"] = o.out;
  result["photographs"] = plan.captures.size();
  result["of"] = "the display";
  result.Print();
}

// A camera capture plan (camera_captures.json): the printed board at each planned pose, through the camera
// --camera describes. The photographs are linear EXR; the plan written beside them names them so.
void PhotographBoard(const PhotographOptions& o) {
  if (!o.scene.empty())
    throw Error(o.captures + " holds a camera capture plan (" + kCameraCapturesFile +
                "), which photographs a printed chessboard, not a display: --scene does not apply");
  if (o.camera.empty())
    throw Error(o.captures + "/" + kCameraCapturesFile +
                ": give the camera to simulate with --camera FILE (a measurements-format \"camera\" object)");
  PhotoCamera camera = CameraOfOptions(o);
  camera.intrinsics = ReadCameraIntrinsicsFile(o.camera);
  CameraCapturePlan plan =
      ReadCameraCapturePlanFile((std::filesystem::path(o.captures) / kCameraCapturesFile).string());
  std::vector<std::string> roots = {kCameraCapturesFile};
  for (PlannedBoardPhoto& p : plan.photos) {
    p.photo = std::filesystem::path(p.photo).replace_extension(".exr").string();
    roots.push_back(p.photo);
  }
  plan.response = "linear";
  StagedOutput stage(o.out, "photograph", roots, {{o.captures, "the captures folder"}, {o.camera, "the camera file"}});
  const BoardPhotoRenderer renderer(camera);
  try {
    for (size_t k = 0; k < plan.photos.size(); ++k)
      WriteExr(stage.staging() + "/" + plan.photos[k].photo,
               renderer.Render(plan.board, PoseOfPlannedPhoto(plan.photos[k], plan.board, camera), k),
               ExrCompression::kZip);
    WriteFileAtomically(stage.staging() + "/" + kCameraCapturesFile, CameraCapturePlanToJson(plan).dump(2) + "\n");
  } catch (const Error& e) {
    throw stage.Explain(e);
  }
  stage.Commit();
  CommandResult result("photograph");
  result.Text("wrote " + std::to_string(plan.photos.size()) + " photographs of the printed board and " +
              kCameraCapturesFile + " to " + o.out + "\n");
  result["out"] = o.out;
  result["photographs"] = plan.photos.size();
  result["of"] = "the printed board";
  result.Print();
}

}  // namespace

void AddPhotographCommand(CLI::App& app) {
  using Options = PhotographOptions;
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "photograph", "Synthetic photographs of a capture plan: a display as built, or a printed chessboard");
  cmd->add_option("captures", o->captures,
                  "Folder written by calibration-patterns (captures.json) or camera-patterns (camera_captures.json)")
      ->required();
  cmd->add_option("--scene", o->scene,
                  "The display as built (scene JSON with its true placements); required for captures.json");
  cmd->add_option("--out", o->out, "Folder for captures.json and the photographs")->required();
  cmd->add_option("--camera", o->camera,
                  "The camera's intrinsics (JSON; default: the plan's; required for camera_captures.json)");
  cmd->add_option("--size", o->size, "Image width and height, pixels (default 720 400)")->expected(2);
  cmd->add_option("--aperture", o->aperture, "Entrance pupil diameter: mm, or with a unit (\"1 mm\"; default 1)");
  cmd->add_option("--focus", o->focus, "Focus: D, or a distance (\"1 m\"; default 1)");
  cmd->add_option("--white", o->white, "Signal of full white at exposure 1, fraction of full scale (default 0.5)");
  cmd->add_option("--full-well", o->full_well, "Electrons at full scale, for photon noise (default 20000; 0: none)");
  cmd->add_option("--read-noise", o->read_noise, "Read noise, fraction of full scale (default 0.001)");
  cmd->add_option("--bits", o->bits, "Round to this many bits (default 0: float)");
  // CLI11 reads "-1" into a uint64_t as 2^64 - 1: refuse the sign before that.
  cmd->add_option("--seed", o->seed, "Noise seed (default 1)")->check([](const std::string& text) {
    return text.find('-') == std::string::npos ? std::string() : "\"" + text + "\": the seed is 0 or more";
  });
  cmd->callback([o] {
    RequirePhotographOptions(*o);
    const bool board = std::filesystem::exists(std::filesystem::path(o->captures) / kCameraCapturesFile) &&
                       !std::filesystem::exists(std::filesystem::path(o->captures) / "captures.json");
    if (board)
      PhotographBoard(*o);
    else
      PhotographDisplay(*o);
  });
}

}  // namespace layerlab::app
