// The compiled paper prototype and its variants against numbers derived by hand.
#include <cmath>
#include <numbers>

#include "layerlab/framework/units.h"
#include "layerlab/systems/system_report.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::Close;
using testing::CompileJson;
using testing::ElementNamed;
using testing::ReadExample;

TEST(Compile, PaperPrototypeMatchesTable1) {
  DisplaySystem s = CompileJson(ReadExample("paper_prototype.json"));
  ASSERT_EQ(s.layers.size(), 4u);
  ASSERT_EQ(s.branches.size(), 2u);
  const double f = 0.075, e = 0.01, p = 117e-6;
  const double diopters[] = {0.4, 1.0, 1.6, 2.2};
  const double distance_mm[] = {72.81, 69.72, 66.85, 64.17};
  const double magnification[] = {34.2, 14.2, 9.2, 6.93};
  for (int k = 0; k < 4; ++k) {
    const VirtualLayer& l = s.layers[k];
    double d = 1 / diopters[k] - e;  // image distance behind the lens
    double M = 1 + d / f;            // = d / s with 1/s = 1/f + 1/d
    EXPECT_TRUE(Close(l.diopters, diopters[k], 1e-12));
    EXPECT_TRUE(Close(l.panel_distance_m * 1e3, distance_mm[k], 0, 0.005)) << l.name;
    EXPECT_TRUE(Close(l.magnification, M, 1e-12));
    EXPECT_TRUE(Close(l.magnification, magnification[k], 0, 0.01));
    EXPECT_TRUE(Close(l.pitch_x_m, M * p, 1e-12));
    EXPECT_TRUE(Close(l.tan_pitch_x, M * p * diopters[k], 1e-12));
    EXPECT_EQ(l.cols, 400);
    EXPECT_EQ(l.rows, 200);
  }
  // The farthest layer sets the field: 2 atan(4.0014 mm x 400 / (2 x 2.5 m)).
  EXPECT_TRUE(Close(s.fov_x_rad * kDegreesPerRadian, 2 * std::atan(34.2 * p * 400 / 5.0) * kDegreesPerRadian, 1e-12));
  EXPECT_TRUE(Close(s.fov_x_rad * kDegreesPerRadian, 35.5, 0, 0.05));
  EXPECT_TRUE(Close(s.fov_y_rad * kDegreesPerRadian, 18.2, 0, 0.05));
  EXPECT_TRUE(Close(s.max_cpd, 1 / (2 * std::atan(34.2 * p / 2.5) * kDegreesPerRadian), 1e-12));
  EXPECT_TRUE(Close(s.max_cpd, 5.4, 0, 0.06));
  // What every layer can show is the coarsest layer's Nyquist: the 2.2 D layer's.
  const double M = 1 + (1 / 2.2 - e) / f;
  EXPECT_TRUE(Close(EveryLayerMaxCpd(s), 1 / (2 * std::atan(M * p * 2.2) * kDegreesPerRadian), 1e-12));
  EXPECT_TRUE(Close(EveryLayerMaxCpd(s), 4.89, 0, 0.005));
}

// A panel of unequal pixel pitches, offset from the axis: each axis keeps its own pitch and offset. By hand
// (the rear panel at 0.4 D behind the 75 mm lens 1 cm from the eye): M = 1 + (1 / 0.4 - 0.01) / 0.075, and a
// panel length x is seen under the tan-angle x M D.
TEST(Compile, UnequalPixelPitchesAndAVerticalOffsetKeepEachAxisApart) {
  nlohmann::json scene = ReadExample("multiplicative_2layer.json");
  nlohmann::json& rear = ElementNamed(scene, "rear");
  rear["pixel_pitch"] = {"117 um", "90 um"};
  rear["offset"] = {"1 mm", "-2.5 mm"};
  const DisplaySystem s = CompileJson(scene);
  const VirtualLayer* l = nullptr;
  for (const VirtualLayer& layer : s.layers)
    if (layer.name == "rear") l = &layer;
  ASSERT_NE(l, nullptr);
  const double D = 0.4, M = 1 + (1 / D - 0.01) / 0.075;
  EXPECT_TRUE(Close(l->pitch_x_m, M * 117e-6, 1e-12));
  EXPECT_TRUE(Close(l->pitch_y_m, M * 90e-6, 1e-12));
  EXPECT_TRUE(Close(l->tan_pitch_x, M * D * 117e-6, 1e-12));
  EXPECT_TRUE(Close(l->tan_pitch_y, M * D * 90e-6, 1e-12));
  EXPECT_TRUE(Close(l->eye_from_layer_tan_x, M * D * 1e-3, 1e-12));
  EXPECT_TRUE(Close(l->eye_from_layer_tan_y, M * D * -2.5e-3, 1e-12));
  EXPECT_TRUE(Close(l->fov_x_rad, 2 * std::atan(400 * M * D * 117e-6 / 2), 1e-12));
  EXPECT_TRUE(Close(l->fov_y_rad, 2 * std::atan(200 * M * D * 90e-6 / 2), 1e-12));
}

