#include "layerlab/analysis/contrast_option_table.h"

#include "layerlab/elements/eye_pose.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

using Kind = OptionKind;

void AddSceneKeys(std::vector<ContrastOptionEntry>& t) {
  ContrastOptionEntry e;
  auto add = [&] {
    t.push_back(e);
    e = ContrastOptionEntry{};
  };
  e.key = "depths", e.kind = Kind::kReal, e.type = "array of depths", e.dimension = Dimension::kOpticalPower;
  e.has_range = true, e.range = {0, 20, true, false}, e.constraint_note = " D";
  e.default_text = "0.7, 1.3, 1.9 D", e.meaning = "grating planes";
  e.cli_flag = "--depths", e.cli_help = "Target depths, comma-separated: D, or with units: \"0.7 D,1.3 D\", \"2 m\"";
  e.python = "depths", e.list = &ContrastOptions::target_diopters;
  add();
  e.key = "frequencies", e.kind = Kind::kReal, e.type = "array of angular frequencies";
  e.dimension = Dimension::kAngularFrequency, e.has_range = true, e.range = {0, 1000, true, false};
  e.constraint_note = " cpd", e.default_text = "2, 4 cpd", e.meaning = "grating frequencies";
  e.cli_flag = "--frequencies", e.cli_help = "Frequencies, comma-separated: cpd";
  e.python = "frequencies", e.list = &ContrastOptions::frequencies_cpd;
  add();
  e.key = "accommodation", e.kind = Kind::kConfig, e.type = "{from, to, step}: depth_range";
  e.default_text = "0 D to 2.6 D by 0.05 D", e.meaning = "the sweep (at least 3 states in a scene)";
  e.cli_flag = "--accommodation",
  e.cli_help = "FROM:TO:STEP, or three or more evenly spaced states: D, or with units: \"0 D:2.6 D:0.05 D\"";
  e.python = "accommodation";
  add();
  e.key = "retina_resolution", e.kind = Kind::kReal, e.type = "angle", e.dimension = Dimension::kAngle;
  e.unit = "deg", e.has_range = true, e.range = {0, 1, true, false}, e.constraint_note = " deg";
  e.default_text = "0.01 deg", e.meaning = "retinal sample size";
  e.cli_flag = "--resolution", e.cli_help = "Retinal sample size: degrees or \"0.6 arcmin\"";
  e.python = "retina_resolution_deg", e.real = &ContrastOptions::retina_resolution_deg;
  add();
  e.key = "retina_field", e.kind = Kind::kReal, e.type = "angle", e.dimension = Dimension::kAngle, e.unit = "deg";
  e.has_range = true, e.range = {0, 170, true, true}, e.constraint_note = " deg";
  e.default_text = "20 deg", e.meaning = "horizontal, centered on field_center";
  e.cli_flag = "--field", e.cli_help = "Retinal field width: degrees";
  e.python = "retina_field_deg", e.real = &ContrastOptions::retina_field_deg;
  add();
  e.key = "field_center", e.kind = Kind::kReal, e.type = "angle", e.dimension = Dimension::kAngle, e.unit = "deg";
  e.has_range = true, e.range = {-80, 80, false, false}, e.constraint_note = " deg";
  e.default_text = "0 deg";
  e.meaning =
      "where the eye looks: the horizontal angle of the retinal window's centre (positive to the right); the window, "
      "its Fourier analysis and natural viewing's reference move there, and off the axis the window must lie inside "
      "each display's field (the target strip's)";
  e.cli_flag = "--field-center", e.cli_help = "Horizontal angle of the retinal window's centre: degrees";
  e.python = "field_center_deg", e.real = &ContrastOptions::field_center_deg;
  add();
  e.key = "strip_rows", e.kind = Kind::kInteger, e.type = "integer", e.has_range = true;
  e.range = {1, 100000, false, false}, e.default_text = "24";
  e.meaning = "light-field rows around the axis (the grating is vertical)";
  e.cli_flag = "--strip-rows", e.cli_help = "Light-field rows around the axis";
  e.python = "strip_rows", e.integer = &ContrastOptions::strip_rows;
  add();
  e.key = "factorized_for", e.kind = Kind::kConfig, e.type = "path", e.default_text = "none";
  e.meaning =
      "a scene whose display the patterns are also solved on, for the same grating; each display then has a second "
      "curve, \"DISPLAY (factorized for SCENE)\", of those patterns seen through it (the layers must match in "
      "count and resolution)";
  e.cli_flag = "--factorized-for",
  e.cli_help = "Scene file: each display also shows the patterns solved on its display";
  e.python = "factorized_for";
  add();
  e.key = "scenes", e.kind = Kind::kConfig, e.type = "array of paths", e.default_text = "none";
  e.meaning = "more displays in the same sweep (on the command line and in Python: the scenes given)";
  add();
}

