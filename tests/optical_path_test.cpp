// Any optical path against independent computations: successive Gaussian
// imaging (the image of the image, lens by lens), the two-lens effective focal
// length, and rays traced in 3D through the folded sequence (tilted fold
// mirrors reflect, lenses deflect in their own plane) onto the panel's pixels.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>

#include <Eigen/Dense>

#include "layerlab/framework/random.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using nlohmann::json;
using testing::Close;
using testing::CompileJson;
using testing::ElementNamed;
using testing::ReadExample;

std::string Mm(double meters) { return std::to_string(meters * 1e3) + " mm"; }

json Eye(const std::string& next, double relief = 0.01) {
  return {{"type", "eye"}, {"name", "eye"}, {"eye_relief", Mm(relief)}, {"views", {3, 3}}, {"next", next}};
}
json Panel(const std::string& name, const std::string& next, double pitch = 100e-6) {
  return {{"type", "lc_panel"}, {"name", name}, {"pixel_pitch", Mm(pitch)}, {"resolution", {64, 40}}, {"next", next}};
}
json Backlight(const std::string& name) { return {{"type", "backlight"}, {"name", name}, {"luminance", 100}}; }
json Scene(json elements) { return {{"format", "layerlab-scene/1"}, {"elements", std::move(elements)}}; }

const VirtualLayer& Layer(const DisplaySystem& s, const std::string& name) {
  for (const VirtualLayer& l : s.layers)
    if (l.name == name) return l;
  throw std::runtime_error("no layer " + name);
}

// ---- Successive Gaussian imaging ------------------------------------------------

struct GaussianImage {
  double position;  // from the pupil
  double magnification;
};

// From the panel toward the eye: each powered element images the previous image.
// Real-is-positive: object distance o > 0 on the incoming side, image distance v > 0
// on the outgoing side; 1/o + 1/v = 1/f, m = -v/o.
GaussianImage ImageLensByLens(const VirtualLayer& layer) {
  double object = layer.position_m, magnification = 1;
  for (auto s = layer.path.rbegin(); s != layer.path.rend(); ++s) {
    if (s->power_diopters == 0) continue;
    const double o = object - *s->position_m;
    const double v = 1.0 / (s->power_diopters - 1.0 / o);
    magnification *= -v / o;
    object = *s->position_m - v;
  }
  return {object, magnification};
}

TEST(OpticalPath, RelayMagnifierMatchesGaussianImaging) {
  DisplaySystem s = CompileJson(ReadExample("relay_magnifier.json"));
  for (const VirtualLayer& l : s.layers) {
    GaussianImage g = ImageLensByLens(l);
    EXPECT_TRUE(Close(l.diopters, 1.0 / g.position, 1e-9)) << l.name;
    EXPECT_TRUE(Close(l.magnification, g.magnification, 1e-9)) << l.name;
    EXPECT_TRUE(l.inverted) << "the 4f relay's real image turns " << l.name;
    EXPECT_TRUE(l.flip_x && l.flip_y);
    EXPECT_TRUE(Close(l.tan_pitch_x, std::abs(g.magnification) * 585e-6 / g.position, 1e-9));
  }
  // The relay alone: magnification -f2/f1 = -1 of the intermediate image.
  EXPECT_TRUE(Close(Layer(s, "rear").magnification / Layer(s, "rear").panel_distance_m, 0, 0, 1e9));
}

