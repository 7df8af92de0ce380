// analysis/layout_svg.h: the report's layout diagram. Issue 50 saw its
// connector lines (panel to image in eye space) cross labels and a section
// title; here each shipped example's diagram is read back and every connector
// and leader line is checked against every text's box, and the eye-space
// labels against each other.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "layerlab/analysis/layout_svg.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/scene.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

struct Box {
  double x0, y0, x1, y1;
  std::string text;
};

struct Segment {
  double x0, y0, x1, y1;
};

double Attribute(const std::string& element, const std::string& name) {
  std::smatch m;
  if (!std::regex_search(element, m, std::regex("\\b" + name + "=\"([-0-9.]+)\""))) return NAN;
  return std::stod(m[1]);
}

// Each <text>'s box, wide enough for Liberation Sans at its size (0.6 em a character; the font's
// widest lowercase average is about 0.55), from its ascent (0.75 em above the baseline) to its
// descent (0.25 em below).
std::vector<Box> TextBoxes(const std::string& svg) {
  std::vector<Box> boxes;
  const std::regex text("<text ([^>]*)>([^<]*)</text>");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), text); it != std::sregex_iterator(); ++it) {
    const std::string attributes = (*it)[1], content = (*it)[2];
    const double size = std::isnan(Attribute(attributes, "font-size")) ? 16 : Attribute(attributes, "font-size");
    const double x = Attribute(attributes, "x"), y = Attribute(attributes, "y");
    const double width = 0.6 * size * static_cast<double>(content.size());
    double left = x;
    if (attributes.find("text-anchor=\"middle\"") != std::string::npos) left = x - width / 2;
    if (attributes.find("text-anchor=\"end\"") != std::string::npos) left = x - width;
    boxes.push_back({left, y - 0.75 * size, left + width, y + 0.25 * size, content});
  }
  return boxes;
}

// The <line>s of a class: "connector" (panel to image), "leader" (image to its label).
std::vector<Segment> Lines(const std::string& svg, const std::string& kind) {
  std::vector<Segment> lines;
  const std::regex line("<line ([^>]*class=\"" + kind + "\"[^>]*)/>");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), line); it != std::sregex_iterator(); ++it) {
    const std::string a = (*it)[1];
    lines.push_back({Attribute(a, "x1"), Attribute(a, "y1"), Attribute(a, "x2"), Attribute(a, "y2")});
  }
  return lines;
}

// Whether the segment passes through the box (Liang-Barsky clipping).
bool Crosses(const Segment& s, const Box& b) {
  double t0 = 0, t1 = 1;
  const double dx = s.x1 - s.x0, dy = s.y1 - s.y0;
  const double p[4] = {-dx, dx, -dy, dy}, q[4] = {s.x0 - b.x0, b.x1 - s.x0, s.y0 - b.y0, b.y1 - s.y0};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return false;
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0)
      t0 = std::max(t0, t);
    else
      t1 = std::min(t1, t);
    if (t0 > t1) return false;
  }
  return true;
}

bool Overlap(const Box& a, const Box& b) { return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1; }

// Every connector and leader clear of every text; the images' labels ("rear_a 0.40 D") clear of each other.
void ExpectNothingCrosses(const DisplaySystem& system) {
  const std::string svg = RenderLayoutSvg(system);
  const std::vector<Segment> connectors = Lines(svg, "connector"), leaders = Lines(svg, "leader");
  ASSERT_EQ(connectors.size(), system.layers.size()) << "one connector per panel";
  ASSERT_EQ(leaders.size(), system.layers.size()) << "one leader per image";
  const std::vector<Box> boxes = TextBoxes(svg);
  ASSERT_GT(boxes.size(), system.layers.size());
  for (const std::vector<Segment>* kind : {&connectors, &leaders})
    for (const Segment& s : *kind)
      for (const Box& b : boxes)
        EXPECT_FALSE(Crosses(s, b)) << (kind == &connectors ? "the connector" : "the leader") << " from (" << s.x0
                                    << ", " << s.y0 << ") to (" << s.x1 << ", " << s.y1 << ") crosses \"" << b.text
                                    << "\"";
  std::vector<Box> image_labels;
  for (const Box& b : boxes)
    if (std::regex_search(b.text, std::regex(" [0-9.]+ D( \\(inverted\\))?$"))) image_labels.push_back(b);
  ASSERT_EQ(image_labels.size(), system.layers.size());
  for (size_t i = 0; i < image_labels.size(); ++i)
    for (size_t j = i + 1; j < image_labels.size(); ++j)
      EXPECT_FALSE(Overlap(image_labels[i], image_labels[j]))
          << "\"" << image_labels[i].text << "\" and \"" << image_labels[j].text << "\" overlap";
}

class LayoutSvg : public ::testing::TestWithParam<std::string> {};

TEST_P(LayoutSvg, ConnectorsAndLeadersCrossNoTextAndImageLabelsDoNotOverlap) {
  ExpectNothingCrosses(Compile(LoadScene(testing::ExamplePath(GetParam()))));
}

// Three images 0.15 D apart (about 51 px): the right one's label on the lowest level, the middle one's a
// level up (it would cover the right one's), and the left one's label, which clears the right one's, must
// still pass below the middle one's leader: two levels up.
TEST(LayoutSvgLabels, ALabelPassesBelowTheLeadersInItsSpan) {
  nlohmann::json scene = testing::ReadExample("tensor_display_3layer.json");
  testing::ElementNamed(scene, "front")["virtual_depth"] = "1.0 m";
  testing::ElementNamed(scene, "middle")["gap"] = "17.647 cm";
  testing::ElementNamed(scene, "rear")["gap"] = "25.21 cm";
  const DisplaySystem system = testing::CompileJson(scene);
  std::vector<double> diopters;
  for (const VirtualLayer& l : system.layers) diopters.push_back(l.diopters);
  std::sort(diopters.begin(), diopters.end());
  ASSERT_EQ(diopters.size(), 3u);
  EXPECT_NEAR(diopters[0], 0.70, 0.001);
  EXPECT_NEAR(diopters[1], 0.85, 0.001);
  EXPECT_NEAR(diopters[2], 1.00, 0.001);
  ExpectNothingCrosses(system);
}

INSTANTIATE_TEST_SUITE_P(Examples, LayoutSvg,
                         ::testing::Values("paper_prototype.json", "multiplicative_2layer.json",
                                           "tensor_display_3layer.json", "multifocal_tunable_4plane.json",
                                           "relay_magnifier.json", "per_branch_magnifiers.json", "hybrid_pbs_hwp.json"),
                         [](const ::testing::TestParamInfo<std::string>& example) {
                           return example.param.substr(0, example.param.find('.'));
                         });

}  // namespace
}  // namespace layerlab
