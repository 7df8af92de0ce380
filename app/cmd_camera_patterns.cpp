// layerlab camera-patterns --out DIR: the chessboard to print and the plan of
// the photographs to take of it (camera_captures.json) for estimating the
// measuring camera's intrinsics with camera-intrinsics; docs/calibration.md.
#include <iostream>
#include <memory>
#include <sstream>

#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/number_list.h"
#include "layerlab/calibration/camera_capture_plan.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/png_writer.h"
#include "layerlab/framework/staged_output.h"

namespace layerlab::app {

void AddCameraPatternsCommand(CLI::App& app) {
  struct Options {
    std::string out, square_size = "20 mm";
    std::vector<int> squares = {10, 7};
    int poses = 12;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "camera-patterns", "A chessboard to print and the photographs of it to take, for the camera's intrinsics");
  cmd->add_option("--out", o->out, std::string("Folder for the board's image and ") + kCameraCapturesFile)->required();
  cmd->add_option("--squares", o->squares, "Chessboard squares across and down (default 10 7)")->expected(2);
  cmd->add_option("--square-size", o->square_size,
                  "The printed square's size: mm, or with a unit (\"20 mm\"; default 20); measure it on the print");
  cmd->add_option("--poses", o->poses, "Photographs to take, 3 to 100 (default 12)");
  cmd->callback([o] {
    CameraPlanOptions options;
    options.squares_x = o->squares[0];
    options.squares_y = o->squares[1];
    options.square_m = ParseOptionValue(o->square_size, "--square-size", kMillimeters) * 1e-3;
    options.poses = o->poses;
    const CameraCapturePlan plan = PlanCameraCaptures(options);
    const PrintedChessboard& board = plan.board;
    StagedOutput stage(o->out, "camera-patterns", {board.image, kCameraCapturesFile}, {});
    try {
      WritePng8(stage.staging() + "/" + board.image, board.image_width(), board.image_height(), 1,
                PrintedChessboardImage(board), PngCompression::kSmallest, board.pixels_per_square / board.square_m);
      WriteFileAtomically(stage.staging() + "/" + kCameraCapturesFile, CameraCapturePlanToJson(plan).dump(2) + "\n");
    } catch (const Error& e) {
      throw stage.Explain(e);
    }
    stage.Commit();
    std::ostringstream text;
    text << "wrote " << o->out << "/" << board.image << " (" << board.squares_x << " x " << board.squares_y
         << " squares; print it at " << FormatGeneral(board.square_m * 1e3)
         << " mm per square, measure a printed square and correct \"square_size\" if it differs, and keep it "
            "flat) and "
         << o->out << "/" << kCameraCapturesFile << " (" << plan.photos.size()
         << " photographs to take, each with its pose)\n";
    CommandResult result("camera-patterns");
    result.Text(text.str());
    result["out"] = o->out;
    result["board_image"] = board.image;
    result["square_size_m"] = board.square_m;
    result["photographs_to_take"] = plan.photos.size();
    result.Print();
  });
}

}  // namespace layerlab::app