// An [r, g, b] black level of equal values is read whole, as the scalar is
// (different values are refused: bad_scene_test BlackLevelPerChannel).
TEST(Compile, BlackLevelIsReadAsOneValueForAllChannels) {
  for (const nlohmann::json& given :
       {nlohmann::json(0.02), nlohmann::json("2 %"), nlohmann::json({0.02, 0.02, 0.02})}) {
    nlohmann::json scene = ReadExample("multiplicative_2layer.json");
    ElementNamed(scene, "rear")["black_level"] = given;
    const DisplaySystem s = CompileJson(scene);
    int found = 0;
    for (const VirtualLayer& l : s.layers)
      if (l.name == "rear") {
        EXPECT_DOUBLE_EQ(l.panel.black_level, 0.02) << given.dump();
        ++found;
      }
    EXPECT_EQ(found, 1) << given.dump();
  }
}

TEST(Compile, PaperBranchesPairFarAndMidPlanes) {
  // Eq. 5: l = P1 t1 . P3 t3 + P2 t2 . P4 t4 with 1 the farthest plane.
  DisplaySystem s = CompileJson(ReadExample("paper_prototype.json"));
  EXPECT_EQ(s.branches[0].layers, (std::vector<int>{2, 0}));  // 1.6 D in front of 0.4 D
  EXPECT_EQ(s.branches[1].layers, (std::vector<int>{3, 1}));  // 2.2 D in front of 1.0 D
  EXPECT_EQ(s.layers[2].position_in_branch, 0);
  EXPECT_EQ(s.layers[0].position_in_branch, 1);
}

TEST(Compile, FlipsComeFromReversedPanelsAndTheMirror) {
  DisplaySystem s = CompileJson(ReadExample("paper_prototype.json"));
  auto layer = [&](const std::string& name) {
    for (const VirtualLayer& l : s.layers)
      if (l.name == name) return l;
    throw std::runtime_error(name);
  };
  EXPECT_FALSE(layer("rear_a").flip_x);   // transmitted, mounted normally
  EXPECT_TRUE(layer("front_a").flip_x);   // transmitted, reversed
  EXPECT_TRUE(layer("rear_b").flip_x);    // reflected by the horizontal fold
  EXPECT_FALSE(layer("front_b").flip_x);  // reflected and reversed: the two cancel
  for (const VirtualLayer& l : s.layers) EXPECT_FALSE(l.flip_y);
}

// A horizontal fold mirrors the reflected branch left-right, a vertical one upside down; a reversed panel flips
// left-right on top. Both folds, for the half mirror of the paper prototype and as a fold mirror in front of it.
TEST(Compile, FlipsFollowTheFoldAxis) {
  for (const char* fold : {"horizontal", "vertical"})
    for (const bool as_mirror : {false, true}) {
      SCOPED_TRACE(std::string(fold) + (as_mirror ? " fold mirror" : " half mirror"));
      nlohmann::json scene = ReadExample("paper_prototype.json");
      const bool horizontal = std::string(fold) == "horizontal";
      if (as_mirror) {  // the half mirror keeps its horizontal fold; a fold mirror in front of it adds its own
        scene["elements"].push_back({{"type", "mirror"}, {"name", "fold"}, {"fold", fold}, {"next", "half_mirror"}});
        ElementNamed(scene, "lens")["next"] = "fold";
      } else {
        ElementNamed(scene, "half_mirror")["fold"] = fold;
      }
      const DisplaySystem s = CompileJson(scene);
      for (const VirtualLayer& l : s.layers) {
        const bool reflected = l.name == "rear_b" || l.name == "front_b", reversed = l.name[0] == 'f';
        bool flip_x = reversed, flip_y = false;
        if (as_mirror) {  // every layer through the fold mirror, the reflected ones through the half mirror too
          (horizontal ? flip_x : flip_y) ^= true;
          if (reflected) flip_x ^= true;
        } else if (reflected) {
          (horizontal ? flip_x : flip_y) ^= true;
        }
        EXPECT_EQ(l.flip_x, flip_x) << l.name;
        EXPECT_EQ(l.flip_y, flip_y) << l.name;
      }
    }
}