TEST(OpticalPath, TwoLensEffectiveFocalLength) {
  // Panel at the pair's front focal point: image at infinity, a pixel subtends p / EFL.
  const double f1 = 0.06, f2 = 0.04, d = 0.03, p = 100e-6;
  const double efl = f1 * f2 / (f1 + f2 - d), ffd = f2 * (f1 - d) / (f1 + f2 - d);
  json scene =
      Scene({Eye("l1"),
             {{"type", "thin_lens"}, {"name", "l1"}, {"focal_length", Mm(f1)}, {"next", "l2"}},
             {{"type", "thin_lens"}, {"name", "l2"}, {"focal_length", Mm(f2)}, {"gap", Mm(d)}, {"next", "panel"}},
             Panel("panel", "bl", p),
             Backlight("bl")});
  ElementNamed(scene, "panel")["gap"] = ffd;
  DisplaySystem s = CompileJson(scene);
  EXPECT_LT(std::abs(s.layers[0].diopters), 1e-12);
  EXPECT_TRUE(Close(s.layers[0].tan_pitch_x, p / efl, 1e-12));
  // A little nearer: a virtual image, diopters by Newton's equation x x' = -EFL^2 (x = -delta).
  const double delta = 2e-3;
  ElementNamed(scene, "panel")["gap"] = ffd - delta;
  s = CompileJson(scene);
  // Back focal point of the pair on the eye side, from l1: f1 (d - f2) / (d - f1 - f2) behind it (toward the eye).
  const double bfd = f1 * (f2 - d) / (f1 + f2 - d);
  const double image_from_rear_focus = efl * efl / delta;  // beyond the pair's eye-side focal point, away from the eye
  const double z = 0.01 - bfd + image_from_rear_focus;
  EXPECT_TRUE(Close(s.layers[0].diopters, 1.0 / z, 1e-9));
}

TEST(OpticalPath, EyeReliefBeyondTheFocalLengthStillFloatsThePanels) {
  // Once refused; with the eye 80 mm before a 75 mm lens the images are still in front of the eye.
  json scene = ReadExample("multiplicative_2layer.json");
  ElementNamed(scene, "eye")["eye_relief"] = "8 cm";
  DisplaySystem s = CompileJson(scene);
  for (const VirtualLayer& l : s.layers) {
    const double d = 1.0 / l.diopters - 0.08, f = 0.075;  // image behind the lens
    EXPECT_TRUE(Close(l.panel_distance_m, d * f / (d + f), 1e-12)) << l.name;
    EXPECT_TRUE(Close(l.magnification, 1 + d / f, 1e-12));
  }
}

TEST(OpticalPath, DirectViewPanelsAreWhereTheyAre) {
  DisplaySystem s = CompileJson(ReadExample("tensor_display_3layer.json"));
  ASSERT_EQ(s.layers.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const double z = 0.5 + 0.012 * (2 - k);  // farthest first
    EXPECT_TRUE(Close(s.layers[k].diopters, 1 / z, 1e-12));
    EXPECT_TRUE(Close(s.layers[k].magnification, 1, 1e-12));
    EXPECT_TRUE(Close(s.layers[k].tan_pitch_x, 400e-6 / z, 1e-12));
  }
  EXPECT_TRUE(s.lens.empty());
}

TEST(OpticalPath, PerBranchMagnifiersPlaceFourPlanes) {
  DisplaySystem s = CompileJson(ReadExample("per_branch_magnifiers.json"));
  const std::map<std::string, std::pair<double, double>> want = {// diopters, focal length
                                                                 {"front_a", {2.4, 0.06}},
                                                                 {"rear_a", {0.8, 0.06}},
                                                                 {"front_b", {1.6, 0.08}},
                                                                 {"rear_b", {0.0, 0.08}}};
  for (const auto& [name, d_f] : want) {
    const VirtualLayer& l = Layer(s, name);
    const auto [D, f] = d_f;
    EXPECT_TRUE(Close(l.diopters, D, 1e-12, 1e-12)) << name;
    // Gaussian: the lens 30 mm from the eye; a virtual image 1/D - 30 mm behind it.
    const double s_expected = D == 0 ? f : (1 / D - 0.03) * f / ((1 / D - 0.03) + f);
    EXPECT_TRUE(Close(l.panel_distance_m, s_expected, 1e-12)) << name;
  }
  EXPECT_TRUE(Layer(s, "rear_b").flip_x) << "the reflected branch is mirrored";
}

// ---- Random chains, traced in 3D through the folded geometry --------------------

struct Frame {
  Eigen::Vector3d origin, e1, e2, e3;  // on-axis point; right, up, along the path
};

struct Ray {
  Eigen::Vector3d p, d;
};

void ToPlane(Ray& ray, const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  ray.p += ((point - ray.p).dot(normal) / ray.d.dot(normal)) * ray.d;
}

