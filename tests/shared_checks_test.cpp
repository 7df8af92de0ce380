// The checks the command line and the Python module share (issue 40): a
// light-field geometry held to a manifest's limits wherever it comes from,
// light and transmittance values named by pixel, retina options by name and
// index, and a retina grid counted before it is cast.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "layerlab/analysis/retina_sweep.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/lightfield_checks.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/retina/retina.h"
#include "layerlab/solvers/solution_writer.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

// The field CheckLightFieldGeometry names and its reason, or "" when it passes.
std::string Refusal(const LightFieldGeometry& g) {
  try {
    CheckLightFieldGeometry(g,
                            [](const std::string& field, const std::string& why) { throw Error(field + ": " + why); });
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(SharedChecks, AGeometryBeyondAManifestsLimitsNamesTheField) {
  EXPECT_EQ(Refusal({}), "");
  auto with = [](auto edit) {
    LightFieldGeometry g;
    edit(g);
    return Refusal(g);
  };
  EXPECT_EQ(with([](auto& g) { g.cols = 0; }), "cols: must be in [1, 16384], got 0");
  EXPECT_EQ(with([](auto& g) { g.rows = 16385; }), "rows: must be in [1, 16384], got 16385");
  EXPECT_EQ(with([](auto& g) { g.views_x = -3; }), "views_x: must be in [1, 256], got -3");
  EXPECT_EQ(with([](auto& g) { g.views_y = 0; }), "views_y: must be in [1, 256], got 0");
  EXPECT_EQ(with([](auto& g) { g.origin_z_m = 0; }), "origin_z: must be in (0, 1e+06] m, got 0");
  EXPECT_EQ(with([](auto& g) { g.window_width_m = NAN; }), "window_width: must be in (0, 1e+06] m, got nan");
  EXPECT_EQ(with([](auto& g) { g.window_height_m = 2e6; }), "window_height: must be in (0, 1e+06] m, got 2e+06");
  EXPECT_EQ(with([](auto& g) { g.window_left_m = -INFINITY; }), "window_left: must be finite, got -inf");
  EXPECT_EQ(with([](auto& g) { g.window_top_m = NAN; }), "window_top: must be finite, got nan");
  EXPECT_EQ(with([](auto& g) { g.eyebox_width_m = -1e-3; }), "eyebox_width: must be in [0, 1] m, got -0.001");
  EXPECT_EQ(with([](auto& g) { g.eyebox_height_m = INFINITY; }), "eyebox_height: must be in [0, 1] m, got inf");
  EXPECT_EQ(with([](auto& g) { g.eyebox_width_m = 0; }), "");  // a pinhole eyebox, as a manifest may have
}

TEST(SharedChecks, RaysBeyondTwoToThe31AreRefused) {
  LightFieldGeometry g;
  g.views_x = g.views_y = 256, g.cols = g.rows = 16384;
  EXPECT_EQ(Refusal(g),
            "rays: 256 x 256 views of 16384 x 16384 pixels: 17592186044416 rays (views x pixels) is beyond the 2^31 "
            "this layerlab handles");
  g.views_x = g.views_y = 128, g.cols = g.rows = 362;  // 2^14 x 131044 = 2147024896: just inside
  EXPECT_EQ(Refusal(g), "");
}

TEST(SharedChecks, AManifestIsHeldToTheSameRayLimit) {
  const fs::path dir = fs::temp_directory_path() / ("layerlab_shared_checks_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "lightfield.json") << R"({"format": "lightfield/1", "origin_plane_z": 1,
      "window": {"left": -0.5, "top": 0.5, "width": 1, "height": 1},
      "resolution": {"cols": 16384, "rows": 16384},
      "views": {"rows": 256, "cols": 256, "eyebox_width": 0.006, "eyebox_height": 0.006},
      "views_pattern": "views/r{row:03}_c{col:03}.exr"})";
  try {
    ReadLightFieldGeometry(dir.string());
    ADD_FAILURE() << "a manifest of 2^44 rays was read";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().file, (dir / "lightfield.json").string());
    EXPECT_NE(e.message().find("17592186044416 rays (views x pixels) is beyond the 2^31"), std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

TEST(SharedChecks, AValueThatIsNotLightIsNamedWithItsViewAndPixel) {
  LightFieldGeometry g;
  g.views_x = 3, g.views_y = 2, g.cols = 4, g.rows = 2;
  LightField lf(g);
  EXPECT_NO_THROW(CheckLightFieldValues(lf, "target"));
  lf.view(4)[(1 * 4 + 2) * 3 + 1] = NAN;  // view 4 (row 1, col 1), pixel (row 1, col 2), G
  try {
    CheckLightFieldValues(lf, "target");
    ADD_FAILURE() << "a NaN was taken for light";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "target: view 4 (row 1, col 1): pixel (row 1, col 2) channel G is NaN; light must be finite and "
                 "non-negative");
  }
}

TEST(SharedChecks, ATransmittanceOutsideZeroToOneIsNamedWithItsPixel) {
  LayerPattern p(3, 2, 0.5f);
  EXPECT_NO_THROW(CheckTransmittance(p, "pattern 0 (front)"));
  auto refusal = [&](float value) {
    LayerPattern bad = p;
    bad.rgb[(1 * 3 + 2) * 3 + 2] = value;  // pixel (row 1, col 2), B
    try {
      CheckTransmittance(bad, "pattern 0 (front)");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(refusal(1.5f),
            "pattern 0 (front): pixel (row 1, col 2) channel B is 1.500000; a transmittance is in [0, 1]");
  EXPECT_EQ(refusal(NAN),
            "pattern 0 (front): pixel (row 1, col 2) channel B is NaN; light must be finite and non-negative");
  EXPECT_EQ(refusal(-0.5f),
            "pattern 0 (front): pixel (row 1, col 2) channel B is negative (-0.500000); light must "
            "be finite and non-negative");
  EXPECT_EQ(refusal(1.0f), "");
}

TEST(SharedChecks, AccommodationStatesAreNamedByIndex) {
  auto refusal = [](const std::vector<double>& states) {
    try {
      CheckAccommodationStates(states, "accommodation");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(refusal({0.4, 0.0, 2.6}), "");
  EXPECT_EQ(refusal({0.4, NAN}), "accommodation[1]: nan is not a finite number of diopters >= 0");
  EXPECT_EQ(refusal({-1.0}), "accommodation[0]: -1 is not a finite number of diopters >= 0");
  EXPECT_EQ(refusal({1.0, INFINITY}), "accommodation[1]: inf is not a finite number of diopters >= 0");
  EXPECT_EQ(refusal({}), "accommodation: no accommodation state given");
}

TEST(SharedChecks, ARetinaGridIsCountedBeforeItIsCast) {
  const double deg = M_PI / 180;
  // 170 deg at 1e-9 deg: 1.7e11 samples a side, beyond int; a cast wrapped it to a 1 x 1 grid.
  EXPECT_THROW(MakeRetinaGrid(170 * deg, 170 * deg, 1e-9 * deg), Error);
  EXPECT_THROW(MakeRetinaGrid(INFINITY, 1.0, 1e-3), Error);
  const RetinaGrid g = MakeRetinaGrid(20 * deg, 10 * deg, 0.05 * deg);
  EXPECT_EQ(g.cols, 400);
  EXPECT_EQ(g.rows, 200);
}

}  // namespace
}  // namespace layerlab