// Scene keys too: the curves across the eyebox.
void AddEyeboxKeys(std::vector<ContrastOptionEntry>& t) {
  ContrastOptionEntry e;
  auto add = [&] {
    t.push_back(e);
    e = ContrastOptionEntry{};
  };
  e.key = "eyebox_range", e.kind = Kind::kReal, e.type = "length", e.dimension = Dimension::kLength;
  e.has_range = true, e.range = {0, kMaxContrastEyeboxRange, false, false}, e.constraint_note = " m (0 = none)";
  e.default_text = "0 m";
  e.meaning =
      "each display's curves also seen from a square grid of pupil positions within this of the eye's, in x and y "
      "(the same factorizations; 0: the eye's pupil alone): the accommodation response across the eyebox "
      "(docs/eye-pose.md)";
  e.cli_flag = "--eyebox-range";
  e.cli_help = "Also sweep from the pupil positions within this of the eye's: m, or with units (\"2 mm\")";
  e.python = "eyebox_range", e.real = &ContrastOptions::eyebox_range_m;
  add();
  e.key = "eyebox_step", e.kind = Kind::kReal, e.type = "length", e.dimension = Dimension::kLength;
  e.has_range = true, e.range = {0, kMaxContrastEyeboxRange, false, false}, e.constraint_note = " m (0 = the range)";
  e.default_text = "0 m", e.meaning = "the eyebox grid's spacing (0: eyebox_range, 3 x 3 positions)";
  e.cli_flag = "--eyebox-step", e.cli_help = "The eyebox grid's spacing: m, or with units (default: the range)";
  e.python = "eyebox_step", e.real = &ContrastOptions::eyebox_step_m;
  add();
}

void AddOtherOptions(std::vector<ContrastOptionEntry>& t) {
  ContrastOptionEntry e;
  auto add = [&] {
    e.in_scene = false;
    t.push_back(e);
    e = ContrastOptionEntry{};
  };
  e.key = "reference", e.kind = Kind::kChoice, e.type = "sampled, continuous", e.default_text = "sampled";
  e.meaning =
      "what normalizes: natural viewing of the sampled target light field (a perfect display scores 1), or of the "
      "continuous plane (every display then also scaled by its pixel hold, sinc(f p))";
  e.cli_flag = "--reference", e.cli_help =
                                  "Normalize by natural viewing of the sampled target light field (a perfect display "
                                  "scores 1) or of the continuous plane: sampled or continuous";
  e.python = "reference", e.choices = {"sampled", "continuous"};
  e.get = [](const ContrastOptions& o) { return int(o.reference); };
  e.set = [](ContrastOptions& o, int i) { o.reference = ContrastReference(i); };
  add();
  e.key = "grating", e.kind = Kind::kChoice, e.type = "angle, plane", e.default_text = "angle";
  e.meaning = "the grating uniform in visual angle, or in meters on the plane";
  e.cli_flag = "--grating", e.cli_help = "Grating uniform in visual angle or in meters on the plane: angle or plane";
  e.python = "grating", e.choices = {"angle", "plane"};
  e.get = [](const ContrastOptions& o) { return int(o.grating); };
  e.set = [](ContrastOptions& o, int i) { o.grating = GratingSpacing(i); };
  add();
  e.key = "peak_uncertainty", e.kind = Kind::kBoolean, e.type = "boolean", e.default_text = "true";
  e.meaning = "a second sweep on a retina moved by half a sample, for each peak's sampling uncertainty";
  e.cli_flag = "--no-peak-uncertainty";
  e.cli_help = "Skip the second sweep on a retina moved by half a sample (the peaks' uncertainty)";
  e.python = "peak_uncertainty";
  e.get = [](const ContrastOptions& o) { return int(o.peak_uncertainty); };
  e.set = [](ContrastOptions& o, int i) { o.peak_uncertainty = i != 0; };
  add();
}

}  // namespace

const std::vector<ContrastOptionEntry>& ContrastOptionTable() {
  static const std::vector<ContrastOptionEntry> table = [] {
    std::vector<ContrastOptionEntry> t;
    AddSceneKeys(t);
    AddEyeboxKeys(t);
    AddOtherOptions(t);
    return t;
  }();
  return table;
}

const ContrastOptionEntry* FindContrastOption(const std::string& key) { return FindOption(ContrastOptionTable(), key); }

bool ContrastOptions::IsValid(std::string* error) const {
  if (!RangesHold(ContrastOptionTable(), *this, error)) return false;
  if (!(accommodation_step_diopters > 0)) {
    *error = OptionViolation("accommodation.step", accommodation_step_diopters, "must be above 0 D");
    return false;
  }
  if (std::string grid = EyeboxGridViolation(eyebox_range_m, eyebox_step_m, kMaxContrastEyeboxPupils); !grid.empty()) {
    *error = std::move(grid);
    return false;
  }
  if (!(accommodation_max_diopters > accommodation_min_diopters)) {
    *error =
        OptionViolation("accommodation.to", accommodation_max_diopters,
                        "must be beyond accommodation.from (" + FormatFixed(accommodation_min_diopters, 2) + " D)");
    return false;
  }
  return true;
}

}  // namespace layerlab
