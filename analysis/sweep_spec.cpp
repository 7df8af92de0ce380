#include "layerlab/analysis/sweep_spec.h"

#include <cstdlib>
#include <filesystem>
#include <set>

#include "layerlab/framework/checked_count.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/units.h"
#include "layerlab/systems/scene.h"
#include "layerlab/systems/scene_document.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

ordered_json InOrder(const nlohmann::json& value) { return ordered_json::parse(value.dump()); }

std::string LabelOf(const ordered_json& value) { return value.is_string() ? value.get<std::string>() : value.dump(); }

void ReadLabels(SweepParameter* p) {
  std::vector<double> numbers;
  std::set<std::string> units;
  for (const std::string& label : p->labels) {
    auto n = NumberWithUnit(label);
    if (!n) return;
    numbers.push_back(n->first);
    units.insert(n->second);
  }
  if (units.size() != 1) return;
  p->unit = *units.begin();
  p->numbers = numbers;
  if (p->unit.empty()) p->unit = "1";  // plain numbers: a dimensionless column
}

bool IsPathPointer(const ordered_json& scene, const std::string& pointer) {
  for (const std::string& p : ScenePathPointers(scene))
    if (p == pointer) return true;
  return false;
}

SweepParameter ReadParameter(Params& p, const SweepSpec& spec) {
  SweepParameter out;
  out.name = p.string("name");
  if (out.name.empty()) p.fail("name", "is empty");
  if (p.has("pointer") == p.has("pointers")) p.fail("pointer", "give either \"pointer\" or \"pointers\"");
  if (p.has("pointer")) {
    out.pointers = {p.string("pointer")};
  } else {
    const nlohmann::json& list = p.raw("pointers");
    if (!list.is_array() || list.empty()) p.fail("pointers", "must be a non-empty array of JSON pointers");
    for (size_t i = 0; i < list.size(); ++i) {
      if (!list[i].is_string()) throw Error(p.where("pointers").child(i), "must be a JSON pointer (a string)");
      out.pointers.push_back(list[i].get<std::string>());
    }
  }
  const std::string key = p.has("pointer") ? "pointer" : "pointers";
  for (size_t i = 0; i < out.pointers.size(); ++i) {
    const Location at = key == "pointer" ? p.where(key) : p.where(key).child(i);
    RequireScenePointer(spec.base, spec.scene, out.pointers[i], at, "a parameter", "/elements/0/pupil_diameter");
  }
  const nlohmann::json& values = p.raw("values");
  if (!values.is_array()) p.fail("values", "must be an array");
  if (values.empty()) p.fail("values", "is empty: a parameter needs at least one value");
  for (size_t i = 0; i < values.size(); ++i) {
    if (out.pointers.size() > 1 && (!values[i].is_array() || values[i].size() != out.pointers.size()))
      throw Error(p.where("values").child(i), "must be an array of " + std::to_string(out.pointers.size()) +
                                                  " values, one per pointer in \"pointers\"");
    out.values.push_back(InOrder(values[i]));
    out.labels.push_back(LabelOf(out.values.back()));
  }
  if (p.has("labels")) {
    const nlohmann::json& labels = p.raw("labels");
    if (!labels.is_array() || labels.size() != values.size())
      p.fail("labels", "must be an array of " + std::to_string(values.size()) + " strings, one per value");
    for (size_t i = 0; i < labels.size(); ++i) {
      if (!labels[i].is_string()) throw Error(p.where("labels").child(i), "must be a string");
      out.labels[i] = labels[i].get<std::string>();
    }
  }
  std::set<std::string> seen;
  for (size_t i = 0; i < out.labels.size(); ++i)
    if (!seen.insert(out.labels[i]).second)
      throw Error(p.where(p.has("labels") ? "labels" : "values").child(i),
                  "\"" + out.labels[i] + "\" appears twice: each point of the grid needs its own label");
  // Path values are written relative to the sweep file; a job's scene lives elsewhere.
  for (size_t k = 0; k < out.pointers.size(); ++k) {
    if (!IsPathPointer(spec.base, out.pointers[k])) continue;
    for (size_t i = 0; i < out.values.size(); ++i) {
      ordered_json& v = out.pointers.size() > 1 ? out.values[i][k] : out.values[i];
      if (!v.is_string()) throw Error(p.where("values").child(i), "must be a path (a string)");
      if (fs::path(v.get<std::string>()).is_relative())
        v = (fs::absolute(spec.file).parent_path() / v.get<std::string>()).lexically_normal().string();
    }
  }
  ReadLabels(&out);
  return out;
}

}  // namespace

std::string SweepParameter::column() const { return unit.empty() || unit == "1" ? name : name + " (" + unit + ")"; }

