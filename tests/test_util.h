// One home for test helpers: tolerances, scene fixtures, captured errors.
#pragma once

#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "layerlab/framework/error.h"
#include "layerlab/framework/lightfield.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/display_model.h"

namespace layerlab::testing {

// |actual - expected| <= max(abs_tol, rel_tol * |expected|).
::testing::AssertionResult Close(double actual, double expected, double rel_tol, double abs_tol = 0.0);

// Values uniform in [lo, hi] (std::mt19937 from `seed`): every layer's, or every ray's in [0, 1].
Patterns RandomPatterns(const DisplayModel& model, unsigned seed, float lo, float hi);
LightField RandomLightField(const LightFieldGeometry& g, unsigned seed);

std::string ExamplePath(const std::string& name);  // examples/<name>
nlohmann::json ReadExample(const std::string& name);

// A one-panel display: the multiplicative two-layer example cut to its rear
// panel of 64 x 48 pixels at `depth` ("1.0 D"), its model bound to the
// display's light field at 1 D, and patterns all 0 for the test to fill.
struct OneLayer {
  DisplaySystem system;
  std::unique_ptr<DisplayModel> model;
  Patterns t;
};
OneLayer OneLayerDisplay(const std::string& depth);

// Parses and compiles a scene given as JSON; throws layerlab::Error.
DisplaySystem CompileJson(const nlohmann::json& scene, const std::string& file = "scene.json");
DisplaySystem CompileJson(const nlohmann::json& scene, const ElementRegistry& registry,
                          const std::string& file = "scene.json");

// The Error's what() from compiling `scene`, or "" if it compiled.
std::string CompileError(const nlohmann::json& scene);

// An example display shrunk for fast tests: every panel's active region
// `cols` x `rows`, the eye's views `views` x `views`.
nlohmann::json ShrunkExample(const std::string& name, int cols, int rows, int views);

// A light field of `views` x `views` views over a 6 mm eyebox and a 10 x 6 deg
// window on its origin plane at 1.3 D, of `cols` x `rows` pixels.
LightFieldGeometry WindowGeometry(int cols, int rows, int views);

// The layerlab::Error's what() from `call`, or "no error" when it returns.
template <class Call>
std::string ErrorOf(Call&& call) {
  try {
    call();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// Finds the element named `name` in a scene document.
nlohmann::json& ElementNamed(nlohmann::json& scene, const std::string& name);

}  // namespace layerlab::testing