void Deflect(Ray& ray, const Frame& f, double power) {
  ToPlane(ray, f.origin, f.e3);
  const Eigen::Vector3d h = ray.p - f.origin;
  const double su = ray.d.dot(f.e1) / ray.d.dot(f.e3) - power * h.dot(f.e1);
  const double sv = ray.d.dot(f.e2) / ray.d.dot(f.e3) - power * h.dot(f.e2);
  ray.d = f.e3 + su * f.e1 + sv * f.e2;
}

// A 90-degree fold by a mirror tilted 45 degrees: the ray reflects off the tilted
// plane; the axis frame turns by a proper rotation (so a panel mounted in it is
// seen mirrored).
void Fold(Ray& ray, Frame& f, bool horizontal) {
  const Eigen::Vector3d turn_to = horizontal ? f.e1 : f.e2;
  const Eigen::Vector3d n = (f.e3 - turn_to).normalized();
  ToPlane(ray, f.origin, n);
  ray.d -= 2 * ray.d.dot(n) * n;
  const Eigen::Matrix3d r = Eigen::Matrix3d::Identity() - 2 * n * n.transpose();
  const Eigen::Vector3d e1 = r * f.e1, e2 = r * f.e2, e3 = r * f.e3;
  if (horizontal)
    f = {f.origin, -e1, e2, e3};
  else
    f = {f.origin, e1, -e2, e3};
}

// What the test knows of each element it wrote, to trace it.
struct Built {
  std::string type;
  double power = 0;
  bool horizontal = true;
  bool reflect = false;       // a combiner's reflected port on this path
  std::optional<double> gap;  // as written
};

class RandomChains : public ::testing::Test {
 protected:
  SplitMix64 random_{20261201};
  double Uniform(double lo, double hi) { return lo + (hi - lo) * random_.uniform(); }
  bool Coin(double p = 0.5) { return random_.uniform() < p; }
};

// Traces rays through one panel's folded path and compares the landing pixel
// with the compiled layer's prediction from the ray's eye-space start.
double WorstPixelError(const VirtualLayer& layer, const std::vector<Built>& elements,
                       const std::vector<double>& positions, SplitMix64& random) {
  double worst = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const double x0 = (random.uniform() - 0.5) * 6e-3, y0 = (random.uniform() - 0.5) * 6e-3;
    const double tx = (random.uniform() - 0.5) * layer.cols * layer.tan_pitch_x;
    const double ty = (random.uniform() - 0.5) * layer.rows * layer.tan_pitch_y;
    const double u = tx - x0 * layer.diopters, v = ty - y0 * layer.diopters;
    Ray ray{{x0, y0, 0}, {u, v, 1}};
    Frame f{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double at = 0;
    for (size_t i = 0; i < elements.size(); ++i) {
      f.origin += (positions[i] - at) * f.e3;
      at = positions[i];
      const Built& e = elements[i];
      if (e.type == "mirror" || e.reflect) Fold(ray, f, e.horizontal);
      if (e.power != 0) Deflect(ray, f, e.power);
    }
    f.origin += (layer.position_m - at) * f.e3;
    ToPlane(ray, f.origin, f.e3);
    const Eigen::Vector3d h = ray.p - f.origin;
    double col = h.dot(f.e1) / layer.panel.pitch_x_m + 0.5 * layer.cols - 0.5;
    if (layer.panel.reversed) col = layer.cols - 1 - col;  // mounted back to front
    const double row = 0.5 * layer.rows - 0.5 - h.dot(f.e2) / layer.panel.pitch_y_m;
    // The compiled layer: tan-angle t from the pupil center; pixel in eye order, then flips.
    const double je = tx / layer.tan_pitch_x + 0.5 * layer.cols - 0.5;
    const double ie = 0.5 * layer.rows - 0.5 - ty / layer.tan_pitch_y;
    const double jp = layer.flip_x ? layer.cols - 1 - je : je, ip = layer.flip_y ? layer.rows - 1 - ie : ie;
    worst = std::max({worst, std::abs(col - jp), std::abs(row - ip)});
    if (std::getenv("LAYERLAB_TRACE_DEBUG") && (std::abs(col - jp) > 1e-6 || std::abs(row - ip) > 1e-6))
      std::printf("%s: traced (%g, %g) predicted (%g, %g) flips %d %d inverted %d\n", layer.name.c_str(), col, row, jp,
                  ip, layer.flip_x, layer.flip_y, layer.inverted);
  }
  return worst;
}

