// layerlab calibration-patterns SCENE.json --out DIR: the images to show on
// the panels while photographing them, and the capture plan (captures.json);
// docs/calibration.md.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/calibration/capture_plan.h"
#include "layerlab/calibration/measurements.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/png_writer.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/scene.h"

namespace layerlab::app {

// "x,y;x,y" in millimeters.
std::vector<std::array<double, 2>> ParsePositions(const std::string& text, const std::string& option) {
  std::vector<std::array<double, 2>> out;
  std::stringstream items(text);
  std::string item;
  while (std::getline(items, item, ';')) {
    double x = 0, y = 0;
    char tail = 0;
    if (std::sscanf(item.c_str(), " %lf , %lf %c", &x, &y, &tail) != 2)
      throw Error(option + ": \"" + item + "\" is not a position \"x,y\" in millimeters (positions separated by ;)");
    out.push_back({x * 1e-3, y * 1e-3});
  }
  if (out.empty()) throw Error(option + ": no camera position given");
  return out;
}

void AddCalibrationPatternsCommand(CLI::App& app) {
  struct Options {
    std::string scene, out, positions = "0,0;2,0;0,2", camera;
    std::vector<int> squares = {10, 6}, levels;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd =
      app.add_subcommand("calibration-patterns",
                         "Panel images (chessboards, luminance ramp) and the capture plan for calibrating a display");
  cmd->add_option("scene", o->scene, "Scene file as designed (JSON)")->required();
  cmd->add_option("--out", o->out, "Folder for patterns/ and captures.json")->required();
  cmd->add_option("--squares", o->squares, "Chessboard squares across and down (default 10 6)")->expected(2);
  cmd->add_option("--positions", o->positions,
                  "Camera positions in the eyebox, mm: \"x,y;x,y;...\" (default 0,0;2,0;0,2)");
  cmd->add_option("--levels", o->levels, "8-bit levels of the luminance ramp (default 0 16 ... 240 255)");
  cmd->add_option("--camera", o->camera,
                  "The camera's intrinsics (a measurements-format \"camera\" object, JSON), kept in the plan");
  cmd->callback([o] {
    if (std::string why = ChessboardSquaresProblem(o->squares[0], o->squares[1]); !why.empty())
      throw Error("--squares " + std::to_string(o->squares[0]) + " " + std::to_string(o->squares[1]) + ": " + why);
    const DisplaySystem system = Compile(LoadScene(o->scene));
    PlanOptions options;
    options.squares_x = o->squares[0];
    options.squares_y = o->squares[1];
    options.positions = ParsePositions(o->positions, "--positions");
    options.levels = o->levels;
    CapturePlan plan = PlanCaptures(system, options);
    if (!o->camera.empty()) plan.camera = ReadCameraIntrinsicsFile(o->camera);
    std::vector<NamedInput> inputs = {{o->scene, "the scene"}};
    if (!o->camera.empty()) inputs.push_back({o->camera, "the camera file"});
    StagedOutput stage(o->out, "calibration-patterns", {kPatternFolder, "captures.json"}, inputs);
    const auto files = PatternFiles(plan);
    try {
      std::filesystem::create_directories(stage.staging() + "/" + kPatternFolder);
      for (const auto& [panel, name] : files) {
        const PanelSpec* spec = nullptr;
        for (const VirtualLayer& layer : system.layers)
          if (layer.name == panel) spec = &layer.panel;
        WritePng8(stage.staging() + "/" + kPatternFolder + "/" + name, static_cast<int>(spec->resolution_cols),
                  static_cast<int>(spec->resolution_rows), 1, PatternImage(system, plan, panel, name),
                  PngCompression::kFast);
      }
      WriteFileAtomically(stage.staging() + "/captures.json", CapturePlanToJson(plan).dump(2) + "\n");
    } catch (const Error& e) {
      throw stage.Explain(e);
    }
    stage.Commit();
    CommandResult result("calibration-patterns");
    result.Text("wrote " + o->out + "/captures.json (" + std::to_string(plan.captures.size()) +
                " photographs to take) and " + std::to_string(files.size()) + " pattern images in " + o->out + "/" +
                kPatternFolder + "/\n");
    result["out"] = o->out;
    result["photographs_to_take"] = plan.captures.size();
    result["pattern_images"] = files.size();
    result.Print();
  });
}

}  // namespace layerlab::app
