// Bad scenes: each is refused with one message naming the file, the JSON
// pointer of the bad value and what was expected. Messages are asserted verbatim.
#include <functional>

#include "layerlab/framework/json_file.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using nlohmann::json;
using testing::ElementNamed;
using testing::ReadExample;

struct BadScene {
  std::string name;
  std::string base;  // example file
  std::function<void(json&)> mutate;
  std::string message;
};

void PrintTo(const BadScene& c, std::ostream* os) { *os << c.name; }

class BadSceneTest : public ::testing::TestWithParam<BadScene> {};

TEST_P(BadSceneTest, IsRefusedWithItsLocation) {
  const BadScene& c = GetParam();
  json scene = ReadExample(c.base);
  c.mutate(scene);
  EXPECT_EQ(testing::CompileError(scene), c.message);
}

const std::string kMul = "multiplicative_2layer.json";
const std::string kHybrid = "paper_prototype.json";

const BadScene kCases[] = {
    {"UnknownType", kMul, [](json& s) { ElementNamed(s, "lens")["type"] = "thin_lense"; },
     "scene.json: /elements/1/type: unknown element type \"thin_lense\"; did you mean \"thin_lens\"? Known types: "
     "backlight, eye, half_mirror, hwp, lc_panel, lens, lens_array, linear_polarizer, mirror, pbs, qwp, thin_lens, "
     "tunable_lens, "
     "world"},
    {"MisspelledKey", kMul,
     [](json& s) {
       json& lens = ElementNamed(s, "lens");
       lens["focal_lenght"] = lens["focal_length"];
       lens.erase("focal_length");
       lens["focal_length"] = "75 mm";
     },
     "scene.json: /elements/1/focal_lenght: unknown key \"focal_lenght\"; did you mean \"focal_length\"?"},
    // A required key misspelled (README.md's example): the typo is named, not the missing key.
    {"MisspelledRequiredKey", kMul,
     [](json& s) {
       json& lens = ElementNamed(s, "lens");
       lens["focal_lenght"] = lens["focal_length"];
       lens.erase("focal_length");
     },
     "scene.json: /elements/1/focal_lenght: unknown key \"focal_lenght\"; did you mean \"focal_length\"?"},
    {"MissingRequiredKey", kMul, [](json& s) { ElementNamed(s, "lens").erase("focal_length"); },
     "scene.json: /elements/1/focal_length: missing required key \"focal_length\""},
    {"WrongKindOfUnit", kMul, [](json& s) { ElementNamed(s, "lens")["focal_length"] = "75 deg"; },
     "scene.json: /elements/1/focal_length: 'deg' is an angle unit; expected a length in m, cm, mm, um, nm"},
    {"UnknownUnit", kMul, [](json& s) { ElementNamed(s, "front")["pixel_pitch"] = "117 uu"; },
     "scene.json: /elements/2/pixel_pitch: unknown unit 'uu' in \"117 uu\"; expected a length in m, cm, mm, um, nm"},
    {"BareNumberForADepth", kMul, [](json& s) { ElementNamed(s, "front")["virtual_depth"] = 2.2; },
     "scene.json: /elements/2/virtual_depth: expected a depth with its unit, such as \"0.4 D\" or \"2.5 m\", got a "
     "number"},
    {"NonFiniteQuantity", kMul, [](json& s) { ElementNamed(s, "lens")["focal_length"] = "nan mm"; },
     "scene.json: /elements/1/focal_length: \"nan mm\" is not a finite number"},
    {"TransmittanceAboveOne", kMul, [](json& s) { ElementNamed(s, "rear")["max_transmittance"] = 1.5; },
     "scene.json: /elements/3/max_transmittance: expected a fraction in [0, 1], got 1.5"},
    {"BlackLevelPerChannel", kMul,
     [](json& s) {
       ElementNamed(s, "rear")["black_level"] = {0.01, 0.02, 0.01};
     },
     "scene.json: /elements/3/black_level: one value for all channels, got [0.0100, 0.0200, 0.0100] (a per-channel "
     "black level is not modelled)"},
    {"ZeroPixelPitch", kMul, [](json& s) { ElementNamed(s, "rear")["pixel_pitch"] = "0 um"; },
     "scene.json: /elements/3/pixel_pitch: must be in (0, 0.01] (SI units), got 0"},
    {"ZeroFillFactor", kMul,
     [](json& s) {
       ElementNamed(s, "front")["fill_factor"] = {0.8, 0};
     },
     "scene.json: /elements/2/fill_factor: must be in (0, 1] (SI units), got 0"},
    {"FillFactorAboveOne", kMul, [](json& s) { ElementNamed(s, "front")["fill_factor"] = 1.2; },
     "scene.json: /elements/2/fill_factor: must be in (0, 1] (SI units), got 1.2"},
    {"NegativeCoherenceWidth", kMul, [](json& s) { ElementNamed(s, "backlight")["coherence_width"] = "-1 um"; },
     "scene.json: /elements/4/coherence_width: must be in [0, 1] (SI units), got -0.000001"},
    {"ZeroFocalLength", kMul, [](json& s) { ElementNamed(s, "lens")["focal_length"] = "0 mm"; },
     "scene.json: /elements/1/focal_length: a thin lens needs a nonzero focal length (0 would be infinite power)"},
    {"FractionalResolution", kMul,
     [](json& s) {
       ElementNamed(s, "rear")["resolution"] = {1280.5, 800};
     },
     "scene.json: /elements/3/resolution/0: expected an integer in [1, 32768], got 1280.5"},
    {"NegativeResolution", kMul,
     [](json& s) {
       ElementNamed(s, "rear")["resolution"] = {1280, -1};
     },
     "scene.json: /elements/3/resolution/1: expected an integer in [1, 32768], got -1"},
    {"StringViews", kMul,
     [](json& s) {
       ElementNamed(s, "eye")["views"] = {"13", 13};
     },
     "scene.json: /elements/0/views/0: expected an integer in [1, 256], got a string \"13\""},
    {"HugeViews", kMul,
     [](json& s) {
       ElementNamed(s, "eye")["views"] = {1e12, 13};
     },
     "scene.json: /elements/0/views/0: expected an integer in [1, 256], got 1000000000000.0"},
    {"InvertedAccommodationRange", kMul,
     [](json& s) {
       ElementNamed(s, "eye")["accommodation_range"] = {"2.6 D", "0 D"};
     },
     "scene.json: /elements/0/accommodation_range: the range is inverted or empty: 2.600 D is not below 0.000 D "
     "(give [far, near] in diopters, far first)"},
    {"DanglingConnection", kMul, [](json& s) { ElementNamed(s, "eye")["next"] = "lenz"; },
     "scene.json: /elements/0/next: dangling connection: no element is named \"lenz\"; did you mean \"lens\"?"},
    {"CyclicConnection", kMul, [](json& s) { ElementNamed(s, "rear")["next"] = "front"; },
     "scene.json: /elements/3/next: cyclic connection: \"front\" is already on the path from the eye to \"rear\";"
     " light that passes an element again gets there by a reflection back toward the eye, which layerlab follows "
     "itself: "
     "a half_mirror or pbs with \"fold\": \"back\" (at normal incidence) or the \"reflected_from_behind\" port of one "
     "folded sideways (docs/optics.md, \"Paths that pass an element more than once\")"},
    {"CycleBackToTheLens", kMul, [](json& s) { ElementNamed(s, "rear")["next"] = "lens"; },
     "scene.json: /elements/3/next: cyclic connection: \"lens\" is already on the path from the eye to \"rear\";"
     " light that passes an element again gets there by a reflection back toward the eye, which layerlab follows "
     "itself: "
     "a half_mirror or pbs with \"fold\": \"back\" (at normal incidence) or the \"reflected_from_behind\" port of one "
     "folded sideways (docs/optics.md, \"Paths that pass an element more than once\")"},
    // Without the lens the panels are viewed directly, which is a display of its own; the lens is then left over.
    {"LensLeftOffThePath", kMul, [](json& s) { ElementNamed(s, "eye")["next"] = "front"; },
     "scene.json: /elements/1: element \"lens\" (thin_lens) is not on the optical path from the eye"},
    {"BacklightRightAfterTheEye", kMul, [](json& s) { ElementNamed(s, "eye")["next"] = "backlight"; },
     "scene.json: /elements/0/next: \"backlight\" is backlight, a backlight; a lens, a mirror, a combiner, an in-line "
     "optic, a panel or the world was expected here"},
    {"CombinerAfterAPanel", kHybrid,
     [](json& s) {
       ElementNamed(s, "rear_a")["next"] = "mirror2";
       s["elements"].push_back({{"type", "half_mirror"},
                                {"name", "mirror2"},
                                {"transmitted", "backlight_a"},
                                {"reflected", "backlight_b"}});
       ElementNamed(s, "rear_b")["next"] = "front_b";
     },
     "scene.json: /elements/4/next: \"mirror2\" is half_mirror, a combiner; a panel or a backlight was expected here"},
    {"PanelBeyondTheFocalLength", kMul,
     [](json& s) {
       json& rear = ElementNamed(s, "rear");
       rear.erase("virtual_depth");
       rear["distance"] = "80 mm";
     },
     "scene.json: /elements/3/distance: panel \"rear\" would be imaged 1190.00 mm behind the eye (-0.840 D) (it is "
     "80.00 mm from the lens, beyond the focal length 75.00 mm): the optics in front of it form a real image beyond "
     "the pupil, whose light converges into the eye, which no eye can focus; a real image in front of the eye is "
     "accepted"},
    // Without optics a panel is seen where it is: 0 D is no place, and the message says why (it said
    // "the optics in front of it image every plane at 0 D" of a path with no optics).
    {"NoOpticsAndZeroDiopters", kMul,
     [](json& s) {
       ElementNamed(s, "eye")["next"] = "front";
       s["elements"].erase(1);  // the lens
       ElementNamed(s, "front")["virtual_depth"] = "0 D";
     },
     "scene.json: /elements/1/virtual_depth: 0.000 D puts \"front\" infinitely far: nothing with optical power "
     "lies between the eye and it, so it is seen where it is (a virtual_depth of D puts it 1/D from the eye); give a "
     "virtual_depth above 0 D, or a lens in front of it"},
    {"TwoPanelsOfAStackAtOneDepth", kMul, [](json& s) { ElementNamed(s, "rear")["virtual_depth"] = "2.2 D"; },
     "scene.json: /elements/3/virtual_depth: panels \"front\" and \"rear\" of one stack are at the same depth "
     "(2.2000 D); a stack needs distinct planes"},
    {"StackOutOfOrder", kMul,
     [](json& s) {
       ElementNamed(s, "front")["virtual_depth"] = "0.4 D";
       ElementNamed(s, "rear")["virtual_depth"] = "2.2 D";
     },
     "scene.json: /elements/3/virtual_depth: panel \"rear\" is behind \"front\" in the stack but nearer the lens "
     "(64.17 mm < 72.81 mm); list each stack from the eye outward"},
    {"BothPlacements", kMul, [](json& s) { ElementNamed(s, "rear")["distance"] = "70 mm"; },
     "scene.json: /elements/3/virtual_depth: give either \"distance\" (from the lens) or \"virtual_depth\" (from the "
     "eye), not both"},
    {"NoPlacement", kMul, [](json& s) { ElementNamed(s, "rear").erase("virtual_depth"); },
     "scene.json: /elements/3/distance: missing placement: give \"distance\" (from the lens, e.g. \"72.81 mm\") or "
     "\"virtual_depth\" (from the eye, e.g. \"0.4 D\")"},
    {"ImageInFrontOfTheLens", kMul, [](json& s) { ElementNamed(s, "front")["virtual_depth"] = "150 D"; },
     "scene.json: /elements/2/virtual_depth: a virtual image at 150.000 D (6.67 mm from the eye) cannot be formed "
     "behind the lens: it is 10.00 mm from the eye, and a panel behind it is imaged between 0 D (at its focal plane, "
     "75.00 mm behind it) and 100.0 D (against it)"},
    {"NoEye", kMul, [](json& s) { s["elements"].erase(0); },
     "scene.json: /elements: the scene has no eye; the optical path starts at an element of type \"eye\""},
    {"TwoEyes", kMul,
     [](json& s) {
       json eye = s["elements"][0];
       eye["name"] = "eye2";
       s["elements"].push_back(eye);
     },
     "scene.json: /elements/5: a second eye \"eye2\"; the scene already has \"eye\" (one eye per scene)"},
    {"ElementOffThePath", kMul,
     [](json& s) {
       s["elements"].push_back({{"type", "backlight"}, {"name", "spare"}, {"luminance", "100 cd/m2"}});
     },
     "scene.json: /elements/5: element \"spare\" (backlight) is not on the optical path from the eye"},
    {"SharedElement", kHybrid, [](json& s) { ElementNamed(s, "rear_b")["next"] = "backlight_a"; },
     "scene.json: /elements/7/next: \"backlight_a\" is already reached by another connection; each element sits on "
     "one optical path"},
    {"ElementNameBeyondTheFileNameLimit", kMul,
     [](json& s) {
       ElementNamed(s, "backlight")["name"] = std::string(232, 'b');
       ElementNamed(s, "rear")["next"] = std::string(232, 'b');
     },
     "scene.json: /elements/4/name: element name of 232 bytes; output files are named after elements, and the file "
     "system allows names of 255 bytes: at most 231"},
    {"DuplicateElementName", kMul, [](json& s) { ElementNamed(s, "backlight")["name"] = "rear"; },
     "scene.json: /elements/4/name: element name \"rear\" is already used by /elements/3"},
    {"MirrorPassesMoreThanItGets", kHybrid, [](json& s) { ElementNamed(s, "half_mirror")["transmittance"] = 0.6; },
     "scene.json: /elements/2/transmittance: reflectance + transmittance is 1.1000 in channel R; a passive mirror "
     "cannot exceed 1"},
    {"UnknownFormat", kMul, [](json& s) { s["format"] = "layerlab-scene/2"; },
     "scene.json: /format: unknown scene format \"layerlab-scene/2\"; this layerlab reads \"layerlab-scene/1\""},
    {"UnknownTopLevelKey", kMul, [](json& s) { s["element"] = json::array(); },
     "scene.json: /element: unknown key \"element\"; did you mean \"elements\"?"},
    {"ElementsNotAnArray", kMul, [](json& s) { s["elements"] = json::object(); },
     "scene.json: /elements: expected an array of elements, got an object"},
    {"BadPupilShape", kMul, [](json& s) { ElementNamed(s, "eye")["pupil_shape"] = "roun"; },
     "scene.json: /elements/0/pupil_shape: \"roun\" is not one of square or round; did you mean \"round\"?"},
    {"UnknownChromaticModel", kMul, [](json& s) { ElementNamed(s, "eye")["chromatic_aberration"] = "thibo"; },
     "scene.json: /elements/0/chromatic_aberration: \"thibo\" is not one of none or thibos; did you mean \"thibos\"?"},
    {"NegativePupil", kMul, [](json& s) { ElementNamed(s, "eye")["pupil_diameter"] = "-4 mm"; },
     "scene.json: /elements/0/pupil_diameter: must be in [0, 0.02] (SI units), got -0.004"},
    {"PupilWordNotAuto", kMul, [](json& s) { ElementNamed(s, "eye")["pupil_diameter"] = "automatic"; },
     "scene.json: /elements/0/pupil_diameter: expected a length (\"4 mm\") or \"auto\", got \"automatic\""},
    {"PupilLuminanceWithoutAuto", kMul, [](json& s) { ElementNamed(s, "eye")["pupil_luminance"] = "100 cd/m2"; },
     "scene.json: /elements/0/pupil_luminance: only with \"pupil_diameter\": \"auto\""},
    {"PupilAgeOutsideTheFormula", kMul,
     [](json& s) {
       ElementNamed(s, "eye")["pupil_diameter"] = "auto";
       ElementNamed(s, "eye")["pupil_age"] = 12;
     },
     "scene.json: /elements/0/pupil_age: must be in [20, 83] (SI units), got 12"},
    {"ZernikeIndexOutOfRange", kMul,
     [](json& s) {
       ElementNamed(s, "eye")["zernike"] = {{"40", "0.1 um"}};
       ElementNamed(s, "eye")["zernike_pupil"] = "6 mm";
     },
     "scene.json: /elements/0/zernike/40: not an OSA/ANSI Zernike index: give j from 0 to 27"},
    {"ZernikeIndexNotANumber", kMul,
     [](json& s) {
       ElementNamed(s, "eye")["zernike"] = {{"Z4", "0.1 um"}};
       ElementNamed(s, "eye")["zernike_pupil"] = "6 mm";
     },
     "scene.json: /elements/0/zernike/Z4: not an OSA/ANSI Zernike index: give j from 0 to 27"},
    {"ZernikeBareNumberIsMeters", kMul,
     [](json& s) {
       ElementNamed(s, "eye")["zernike"] = {{"4", 0.1}};
       ElementNamed(s, "eye")["zernike_pupil"] = "6 mm";
     },
     "scene.json: /elements/0/zernike/4: a coefficient must lie within 50 um of 0, got 100000.000 um (a bare number is "
     "meters: give \"0.1 um\")"},
    {"ZernikeWithoutPupil", kMul,
     [](json& s) {
       ElementNamed(s, "eye")["zernike"] = {{"4", "0.1 um"}};
     },
     "scene.json: /elements/0/zernike: coefficients need zernike_pupil, the pupil diameter they were measured at"},
    {"UnknownPopulation", kMul, [](json& s) { ElementNamed(s, "eye")["zernike"] = "thibos_2002"; },
     "scene.json: /elements/0/zernike: unknown population \"thibos_2002\"; known: salmon_van_de_pol_2006 (or give "
     "{\"j\": coefficient} with zernike_pupil)"},
    {"ChannelWavelengthOutsideTheVisible", kMul,
     [](json& s) {
       ElementNamed(s, "eye")["channel_wavelengths"] = {"612 nm", "549 nm", "46.5 nm"};
     },
     "scene.json: /elements/0/channel_wavelengths/2: a wavelength must lie in 380 to 780 nm, got 46.5 nm"},
    {"DiffractionNotABoolean", kMul, [](json& s) { ElementNamed(s, "eye")["diffraction"] = "airy"; },
     "scene.json: /elements/0/diffraction: expected false, true (the same as \"mtf\") or \"wave\", got \"airy\""},
    {"DiffractionThroughAPinhole", kMul,
     [](json& s) {
       ElementNamed(s, "eye")["pupil_diameter"] = "0 mm";
       ElementNamed(s, "eye")["diffraction"] = true;
     },
     "scene.json: /elements/0/diffraction: a pinhole pupil (pupil_diameter 0) has no diffraction-limited image"},
    {"StilesCrawfordWithoutWaveOptics", kMul, [](json& s) { ElementNamed(s, "eye")["stiles_crawford"] = true; },
     "scene.json: /elements/0/stiles_crawford: the Stiles-Crawford apodization is part of the pupil function: set "
     "diffraction \"wave\""},
    {"StilesCrawfordNegative", kMul,
     [](json& s) {
       ElementNamed(s, "eye")["diffraction"] = "wave";
       ElementNamed(s, "eye")["stiles_crawford"] = -0.05;
     },
     "scene.json: /elements/0/stiles_crawford: expected true, false or rho per mm^2 in [0, 1], got -0.05"},
    {"SpectralTableMissesAChannel", "hybrid_pbs_hwp.json",
     [](json& s) {
       ElementNamed(s, "pbs")["transmittance_p"] = {{"wavelengths", {"500 nm", "700 nm"}}, {"values", {0.9, 0.9}}};
     },
     "scene.json: /elements/2/transmittance_p/wavelengths: the table covers 500 to 700 nm but channel B is at 465 nm"},
};

INSTANTIATE_TEST_SUITE_P(Scenes, BadSceneTest, ::testing::ValuesIn(kCases),
                         [](const auto& test_info) { return test_info.param.name; });

TEST(BadSceneText, MalformedJsonGivesLineAndColumn) {
  try {
    ParseJson("{\n  \"elements\": [\n    {\"type\": \"eye\",}\n  ]\n}", "scene.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "scene.json:3:20: malformed JSON: syntax error while parsing object key - unexpected '}'; "
                 "expected string literal");
  }
}

TEST(BadSceneText, DuplicateKeyInAnElement) {
  try {
    ParseJson(R"({"elements": [{"type": "eye", "name": "a", "name": "b"}]})", "scene.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "scene.json: /elements/0/name: duplicate key \"name\" (each key may appear once per object)");
  }
}

}  // namespace
}  // namespace layerlab