TEST(Compile, BrightnessOfTheDisplayVariants) {
  // Per backlight: half mirror 0.5 times two panels at 0.3 each.
  DisplaySystem hybrid = CompileJson(ReadExample("paper_prototype.json"));
  DisplaySystem multiplicative = CompileJson(ReadExample("multiplicative_2layer.json"));
  DisplaySystem additive = CompileJson(ReadExample("additive_2layer.json"));
  EXPECT_TRUE(Close(hybrid.luminance_efficiency, 0.5 * 0.3 * 0.3, 1e-12));
  EXPECT_TRUE(Close(multiplicative.luminance_efficiency, 0.3 * 0.3, 1e-12));
  EXPECT_TRUE(Close(additive.luminance_efficiency, 0.5 * 0.3, 1e-12));
  EXPECT_TRUE(Close(hybrid.luminance_efficiency / multiplicative.luminance_efficiency, 0.5, 1e-12));
  // Full white with both 250 cd/m2 backlights: 2 x 250 x 0.045.
  EXPECT_TRUE(Close(hybrid.peak_luminance_cd_m2[1], 22.5, 1e-12));
  for (const Branch& b : hybrid.branches) EXPECT_TRUE(Close(b.efficiency[0], 0.045, 1e-12));
}

TEST(Compile, PanelAtTheFocalPlaneIsALayerAtInfinity) {
  nlohmann::json scene = ReadExample("multiplicative_2layer.json");
  nlohmann::json& rear = ElementNamed(scene, "rear");
  rear.erase("virtual_depth");
  rear["distance"] = "75 mm";
  DisplaySystem s = CompileJson(scene);
  const VirtualLayer& l = s.layers[0];
  EXPECT_EQ(l.diopters, 0.0);
  EXPECT_TRUE(std::isinf(l.depth_m));
  EXPECT_TRUE(Close(l.tan_pitch_x, 117e-6 / 0.075, 1e-12));
  EXPECT_TRUE(std::isfinite(s.fov_x_rad));
  EXPECT_TRUE(Close(s.fov_x_rad, 2 * std::atan(400 * 117e-6 / 0.075 / 2), 1e-12));
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0], "panel \"rear\" sits at the focal plane: its image is at infinity (0 D)");
}

TEST(Compile, DistanceAndVirtualDepthAgree) {
  nlohmann::json scene = ReadExample("multiplicative_2layer.json");
  nlohmann::json& rear = ElementNamed(scene, "rear");
  rear.erase("virtual_depth");
  rear["distance"] = "72.8070175 mm";  // 1 / (1/75 + 1/2490) mm
  DisplaySystem s = CompileJson(scene);
  EXPECT_TRUE(Close(s.layers[0].diopters, 0.4, 1e-5));
}

TEST(Compile, ListsOnlyTheComponentsInUse) {
  DisplaySystem multiplicative = CompileJson(ReadExample("multiplicative_2layer.json"));
  EXPECT_EQ(multiplicative.components,
            (std::vector<std::string>{"thin-lens floating (2 virtual layers)", "multiplicative stacks in 1 branch",
                                      "no polarization model (no polarizing element)",
                                      "mirrored layers (reversed panels or reflected branches)"}));
  DisplaySystem pbs = CompileJson(ReadExample("hybrid_pbs_hwp.json"));
  EXPECT_TRUE(pbs.polarization_tracked);
  EXPECT_FALSE(CompileJson(ReadExample("paper_prototype.json")).polarization_tracked);
}

