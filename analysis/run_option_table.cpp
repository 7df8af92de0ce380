#include "layerlab/analysis/run_option_table.h"

#include <optional>

#include "layerlab/framework/error.h"
#include "layerlab/solvers/solver_option_table.h"

namespace layerlab {
namespace {

using Kind = OptionKind;

// One entry of kind kConfig: a key its reader reads by hand.
template <class Options>
OptionEntry<Options> ByHand(const std::string& key, const std::string& type, const std::string& default_text,
                            const std::string& meaning) {
  OptionEntry<Options> e;
  e.key = key, e.kind = Kind::kConfig, e.type = type, e.default_text = default_text, e.meaning = meaning;
  return e;
}

std::vector<RunOptionEntry> MakeRunTable() {
  std::vector<RunOptionEntry> t = {
      ByHand<RunConfig>("retina", "object", "none", "retinal images over accommodation (run.retina)"),
      ByHand<RunConfig>("contrast", "object", "none", "contrast against accommodation, Fig. 5 (run.contrast)"),
      ByHand<RunConfig>("compare", "object", "none", "other displays on the same target (run.compare)"),
      ByHand<RunConfig>("frames", "object", "none", "a moving target scene solved frame by frame (run.frames)")};
  RunOptionEntry e;
  e.key = "write_lightfield", e.kind = Kind::kBoolean, e.type = "boolean", e.default_text = "false";
  e.meaning = "the solve also writes the synthesized light field";
  e.get = [](const RunConfig& o) { return int(o.write_lightfield); };
  e.set = [](RunConfig& o, int i) { o.write_lightfield = i != 0; };
  t.push_back(e);
  return t;
}

std::vector<RetinaRunOptionEntry> MakeRetinaTable() {
  std::vector<RetinaRunOptionEntry> t;
  RetinaRunOptionEntry e;
  auto add = [&] {
    t.push_back(e);
    e = RetinaRunOptionEntry{};
  };
  e.key = "accommodation", e.kind = Kind::kReal, e.type = "array of depths", e.dimension = Dimension::kOpticalPower;
  e.has_range = true, e.range = {0, 20, false, false}, e.constraint_note = " D";
  e.default_text = "the display's layer depths", e.meaning = "states shown as the slider's marks";
  e.list = &RetinaRunConfig::accommodation_diopters;
  add();
  t.push_back(ByHand<RetinaRunConfig>("focal_stack", "{from, to, step}: depth_range", "none",
                                      "more states, so that the slider scrubs a focal stack"));
  e.key = "resolution", e.kind = Kind::kReal, e.type = "angle", e.dimension = Dimension::kAngle, e.unit = "deg";
  e.has_range = true, e.range = {0, 10, true, true}, e.constraint_note = " deg";
  e.default_text = "0.05 deg", e.meaning = "retinal sample size", e.real = &RetinaRunConfig::resolution_deg;
  add();
  e = ByHand<RetinaRunConfig>("field", "[angle, angle] or angle", "the display's field of view",
                              "retinal field, centered");
  e.dimension = Dimension::kAngle, e.unit = "deg", e.has_range = true, e.range = {0, 170, true, true};
  e.constraint_note = " deg";
  add();
  t.push_back(ByHand<RetinaRunConfig>("metrics", "names, comma-separated", "\"psnr\"",
                                      "each state's display image scored against natural viewing, a retina.csv "
                                      "column each: psnr, ssim, ms_ssim, jnd, or all (docs/metrics.md)"));
  t.push_back(ByHand<RetinaRunConfig>("fovea", "[angle, angle]", "none (uniform)",
                                      "weight every metric by eccentricity from this gaze, right and up from the "
                                      "retina's centre (docs/metrics.md)"));
  t.push_back(ByHand<RetinaRunConfig>("jnd_minkowski_exponent", "number, at least 1", "4",
                                      "the JND metric's Minkowski pooling exponent (docs/metrics.md)"));
  e.key = "natural", e.kind = Kind::kBoolean, e.type = "boolean", e.default_text = "true";
  e.meaning = "also natural viewing of the target, side by side";
  e.get = [](const RetinaRunConfig& o) { return int(o.natural); };
  e.set = [](RetinaRunConfig& o, int i) { o.natural = i != 0; };
  add();
  e.key = "natural_viewing", e.kind = Kind::kChoice, e.type = "string", e.default_text = "light field";
  e.meaning =
      "\"light field\": the eye looks at the target light field, the rays the display is asked to reproduce; "
      "\"traced\": at a target scene itself, traced ray by ray with Embree (finer than the views, seconds per state)";
  e.choices = {"light field", "traced"};
  e.get = [](const RetinaRunConfig& o) { return int(o.natural_traced); };
  e.set = [](RetinaRunConfig& o, int i) { o.natural_traced = i != 0; };
  add();
  e.key = "exr", e.kind = Kind::kChoice, e.type = "string", e.default_text = "half";
  e.meaning =
      "how the retinal images' EXRs store a value: \"half\" (16 bits, a relative error of at most 0.049 %, half "
      "the size: pictures to look at; retina.csv and the page's numbers come from the float images) or \"float\"";
  e.choices = {"half", "float"};
  e.get = [](const RetinaRunConfig& o) { return int(o.exr_float); };
  e.set = [](RetinaRunConfig& o, int i) { o.exr_float = i != 0; };
  add();
  return t;
}

std::vector<CompareRunOptionEntry> MakeCompareTable() {
  std::vector<CompareRunOptionEntry> t = {
      ByHand<CompareRunConfig>("scenes", "array of paths", "none", "displays beside this one"),
      ByHand<CompareRunConfig>("solvers", "array of solver names", "each scene's own",
                               "every display runs every solver it suits")};
  // Unset unless given (std::optional fields): read by hand, with these ranges.
  CompareRunOptionEntry e =
      ByHand<CompareRunConfig>("iterations", "integer", "each run's own", "outer iterations of every run");
  e.has_range = true, e.range = FindSolverOption("iterations")->range;
  t.push_back(e);
  e = ByHand<CompareRunConfig>("time_budget", "time", "each run's own", "wall-clock budget of every run");
  e.dimension = Dimension::kTime, e.has_range = true, e.range = {0, 1e7, true, false}, e.constraint_note = " s";
  t.push_back(e);
  t.push_back(ByHand<CompareRunConfig>(
      "objectives", "array of strings", "each run's own",
      "\"lightfield\", \"retinal\": each solver runs each objective it minimizes (the retinal one: joint, "
      "quasi-newton); with \"retinal\" every row also records the focal-stack PSNR"));
  t.push_back(ByHand<CompareRunConfig>("metrics", "names, comma-separated", "none",
                                       "the focal stack also measured by these beside its PSNR: ssim, ms_ssim, jnd or "
                                       "all; every row then measures the focal stack (docs/metrics.md)"));
  t.push_back(ByHand<CompareRunConfig>("fovea", "[angle, angle]", "none (uniform)",
                                       "weight every metric by eccentricity from this gaze, right and up from the "
                                       "retina's centre (docs/metrics.md)"));
  t.push_back(ByHand<CompareRunConfig>("jnd_minkowski_exponent", "number, at least 1", "4",
                                       "the JND metric's Minkowski pooling exponent (docs/metrics.md)"));
  return t;
}

template <class Options>
const OptionEntry<Options>& Named(const std::vector<OptionEntry<Options>>& table, const std::string& key) {
  if (const OptionEntry<Options>* e = FindOption(table, key)) return *e;
  throw Error("run option table: no option \"" + key + "\"");
}

// False, with "field: value: constraint", when an optional value is set outside its entry's range.
template <class Options, class T>
bool SetValueHolds(const OptionEntry<Options>& e, const std::optional<T>& value, std::string* error) {
  if (!value || e.range.Contains(double(*value))) return true;
  *error = OptionViolation(e.key, double(*value), e.Constraint());
  return false;
}

std::vector<FramesRunOptionEntry> MakeFramesTable() {
  std::vector<FramesRunOptionEntry> t;
  auto integer = [&](const char* key, int FramesRunConfig::*field, double min, double max, const char* fallback,
                     const char* meaning) {
    FramesRunOptionEntry e;
    e.key = key, e.kind = Kind::kInteger, e.type = "integer", e.has_range = true, e.range = {min, max, false, false};
    e.default_text = fallback, e.meaning = meaning, e.integer = field;
    t.push_back(e);
  };
  integer("count", &FramesRunConfig::count, 1, 100000, "required", "frames, the first at time 0");
  integer("frame_iterations", &FramesRunConfig::frame_iterations, 1, 10000, "3",
          "iterations of each frame after the first, begun from the frame before");
  integer("cold_every", &FramesRunConfig::cold_every, 0, 100000, "1",
          "every k-th frame also solved cold, as its PSNR reference (0: none)");
  return t;
}

}  // namespace

const std::vector<RunOptionEntry>& RunOptionTable() {
  static const std::vector<RunOptionEntry> table = MakeRunTable();
  return table;
}

const std::vector<RetinaRunOptionEntry>& RetinaRunOptionTable() {
  static const std::vector<RetinaRunOptionEntry> table = MakeRetinaTable();
  return table;
}

const std::vector<CompareRunOptionEntry>& CompareRunOptionTable() {
  static const std::vector<CompareRunOptionEntry> table = MakeCompareTable();
  return table;
}

const RetinaRunOptionEntry& RetinaRunOption(const std::string& key) { return Named(RetinaRunOptionTable(), key); }
const CompareRunOptionEntry& CompareRunOption(const std::string& key) { return Named(CompareRunOptionTable(), key); }

const std::vector<FramesRunOptionEntry>& FramesRunOptionTable() {
  static const std::vector<FramesRunOptionEntry> table = MakeFramesTable();
  return table;
}

bool FramesRunConfig::IsValid(std::string* error) const { return RangesHold(FramesRunOptionTable(), *this, error); }

bool RetinaRunConfig::IsValid(std::string* error) const {
  if (!RangesHold(RetinaRunOptionTable(), *this, error)) return false;
  const RetinaRunOptionEntry& field = RetinaRunOption("field");
  for (double side : {field_x_deg, field_y_deg})  // 0 x 0: the display's field of view
    if (!(field_x_deg == 0 && field_y_deg == 0) && !field.range.Contains(side)) {
      *error = OptionViolation("field", side, field.Constraint());
      return false;
    }
  return true;
}

bool CompareRunConfig::IsValid(std::string* error) const {
  return SetValueHolds(CompareRunOption("iterations"), iterations, error) &&
         SetValueHolds(CompareRunOption("time_budget"), time_budget_s, error);
}

bool RunConfig::IsValid(std::string* error) const {
  return retina.IsValid(error) && contrast.options.IsValid(error) && compare.IsValid(error) &&
         (!frames.enabled || frames.IsValid(error));
}

}  // namespace layerlab