TEST_F(RandomChains, RaysTracedThroughTheFoldedPathLandOnThePredictedPixel) {
  int compiled = 0, refused = 0;
  double worst = 0;
  for (int chain = 0; compiled < 1000 && chain < 20000; ++chain) {
    json elements = json::array();
    std::vector<Built> built;
    const int count = static_cast<int>(Uniform(0, 5));
    elements.push_back(Eye(count > 0 ? "e0" : "front", Uniform(0.005, 0.03)));
    double placed_at = 0;           // the last placed element's position
    std::optional<double> lens_at;  // the nearest lens or curved mirror's
    for (int i = 0; i < count; ++i) {
      const std::string name = "e" + std::to_string(i), next = i + 1 < count ? "e" + std::to_string(i + 1) : "front";
      json e = {{"name", name}};
      Built b;
      const double kind = Uniform(0, 1);
      if (kind < 0.45) {
        b.type = "thin_lens";
        const double f = (Coin() ? 1 : -1) * Uniform(0.03, 0.3);
        b.power = 1 / f;
        e["focal_length"] = f;
      } else if (kind < 0.75) {
        b.type = "mirror";
        b.horizontal = Coin();
        e["fold"] = b.horizontal ? "horizontal" : "vertical";
        if (Coin(0.4)) {
          const double f = (Coin(0.7) ? 1 : -1) * Uniform(0.05, 0.3);
          b.power = 1 / f;
          e["focal_length"] = f;
        }
      } else {
        b.type = "half_mirror";
        b.horizontal = Coin();
        b.reflect = Coin();
        e["fold"] = b.horizontal ? "horizontal" : "vertical";
        e[b.reflect ? "reflected" : "transmitted"] = next;
        e[b.reflect ? "transmitted" : "reflected"] = "side" + std::to_string(i);
      }
      if (b.type != "half_mirror") e["next"] = next;
      e["type"] = b.type;
      // The first element, when it has power, may take the eye relief; the last, when flat, may float
      // (the panel behind it is then placed by "distance" or "virtual_depth").
      const bool eye_relief = i == 0 && b.power != 0 && Coin();
      const bool floats = i + 1 == count && b.power == 0 && Coin(0.4);
      if (eye_relief) {
        placed_at = std::stod(elements[0]["eye_relief"].get<std::string>()) * 1e-3;
      } else if (!floats) {
        b.gap = Uniform(0.005, 0.08);
        e["gap"] = *b.gap;
        placed_at += *b.gap;
      }
      if (b.power != 0) lens_at = placed_at;
      elements.push_back(e);
      built.push_back(b);
    }
    const bool last_floats = count > 0 && !built.back().gap && built.back().power == 0;
    auto place = [&](json& panel) {
      if (!last_floats)
        panel["gap"] = Uniform(0.005, 0.15);
      else if (lens_at && Coin())
        panel["distance"] = placed_at - *lens_at + Uniform(0.005, 0.15);
      else
        panel["virtual_depth"] = std::to_string(Uniform(0.2, 3.0)) + " D";
    };
    json front = Panel("front", Coin() ? "rear" : "bl");
    place(front);
    if (Coin(0.2)) front["reversed"] = true;
    elements.push_back(front);
    if (front["next"] == "rear") {
      json rear = Panel("rear", "bl");
      rear["gap"] = Uniform(0.002, 0.02);
      elements.push_back(rear);
    }
    elements.push_back(Backlight("bl"));
    for (int i = 0; i < count; ++i)
      if (built[i].type == "half_mirror") {
        json side = Panel("side" + std::to_string(i), "bl_side" + std::to_string(i));
        if (built[i].gap)
          side["gap"] = Uniform(0.005, 0.15);
        else
          place(side);
        elements.push_back(side);
        elements.push_back(Backlight("bl_side" + std::to_string(i)));
      }
    DisplaySystem s;
    try {
      s = CompileJson(Scene(elements));
    } catch (const Error& e) {
      // Only an image no eye can see may be refused; check it by Gaussian imaging of the scene as written.
      const std::string what = e.what();
      EXPECT_TRUE(
          what.find("behind the eye") != std::string::npos || what.find("real, inverted image") != std::string::npos ||
          what.find("into the pupil plane") != std::string::npos ||
          what.find("cannot be formed") != std::string::npos || what.find("would not lie behind") != std::string::npos)
          << what;
      ++refused;
      continue;
    }
    ++compiled;
    for (const VirtualLayer& l : s.layers) {
      // The path as placed: flat elements without a gap go anywhere between their neighbors.
      std::vector<Built> on_path;
      std::vector<double> positions;
      double last = 0;
      for (size_t i = 0; i < l.path.size(); ++i) {
        const PathStep& step = l.path[i];
        Built b;
        b.type = step.type;
        b.power = step.power_diopters;
        b.horizontal = step.flips_x;
        b.reflect = step.port == "reflected";
        if (step.kind == ElementKind::kPanel) b.type = "panel";
        double next_placed = l.position_m;
        for (size_t j = i + 1; j < l.path.size(); ++j)
          if (l.path[j].position_m) {
            next_placed = *l.path[j].position_m;
            break;
          }
        const double where = step.position_m ? *step.position_m : last + random_.uniform() * (next_placed - last);
        positions.push_back(where);
        last = where;
        on_path.push_back(b);
      }
      // Independent: the image by successive Gaussian imaging.
      GaussianImage g = ImageLensByLens(l);
      if (std::abs(g.position) < 1e3 && std::abs(l.diopters) > 1e-3) {
        EXPECT_TRUE(Close(l.diopters, 1 / g.position, 1e-7, 1e-9)) << "chain " << chain << " " << l.name;
        EXPECT_TRUE(Close(l.magnification, g.magnification, 1e-7)) << "chain " << chain << " " << l.name;
      }
      worst = std::max(worst, WorstPixelError(l, on_path, positions, random_));
    }
  }
  EXPECT_GE(compiled, 1000) << refused << " refused";
  EXPECT_LT(worst, 1e-6) << "pixels";
  std::printf("%d chains compiled, %d refused (images no eye can see); worst pixel error %.3g\n", compiled, refused,
              worst);
}