size_t SweepSpec::job_count() const {
  size_t n = 1;
  for (const SweepParameter& p : parameters)
    n = CheckedProduct({n, p.values.size()}, Location{file, "/parameters"}, "the grid's points");
  return n;
}

std::vector<std::string> SweepSpec::work() const {
  std::vector<std::string> w;
  if (solve) w.push_back("solve");
  if (retina) w.push_back("retina");
  if (contrast) w.push_back("contrast");
  return w;
}

SweepSpec ReadSweepSpec(const std::string& path) {
  SweepSpec spec;
  spec.file = path;
  const nlohmann::json document = ReadJsonFile(path);
  if (!document.is_object()) throw Error(Location{path, ""}, "a sweep file is a JSON object");
  Params p(document, Location{path, ""});
  if (const std::string format = p.string("format"); format != kSweepFormat)
    p.fail("format", "is \"" + format + "\"; a sweep file is \"" + kSweepFormat + "\"");
  spec.named = p.has("name");
  spec.name = p.string("name", fs::path(path).stem().string());
  spec.description = p.string("description", "");
  const std::string scene = p.string("scene");
  spec.scene = (fs::path(path).parent_path() / scene).lexically_normal().string();
  if (fs::path(scene).is_absolute()) spec.scene = scene;
  try {
    // The base scene's keys are its own tables' (tests/scene_reference_test.cpp), not the sweep's: a
    // recorder of this scope keeps them out of one a caller has, which records JSON pointers, not files.
    ParamsKeyRecorder scene_keys;
    LoadScene(spec.scene);  // checked whole before anything is expanded
  } catch (const Error& e) {
    throw Error(p.where("scene"), "the base scene is not usable: " + std::string(e.what()));
  }
  spec.base = ReadDocumentInOrder(spec.scene);

  const nlohmann::json& work = p.raw("work");
  if (!work.is_array() || work.empty())
    p.fail("work", "must be a non-empty array of \"solve\", \"retina\", \"contrast\"");
  for (size_t i = 0; i < work.size(); ++i) {
    const std::string w = work[i].is_string() ? work[i].get<std::string>() : work[i].dump();
    bool* flag = w == "solve" ? &spec.solve : w == "retina" ? &spec.retina : w == "contrast" ? &spec.contrast : nullptr;
    if (!flag) {
      std::string hint;
      if (auto near = ClosestWord(w, {"solve", "retina", "contrast"})) hint = " (did you mean \"" + *near + "\"?)";
      throw Error(p.where("work").child(i), "unknown work \"" + w + "\"; known: solve, retina, contrast" + hint);
    }
    if (*flag) throw Error(p.where("work").child(i), "\"" + w + "\" is listed twice");
    *flag = true;
  }
  if (spec.retina && !spec.solve) p.fail("work", "\"retina\" looks at the solved patterns: it needs \"solve\" too");
  const ordered_json* solve_section = spec.base.contains("solve") ? &spec.base["solve"] : nullptr;
  if (spec.solve && !(solve_section && (solve_section->contains("target") || solve_section->contains("target_scene"))))
    p.fail("work",
           "\"solve\" needs a target: the base scene " + spec.scene + " has no /solve/target or /solve/target_scene");
  if (p.has("iterations")) spec.iterations = static_cast<int>(p.integer("iterations", 1, 1000000));
  spec.threads = static_cast<int>(p.integer("threads", 0, 1024, 1));
  if (p.has("slurm")) {
    if (!p.raw("slurm").is_object())
      p.fail("slurm", "must be an object (time, mem, partition, account, cpus-per-task)");
    Params slurm = p.object("slurm");
    spec.slurm = ReadSlurmResources(slurm);
  }

  const nlohmann::json& parameters = p.raw("parameters");
  if (!parameters.is_array()) p.fail("parameters", "must be an array of parameters");
  if (parameters.empty()) p.fail("parameters", "is empty: a sweep needs at least one parameter");
  std::set<std::string> names;
  for (size_t i = 0; i < parameters.size(); ++i) {
    const Location at = p.where("parameters").child(i);
    if (!parameters[i].is_object()) throw Error(at, "a parameter is an object (name, pointer, values)");
    Params q(parameters[i], at);
    spec.parameters.push_back(ReadParameter(q, spec));
    q.check_all_read();
    if (!names.insert(spec.parameters.back().name).second)
      throw Error(at.child("name"), "\"" + spec.parameters.back().name + "\" names two parameters");
  }
  p.check_all_read();
  if (const size_t points = spec.job_count(); points > kMaxSweepPoints)
    p.fail("parameters", "the grid has " + std::to_string(points) + " points; more than " +
                             std::to_string(kMaxSweepPoints) + " is surely a mistake");
  return spec;
}

}  // namespace layerlab