// A thin lens standing in for a 3 mm lenslet compiled silently as a magnifier of 150 deg; first-order
// optics is now said not to hold there, with the field it was asked to cover, and so is a lens faster than
// f/1. None of the shipped examples is warned of.
TEST(Compile, AThinLensBeyondFirstOrderIsWarnedOf) {
  auto first_order = [](const DisplaySystem& s) {
    std::string found;
    for (const std::string& w : s.warnings)
      if (w.find("modelled to first order outside where that holds") != std::string::npos) found = w;
    return found;
  };
  nlohmann::json lenslet = ReadExample("multiplicative_2layer.json");
  ElementNamed(lenslet, "lens")["focal_length"] = "3 mm";
  ElementNamed(lenslet, "lens")["clear_aperture"] = "3 mm";
  const DisplaySystem wide = CompileJson(lenslet);
  const std::string warning = first_order(wide);
  const double fx = wide.layers.front().fov_x_rad / kRadiansPerDegree;
  ASSERT_GT(fx, kFirstOrderFieldDeg);
  EXPECT_NE(warning.find("\"lens\""), std::string::npos) << warning;
  EXPECT_NE(warning.find(FormatFixed(fx, 0) + " x "), std::string::npos) << warning;
  EXPECT_NE(warning.find("describe it as a \"lens\" of surfaces"), std::string::npos) << warning;

  nlohmann::json fast = ReadExample("multiplicative_2layer.json");
  ElementNamed(fast, "lens")["clear_aperture"] = "100 mm";  // 75 mm over 100 mm: f/0.75
  EXPECT_NE(first_order(CompileJson(fast)).find("it is f/0.75 (75.00 mm over a 100.00 mm clear aperture)"),
            std::string::npos)
      << first_order(CompileJson(fast));

  // A tunable lens is first-order too: at its strongest power (13.8841 D: 72.02 mm) over 80 mm, f/0.90.
  nlohmann::json tunable = ReadExample("multifocal_tunable_4plane.json");
  ElementNamed(tunable, "tunable")["clear_aperture"] = "80 mm";
  const std::string tunable_warning = first_order(CompileJson(tunable));
  EXPECT_NE(tunable_warning.find("the tunable lens \"tunable\""), std::string::npos) << tunable_warning;
  EXPECT_NE(tunable_warning.find("it is f/0.90 (72.02 mm over a 80.00 mm clear aperture)"), std::string::npos)
      << tunable_warning;
  EXPECT_NE(tunable_warning.find("no exact model of a tunable lens"), std::string::npos) << tunable_warning;

  // A curved mirror as the magnifier (f = 3 mm): a 165 deg field, by first order.
  nlohmann::json mirror = ReadExample("multiplicative_2layer.json");
  ElementNamed(mirror, "lens") = {
      {"type", "mirror"}, {"name", "lens"}, {"focal_length", "3 mm"}, {"fold", "horizontal"}, {"next", "front"}};
  const DisplaySystem curved = CompileJson(mirror);
  const std::string mirror_warning = first_order(curved);
  const double mirror_fx = curved.layers.front().fov_x_rad / kRadiansPerDegree;
  ASSERT_GT(mirror_fx, kFirstOrderFieldDeg);
  EXPECT_NE(mirror_warning.find("the curved mirror \"lens\""), std::string::npos) << mirror_warning;
  EXPECT_NE(mirror_warning.find(FormatFixed(mirror_fx, 0) + " x "), std::string::npos) << mirror_warning;
  EXPECT_NE(mirror_warning.find("no exact model of a curved mirror"), std::string::npos) << mirror_warning;

  for (const char* example : {"paper_prototype.json", "multiplicative_2layer.json", "additive_2layer.json",
                              "relay_magnifier.json", "per_branch_magnifiers.json", "multifocal_tunable_4plane.json",
                              "tensor_display_rank2.json", "hybrid_pbs_hwp.json"})
    EXPECT_EQ(first_order(CompileJson(ReadExample(example))), "") << example;
}

}  // namespace
}  // namespace layerlab