TEST(OpticalPath, EveryExampleLandsOnThePredictedPixel) {
  SplitMix64 random(7);
  for (const char* name :
       {"paper_prototype.json", "hybrid_pbs_hwp.json", "additive_2layer.json", "multiplicative_2layer.json",
        "tensor_display_3layer.json", "per_branch_magnifiers.json", "relay_magnifier.json"}) {
    DisplaySystem s = CompileJson(ReadExample(name));
    for (const VirtualLayer& l : s.layers) {
      std::vector<Built> on_path;
      std::vector<double> positions;
      double last = 0;
      for (const PathStep& step : l.path) {
        Built b;
        b.type = step.kind == ElementKind::kPanel ? "panel" : step.type;
        b.power = step.power_diopters;
        b.horizontal = step.flips_x;
        b.reflect = step.port == "reflected";
        positions.push_back(step.position_m ? *step.position_m : last + 1e-3);
        last = positions.back();
        on_path.push_back(b);
      }
      EXPECT_LT(WorstPixelError(l, on_path, positions, random), 1e-6) << name << " " << l.name;
    }
  }
}

// ---- Placement errors ----------------------------------------------------------

TEST(OpticalPath, PlacementErrorsNameTheKeyAndTheOptics) {
  auto error = [](json scene) { return testing::CompileError(scene); };
  json base = Scene({Eye("bs"),
                     {{"type", "half_mirror"}, {"name", "bs"}, {"transmitted", "front"}, {"reflected", "side"}},
                     Panel("front", "bl"),
                     Backlight("bl"),
                     Panel("side", "bl2"),
                     Backlight("bl2")});
  ElementNamed(base, "side")["virtual_depth"] = "1 D";

  json gap_after_unplaced = base;
  ElementNamed(gap_after_unplaced, "front")["gap"] = "5 cm";
  EXPECT_EQ(error(gap_after_unplaced),
            "scene.json: /elements/2/gap: \"gap\" is measured from \"bs\", which has no place of its own (a flat "
            "element without \"gap\"); give \"bs\" a \"gap\" as well");

  json distance_without_lens = base;
  ElementNamed(distance_without_lens, "front")["distance"] = "5 cm";
  EXPECT_EQ(
      error(distance_without_lens),
      "scene.json: /elements/2/distance: \"distance\" is measured from the nearest lens or curved mirror in front "
      "of the panel, and none lies between the eye and \"front\"; give \"gap\" (from \"bs\") or "
      "\"virtual_depth\" (from the eye)");

  // A 50 mm lens 20 mm from the eye with the panel 200 mm behind it: a real image 47 mm behind the lens,
  // 27 mm behind the eye.
  json converging =
      Scene({Eye("lens", 0.02),
             {{"type", "thin_lens"}, {"name", "lens"}, {"focal_length", "50 mm"}, {"next", "relay"}},
             {{"type", "thin_lens"}, {"name", "relay"}, {"focal_length", "-500 mm"}, {"gap", "1 mm"}, {"next", "p"}},
             Panel("p", "bl"),
             Backlight("bl")});
  ElementNamed(converging, "p")["gap"] = "200 mm";
  EXPECT_NE(error(converging).find("/elements/3/gap: panel \"p\" would be imaged"), std::string::npos)
      << error(converging);
  EXPECT_NE(error(converging).find("behind the eye"), std::string::npos);

  json second_lens_unplaced = converging;
  ElementNamed(second_lens_unplaced, "relay").erase("gap");
  EXPECT_EQ(error(second_lens_unplaced),
            "scene.json: /elements/2/gap: missing placement: \"relay\" is not the first lens or curved mirror on its "
            "path, so the eye's eye_relief does not place it; give \"gap\" (the path length from \"lens\")");

  json zero_gap = converging;
  ElementNamed(zero_gap, "relay")["gap"] = "0 mm";
  EXPECT_EQ(error(zero_gap),
            "scene.json: /elements/2/gap: the path length from the element before must be positive, "
            "got 0.000 mm");

  json pupil_image = Scene({Eye("lens", 0.05),
                            {{"type", "thin_lens"}, {"name", "lens"}, {"focal_length", "25 mm"}, {"next", "p"}},
                            Panel("p", "bl"),
                            Backlight("bl")});
  ElementNamed(pupil_image, "p")["gap"] = "50 mm";  // 2f - 2f: the panel is conjugate to the pupil
  EXPECT_EQ(error(pupil_image),
            "scene.json: /elements/2/gap: panel \"p\" is imaged into the pupil plane, where no eye "
            "can focus; move it or the optics in front of it");

  // Two lenses that image the pupil onto the panel: b = b' + t d is zero only to rounding (-1e-17 m in double,
  // an image at 1.4e17 D if taken at its word).
  json relayed_pupil =
      Scene({Eye("lens1", 0.02),
             {{"type", "thin_lens"}, {"name", "lens1"}, {"focal_length", "20 mm"}, {"next", "lens2"}},
             {{"type", "thin_lens"}, {"name", "lens2"}, {"focal_length", "30 mm"}, {"gap", "100 mm"}, {"next", "p"}},
             Panel("p", "bl"),
             Backlight("bl")});
  ElementNamed(relayed_pupil, "p")["gap"] = "30 mm";  // lens1 images the pupil 60 mm behind it, lens2 that 30 mm on
  EXPECT_EQ(error(relayed_pupil),
            "scene.json: /elements/3/gap: panel \"p\" is imaged into the pupil plane, where no eye "
            "can focus; move it or the optics in front of it");

  json unreachable = Scene({Eye("lens", 0.01),
                            {{"type", "thin_lens"}, {"name", "lens"}, {"focal_length", "75 mm"}, {"next", "m"}},
                            {{"type", "mirror"}, {"name", "m"}, {"gap", "30 mm"}, {"next", "p"}},
                            Panel("p", "bl"),
                            Backlight("bl")});
  ElementNamed(unreachable, "p")["virtual_depth"] = "20 D";
  // At the mirror: a = 1 - 30/75 = 0.6, b = 10 + 30 (1 - 10/75) = 36 mm; a panel there is seen at a/b = 16.667 D,
  // one far behind it at c/d = -(1/75 mm) / (1 - 10/75) = -15.385 D.
  EXPECT_EQ(error(unreachable),
            "scene.json: /elements/3/virtual_depth: a virtual image at 20.000 D (50.00 mm from the "
            "eye) cannot be formed behind \"m\" (40.00 mm from the pupil): panels behind it are "
            "imaged between -15.385 and 16.667 D");
}

