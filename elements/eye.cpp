// eye: the viewer, where every optical path starts.
//
// | key                 | type               | default          | meaning                                  |
// |---------------------|--------------------|------------------|------------------------------------------|
// | pupil_diameter      | length             | 4 mm             | side of a square / diameter of a round pupil; 0 = pinhole |
// | pupil_shape         | square, round      | square           | the paper uses a square pupil            |
// | pupil_samples       | [x, y] integers    | [9, 9]           | pupil points for retinal images          |
// | pupil_sampling      | grid, jittered, poisson | grid        | how those points are placed              |
// | pupil_seed          | integer            | 1                | for jittered and poisson sampling        |
// | eye_relief          | length             | 1 cm             | pupil plane to main lens                 |
// | accommodation_range | [depth, depth]     | ["0 D", "2.6 D"] | far and near point: a layer outside gets a warning; swept by focal stacks and contrast curves |
// | chromatic_defocus   | [r, g, b] optical powers | [0, 0, 0]  | defocus added per channel (longitudinal chromatic aberration) |
// | eyebox              | [length, length]   | [6 mm, 6 mm]     | width, height the views cover            |
// | views               | [x, y] integers    | [13, 13]         | views of target light fields             |
// | next                | element name       | required         | the main lens                            |
#include <algorithm>

#include "elements/element.h"
#include "elements/registry.h"

namespace layerlab {
namespace {

std::unique_ptr<Element> MakeEye(Params& p) {
  EyeModel m;
  m.pupil_diameter = p.quantity("pupil_diameter", Dimension::kLength, m.pupil_diameter);
  p.require_range("pupil_diameter", m.pupil_diameter, 0.0, 0.02, false, false);
  m.pupil_shape =
      p.choice("pupil_shape", {"square", "round"}, "square") == "square" ? PupilShape::kSquare : PupilShape::kRound;
  if (p.has("pupil_samples")) {
    auto n = p.integer_pair("pupil_samples", 1, 1024);
    m.pupil_samples_x = static_cast<int>(n[0]);
    m.pupil_samples_y = static_cast<int>(n[1]);
  }
  std::string sampling = p.choice("pupil_sampling", {"grid", "jittered", "poisson"}, "grid");
  m.pupil_sampling = sampling == "grid"       ? PupilSampling::kGrid
                     : sampling == "jittered" ? PupilSampling::kJittered
                                              : PupilSampling::kPoisson;
  m.pupil_seed = static_cast<uint64_t>(p.integer("pupil_seed", 0, INT64_MAX, 1));
  m.eye_relief = p.quantity("eye_relief", Dimension::kLength, m.eye_relief);
  p.require_range("eye_relief", m.eye_relief, 0.0, 1.0, true, false);

  p.mark_read("accommodation_range");
  if (p.has("accommodation_range")) {
    const nlohmann::json& range = p.raw("accommodation_range");
    if (!range.is_array() || range.size() != 2)
      p.fail("accommodation_range", "expected two depths [\"0 D\", \"2.6 D\"], got " + range.dump());
    Params ends(nlohmann::json{{"0", range[0]}, {"1", range[1]}}, p.where("accommodation_range"));
    m.accommodation_min = ends.optional_depth("0")->diopters;
    m.accommodation_max = ends.optional_depth("1")->diopters;
    if (!(m.accommodation_min < m.accommodation_max))
      p.fail("accommodation_range", "the range is inverted or empty: " + FormatFixed(m.accommodation_min, 3) +
                                        " D is not below " + FormatFixed(m.accommodation_max, 3) +
                                        " D (give [far, near] in diopters, far first)");
  }
  p.mark_read("chromatic_defocus");
  if (p.has("chromatic_defocus")) {
    const nlohmann::json& v = p.raw("chromatic_defocus");
    if (!v.is_array() || v.size() != 3) p.fail("chromatic_defocus", "expected three powers [R, G, B] in D");
    Params rgb(nlohmann::json{{"0", v[0]}, {"1", v[1]}, {"2", v[2]}}, p.where("chromatic_defocus"));
    for (int c = 0; c < 3; ++c) {
      m.chromatic_defocus[c] = rgb.quantity(std::to_string(c), Dimension::kOpticalPower);
      rgb.require_range(std::to_string(c), m.chromatic_defocus[c], -5.0, 5.0, false, false);
    }
  }
  auto eyebox = p.quantity_pair("eyebox", Dimension::kLength, {m.eyebox_width, m.eyebox_height});
  m.eyebox_width = eyebox[0];
  m.eyebox_height = eyebox[1];
  p.require_range("eyebox", std::min(eyebox[0], eyebox[1]), 0.0, 0.1, true, false);
  p.require_range("eyebox", std::max(eyebox[0], eyebox[1]), 0.0, 0.1, true, false);
  if (p.has("views")) {
    auto n = p.integer_pair("views", 1, 256);
    m.views_x = static_cast<int>(n[0]);
    m.views_y = static_cast<int>(n[1]);
  }
  return std::make_unique<EyeElement>(m);
}

}  // namespace

ElementType EyeType() { return {"eye", ElementKind::kEye, "the viewer: pupil, eye relief, views", MakeEye}; }

}  // namespace layerlab
