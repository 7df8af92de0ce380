// layerlab camera-intrinsics DIR --out CAMERA.json: the measuring camera's
// intrinsics and their standard deviations from the photographs of a printed
// chessboard that camera-patterns planned (calibration/camera_calibration.h;
// needs OpenCV). Each photograph that cannot be used is named with its reason,
// and the rest go on.
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/calibration/camera_calibration.h"
#include "layerlab/calibration/measurements.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/framework/units.h"

namespace layerlab::app {
namespace {

std::string PlusMinus(double value, double sigma, int decimals) {
  return FormatFixed(value, decimals) + " +- " + FormatFixed(sigma, decimals);
}

std::string EstimateText(const IntrinsicsEstimate& e) {
  const CameraIntrinsics& c = e.camera;
  const CameraIntrinsicsUncertainty& u = *c.uncertainty;
  std::ostringstream out;
  out << "camera intrinsics from " << e.views.size() << " photographs (" << e.width << " x " << e.height
      << " pixels), one standard deviation:\n"
      << "  fx " << PlusMinus(c.fx, u.fx_px, 2) << " px   fy " << PlusMinus(c.fy, u.fy_px, 2) << " px\n"
      << "  cx " << PlusMinus(c.cx, u.cx_px, 2) << " px   cy " << PlusMinus(c.cy, u.cy_px, 2) << " px\n"
      << "  k1 " << PlusMinus(c.k1, u.k1, 4) << "   k2 " << PlusMinus(c.k2, u.k2, 4) << "\n"
      << "  reprojection error " << FormatFixed(u.rms_reprojection_px, 3) << " px RMS; per photograph:\n";
  for (const BoardView& v : e.views)
    out << "    " << v.photo << "  " << FormatFixed(v.rms_px, 3) << " px, the board tilted "
        << FormatFixed(v.tilt_rad * kDegreesPerRadian, 0) << " deg from face-on\n";
  return out.str();
}

}  // namespace

void AddCameraIntrinsicsCommand(CLI::App& app) {
  struct Options {
    std::string captures, out;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "camera-intrinsics", "Estimate the camera's intrinsics from photographs of a printed chessboard (OpenCV)");
  cmd->add_option("captures", o->captures,
                  std::string("Folder with ") + kCameraCapturesFile + " (from camera-patterns) and the photographs")
      ->required();
  cmd->add_option("--out", o->out, "The camera file to write (a measurements-format \"camera\" object, JSON)")
      ->required();
  cmd->callback([o] {
    RefuseOutputOverlappingInputs(o->out, {{o->captures, "the captures folder"}});
    const CameraCapturePlan plan =
        ReadCameraCapturePlanFile((std::filesystem::path(o->captures) / kCameraCapturesFile).string());
    const IntrinsicsEstimate e = EstimateIntrinsics(o->captures, plan);
    for (const PhotoFailure& f : e.failures) std::cerr << "warning: " << f.photo << ": " << f.reason << "\n";
    CommandResult result("camera-intrinsics");
    result.Text(EstimateText(e));
    WriteFileAtomically(o->out, CameraIntrinsicsToJson(e.camera).dump(2) + "\n");
    result.Text("used " + std::to_string(e.views.size()) + " of " + std::to_string(plan.photos.size()) +
                " photographs" +
                (e.failures.empty() ? "" : " (" + std::to_string(e.failures.size()) + " failed, named above)") +
                "; wrote " + o->out + "\n");
    result["out"] = o->out;
    result["camera"] = CameraIntrinsicsToJson(e.camera);
    result["photographs_used"] = e.views.size();
    result["photographs"] = plan.photos.size();
    result.Print();
  });
}

}  // namespace layerlab::app