TEST(OpticalPath, ScenesBeyondTheLimitsAreRefusedUpFront) {
  // A chain of 20,000 half mirrors (each reflected port a panel): every layer keeps its path, so the compile's
  // memory grew with the square of the chain (std::bad_alloc before the limit); now refused at element 256.
  const int n = 20000;
  json chain = json::array({Eye("bs0")});
  for (int i = 0; i < n; ++i) {
    chain.push_back({{"type", "half_mirror"},
                     {"name", "bs" + std::to_string(i)},
                     {"transmitted", i + 1 < n ? "bs" + std::to_string(i + 1) : "last"},
                     {"reflected", "p" + std::to_string(i)}});
    json panel = Panel("p" + std::to_string(i), "bl" + std::to_string(i));
    panel["virtual_depth"] = "1 D";
    chain.push_back(panel);
    chain.push_back(Backlight("bl" + std::to_string(i)));
  }
  json last = Panel("last", "bl_last");
  last["virtual_depth"] = "1 D";
  chain.push_back(last);
  chain.push_back(Backlight("bl_last"));
  EXPECT_EQ(testing::CompileError(Scene(chain)),
            "scene.json: /elements/766: the path from the eye to \"bs255\" passes more than 256 elements; layerlab "
            "compiles paths of up to 256");

  // A stack of 40 panels: products of 40 transmittances.
  json stack = json::array({Eye("p0")});
  for (int i = 0; i < 40; ++i) {
    json panel = Panel("p" + std::to_string(i), i + 1 < 40 ? "p" + std::to_string(i + 1) : "bl");
    if (i == 0)
      panel["virtual_depth"] = "2 D";
    else
      panel["gap"] = "0.1 mm";
    stack.push_back(panel);
  }
  stack.push_back(Backlight("bl"));
  const std::string error = testing::CompileError(Scene(stack));
  EXPECT_NE(error.find("scene.json: /elements/33: a stack of more than 32 panels"), std::string::npos) << error;
  EXPECT_NE(error.find("underflows"), std::string::npos) << error;
}

TEST(OpticalPath, ApertureThatCutsTheFieldIsNamed) {
  json scene = ReadExample("multiplicative_2layer.json");
  ElementNamed(scene, "lens")["clear_aperture"] = "8 mm";
  DisplaySystem s = CompileJson(scene);
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_NE(s.warnings.back().find("the clear aperture of \"lens\" vignettes \"rear\""), std::string::npos)
      << s.warnings.back();
  EXPECT_NE(s.warnings.back().find("\"front\""), std::string::npos);
  // Rays from the eyebox corner to the far layer's corner: |x0 + e (t - x0 D)| per axis, then the radius.
  const VirtualLayer& rear = Layer(s, "rear");
  const double e = 0.01, tx = 200 * rear.tan_pitch_x, ty = 100 * rear.tan_pitch_y;
  const double hx = 3e-3 + e * (tx - 3e-3 * rear.diopters), hy = 3e-3 + e * (ty - 3e-3 * rear.diopters);
  EXPECT_NE(s.warnings.back().find("\"rear\" (rays up to " + FormatFixed(std::hypot(hx, hy) * 1e3, 2) + " mm"),
            std::string::npos)
      << s.warnings.back();
}

}  // namespace
}  // namespace layerlab
