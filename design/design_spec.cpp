#include "layerlab/design/design_spec.h"

#include <cmath>
#include <filesystem>
#include <optional>
#include <set>
#include <system_error>

#include "layerlab/design/design_gradient.h"
#include "layerlab/elements/registry.h"
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

struct Amount {
  double value = 0;
  std::string unit;
};

// "0.4 D" -> (0.4, "D"); 0.4 -> (0.4, ""): a number with the unit it is written in, not converted.
Amount ReadAmount(const nlohmann::json& v, const Location& at) {
  if (v.is_number()) {
    const double x = v.get<double>();
    if (!std::isfinite(x)) throw Error(at, "must be a finite number");
    return {x, ""};
  }
  if (v.is_string())
    if (auto n = NumberWithUnit(v.get<std::string>()); n && std::isfinite(n->first)) return {n->first, n->second};
  throw Error(at, "must be a number or a quantity with its unit (\"0.4 D\", \"60 mm\"), not " + v.dump());
}

// Refuses a unit layerlab does not know, so that a typo is named here and not by every evaluation.
void CheckUnit(const std::string& unit, const Location& at) {
  if (unit.empty()) return;
  for (Dimension d : {Dimension::kLength, Dimension::kOpticalPower, Dimension::kAngle, Dimension::kLuminance,
                      Dimension::kAngularFrequency, Dimension::kFraction, Dimension::kTime, Dimension::kFrequency}) {
    try {
      ParseQuantity("1 " + unit, d);
      return;
    } catch (const Error&) {
    }
  }
  throw Error(at, "unknown unit \"" + unit + "\"");
}

Amount ReadAmountInUnit(Params& p, const std::string& key, const std::string& unit, const std::string& whose) {
  const Amount a = ReadAmount(p.raw(key), p.where(key));
  if (a.unit != unit)
    p.fail(key, "is in \"" + a.unit + "\", but " + whose + " is in \"" + unit +
                    "\": write it in that unit (the optimizer does not convert)");
  return a;
}

std::optional<double> SceneValueIn(const ordered_json& scene, const std::string& pointer, const std::string& unit) {
  const ordered_json& v = scene[ordered_json::json_pointer(pointer)];
  if (unit.empty() && v.is_number()) return v.get<double>();
  if (!v.is_string()) return std::nullopt;
  auto n = NumberWithUnit(v.get<std::string>());
  if (!n || n->second != unit) return std::nullopt;
  return n->first;
}

void CheckPointer(const DesignSpec& spec, const std::string& pointer, const Location& at) {
  RequireScenePointer(spec.base, spec.scene, pointer, at, "a variable", "/elements/3/virtual_depth");
  for (const std::string& path : ScenePathPointers(spec.base))
    if (path == pointer)
      throw Error(at, "\"" + pointer + "\" is a file path; a design sets numbers and settings, not paths");
}

// A variable sets a number: the value it replaces must be one, or a quantity.
void CheckNumberAt(const DesignSpec& spec, const std::string& pointer, const Location& at) {
  const ordered_json& v = spec.base[ordered_json::json_pointer(pointer)];
  if (!v.is_number() && !v.is_string())
    throw Error(at, "\"" + pointer + "\" holds " + JsonKindName(nlohmann::json::parse(v.dump())) +
                        " in the scene; a variable replaces a number or a quantity");
}

// Whether two JSON pointers name the same value or one lies inside the other.
bool Overlaps(const std::string& a, const std::string& b) {
  return a == b || a.rfind(b + "/", 0) == 0 || b.rfind(a + "/", 0) == 0;
}

// No scene value may be set twice, nor inside another that is set: the later write would undo the earlier.
void CheckDistinctWrites(const DesignSpec& spec, const std::string& pointer, const Location& at) {
  for (const DesignVariable& v : spec.variables)
    for (const DesignWrite& w : v.writes)
      if (Overlaps(w.pointer, pointer))
        throw Error(at,
                    "\"" + pointer + "\" overlaps \"" + w.pointer + "\", which the variable \"" + v.name + "\" sets");
}

DesignVariable ReadVariable(Params& p, const DesignSpec& spec) {
  DesignVariable v;
  v.name = p.string("name");
  if (v.name.empty()) p.fail("name", "is empty");
  const Amount lo = ReadAmount(p.raw("min"), p.where("min"));
  v.unit = lo.unit;
  CheckUnit(v.unit, p.where("min"));
  v.min = lo.value;
  v.max = ReadAmountInUnit(p, "max", v.unit, "\"min\"").value;
  if (!(v.min < v.max)) p.fail("max", "must be above \"min\" (" + FormatGeneral(v.min) + " " + v.unit + ")");
  if (!std::isfinite(v.max - v.min)) p.fail("max", "is too far from \"min\": their difference is not a finite number");
  if (p.has("pointer") == p.has("pointers")) p.fail("pointer", "give either \"pointer\" or \"pointers\"");
  if (p.has("pointer")) {
    v.writes.push_back({.pointer = p.string("pointer")});
    CheckPointer(spec, v.writes[0].pointer, p.where("pointer"));
    CheckDistinctWrites(spec, v.writes[0].pointer, p.where("pointer"));
    CheckNumberAt(spec, v.writes[0].pointer, p.where("pointer"));
  } else {
    const nlohmann::json& list = p.raw("pointers");
    if (!list.is_array() || list.empty())
      p.fail("pointers", "must be a non-empty array of {\"pointer\", \"scale\", \"offset\"}");
    for (size_t i = 0; i < list.size(); ++i) {
      const Location at = p.where("pointers").child(i);
      if (!list[i].is_object()) throw Error(at, "must be an object {\"pointer\", \"scale\", \"offset\"}");
      Params w(list[i], at);
      DesignWrite write{.pointer = w.string("pointer")};
      CheckPointer(spec, write.pointer, w.where("pointer"));
      CheckDistinctWrites(spec, write.pointer, w.where("pointer"));
      CheckNumberAt(spec, write.pointer, w.where("pointer"));
      for (const DesignWrite& earlier : v.writes)
        if (Overlaps(earlier.pointer, write.pointer))
          throw Error(w.where("pointer"),
                      "\"" + write.pointer + "\" overlaps \"" + earlier.pointer + "\" of this variable");
      if (w.has("scale")) {
        const nlohmann::json& s = w.raw("scale");
        if (!s.is_number() || !std::isfinite(s.get<double>()) || s.get<double>() == 0)
          w.fail("scale", "must be a non-zero number");
        write.scale = s.get<double>();
      }
      if (w.has("offset")) write.offset = ReadAmountInUnit(w, "offset", v.unit, "the variable").value;
      w.check_all_read();
      v.writes.push_back(write);
    }
  }
  const DesignWrite& first = v.writes.front();
  v.start = 0.5 * (v.min + v.max);
  if (auto now = SceneValueIn(spec.base, first.pointer, v.unit)) {
    const double x = (*now - first.offset) / first.scale;
    if (x >= v.min && x <= v.max) v.start = x;
  }
  if (p.has("start")) {
    v.start = ReadAmountInUnit(p, "start", v.unit, "\"min\"").value;
    if (v.start < v.min || v.start > v.max) p.fail("start", "is outside [min, max]");
  }
  v.tolerance = (v.max - v.min) / 1000;
  if (p.has("tolerance")) {
    v.tolerance = ReadAmountInUnit(p, "tolerance", v.unit, "\"min\"").value;
    if (!(v.tolerance > 0)) p.fail("tolerance", "must be positive");
  }
  return v;
}

// The base scene with every variable at its start must be one the scene reader takes: a variable in
// a unit its value cannot have is named here, not by every evaluation.
void CheckStartScene(Params& p, const DesignSpec& spec) {
  ordered_json scene = spec.base;
  for (const DesignVariable& v : spec.variables)
    for (const DesignWrite& w : v.writes)
      scene[ordered_json::json_pointer(w.pointer)] = v.SceneValue(w.scale * v.start + w.offset);
  try {
    ParamsKeyRecorder scene_keys;
    ParseScene(nlohmann::json::parse(scene.dump()), spec.scene, ElementRegistry::WithBuiltins());
  } catch (const Error& e) {
    p.fail("variables", "the base scene with the variables at their starts is not usable: " + std::string(e.what()));
  }
}

// "fixed": values written into the base scene itself, before anything else reads it. A value may
// be new where its parent object exists (a "run" section the base scene lacks); none may hold a path.
void ReadFixed(Params& p, DesignSpec* spec) {
  const nlohmann::json& fixed = p.raw("fixed");
  if (!fixed.is_object()) p.fail("fixed", "must be an object of JSON pointers and values");
  const std::vector<std::string> paths = ScenePathPointers(spec->base);
  for (const auto& [pointer, value] : fixed.items()) {
    const Location at = p.where("fixed").child(pointer);
    std::optional<ordered_json::json_pointer> where;
    try {
      where = ordered_json::json_pointer(pointer);
    } catch (const ordered_json::exception&) {
      throw Error(at, "\"" + pointer + "\" is not a JSON pointer (\"/elements/2/fill_factor\")");
    }
    if (pointer.empty()) throw Error(at, "the whole scene cannot be a design value");
    const ordered_json::json_pointer parent = where->parent_pointer();
    bool there = false, parent_there = false;
    try {
      there = spec->base.contains(*where);
      parent_there = spec->base.contains(parent) && spec->base[parent].is_object();
    } catch (const ordered_json::exception&) {
      throw Error(at, "\"" + pointer + "\" is not a place in the scene (an array index out of range)");
    }
    if (!there && !parent_there)
      throw Error(at, "\"" + pointer + "\" is not in the scene " + spec->scene + ", nor is the object it would go in");
    for (const DesignVariable& v : spec->variables)
      for (const DesignWrite& w : v.writes)
        if (Overlaps(w.pointer, pointer)) throw Error(at, "holds what the variable \"" + v.name + "\" sets");
    spec->base[*where] = ordered_json::parse(value.dump());
    if (ScenePathPointers(spec->base) != paths)
      throw Error(at, "holds a file path; a fixed value is a number or a setting");
  }
  try {
    ParamsKeyRecorder scene_keys;
    ParseScene(nlohmann::json::parse(spec->base.dump()), spec->scene, ElementRegistry::WithBuiltins());
  } catch (const Error& e) {
    p.fail("fixed", "the base scene with these values is not usable: " + std::string(e.what()));
  }
}

size_t AddMetric(DesignSpec* spec, const std::string& name, const Location& at) {
  std::string error;
  const std::optional<DesignMetric> m = FindDesignMetric(name, &error);
  if (!m) throw Error(at, error);
  for (size_t i = 0; i < spec->metrics.size(); ++i)
    if (spec->metrics[i].name == name) return i;
  spec->metrics.push_back(*m);
  return spec->metrics.size() - 1;
}

DesignConstraint ReadConstraint(Params& p, DesignSpec* spec) {
  DesignConstraint c;
  c.name = p.string("name");
  if (c.name.empty()) p.fail("name", "is empty");
  if (p.has("terms") == p.has("metric")) p.fail("terms", "give either \"terms\" (linear) or \"metric\"");
  if (p.has("metric")) {
    c.metric = AddMetric(spec, p.string("metric"), p.where("metric"));
    c.unit = spec->metrics[*c.metric].unit;
    c.what = spec->metrics[*c.metric].column();
  } else {
    const nlohmann::json& terms = p.raw("terms");
    if (!terms.is_object() || terms.empty())
      p.fail("terms", "must be an object of variable names and coefficients ({\"front\": 1, \"rear\": -1})");
    c.coefficients.assign(spec->variables.size(), 0.0);
    std::optional<std::string> unit;
    for (const auto& [name, coefficient] : terms.items()) {
      const Location at = p.where("terms").child(name);
      size_t k = 0;
      while (k < spec->variables.size() && spec->variables[k].name != name) ++k;
      if (k == spec->variables.size()) throw Error(at, "\"" + name + "\" is not a variable of this design");
      if (!coefficient.is_number() || !std::isfinite(coefficient.get<double>()))
        throw Error(at, "must be a number (the variable's coefficient)");
      if (unit && *unit != spec->variables[k].unit)
        throw Error(at, "\"" + name + "\" is in \"" + spec->variables[k].unit + "\" and another term in \"" + *unit +
                            "\": a constraint adds values of one unit");
      unit = spec->variables[k].unit;
      c.coefficients[k] = coefficient.get<double>();
      const double a = c.coefficients[k];
      c.what += (c.what.empty() ? (a < 0 ? "-" : "") : (a < 0 ? " - " : " + ")) +
                (std::abs(a) == 1 ? "" : FormatGeneral(std::abs(a)) + " ") + name;
    }
    c.unit = *unit;
    c.what += c.unit.empty() ? "" : " (" + c.unit + ")";
  }
  if (!p.has("min") && !p.has("max")) p.fail("min", "a constraint needs \"min\", \"max\" or both");
  const std::string whose = c.metric ? "its metric" : "its terms";
  const std::string unit = c.unit == "1" ? "" : c.unit;
  if (p.has("min")) c.min = ReadAmountInUnit(p, "min", unit, whose).value;
  if (p.has("max")) c.max = ReadAmountInUnit(p, "max", unit, whose).value;
  if (c.min && c.max && !(*c.min < *c.max))
    p.fail("max", *c.min == *c.max
                      ? "equals \"min\": an equality leaves no room to search; fix a variable instead, or give a range"
                      : "is below \"min\"");
  for (size_t k = 0; k < c.coefficients.size(); ++k)
    if (!std::isfinite(c.coefficients[k] * spec->variables[k].min) ||
        !std::isfinite(c.coefficients[k] * spec->variables[k].max))
      p.fail("terms", "the coefficient of \"" + spec->variables[k].name + "\" times its bounds is not a finite number");
  double reach = 0;
  for (size_t k = 0; k < c.coefficients.size(); ++k)
    reach += std::abs(c.coefficients[k]) * std::max(std::abs(spec->variables[k].min), std::abs(spec->variables[k].max));
  if (!std::isfinite(reach)) p.fail("terms", "the sum of the terms over the bounds is not a finite number");
  return c;
}

void ReadObjective(Params& p, DesignSpec* spec) {
  const nlohmann::json& o = p.raw("objective");
  if (o.is_string()) {
    spec->objective.push_back({AddMetric(spec, o.get<std::string>(), p.where("objective")), 1.0});
    return;
  }
  if (!o.is_object()) p.fail("objective", "must be a metric name (\"psnr\") or {\"terms\": [...]}");
  Params q = p.object("objective");
  const nlohmann::json& terms = q.raw("terms");
  if (!terms.is_array() || terms.empty()) q.fail("terms", "must be a non-empty array of {\"metric\", \"weight\"}");
  for (size_t i = 0; i < terms.size(); ++i) {
    const Location at = q.where("terms").child(i);
    if (!terms[i].is_object()) throw Error(at, "must be an object {\"metric\", \"weight\"}");
    Params t(terms[i], at);
    DesignTerm term{.metric = AddMetric(spec, t.string("metric"), t.where("metric"))};
    if (t.has("weight")) {
      const nlohmann::json& w = t.raw("weight");
      if (!w.is_number() || !(w.get<double>() > 0) || !std::isfinite(w.get<double>()))
        t.fail("weight", "must be a positive number");
      term.weight = w.get<double>();
    }
    for (const DesignTerm& other : spec->objective)
      if (other.metric == term.metric) t.fail("metric", "is already a term of the objective");
    t.check_all_read();
    spec->objective.push_back(term);
  }
  q.check_all_read();
}

}  // namespace

std::string BudgetProblem(const DesignOptimizer& o) {
  if (o.evaluations >= o.starts) return "";
  return "fewer evaluations than the " + std::to_string(o.starts) +
         " starts: each start's local search needs at least one evaluation";
}

namespace {

DesignOptimizer ReadOptimizer(Params& p) {
  DesignOptimizer o;
  if (!p.has("optimizer")) return o;
  if (!p.raw("optimizer").is_object())
    p.fail("optimizer", "must be an object (local, global, starts, evaluations, seconds, seed)");
  Params q = p.object("optimizer");
  o.local = q.choice("local", {"cobyla", "bobyqa", "nelder-mead", "slsqp"}, "cobyla");
  o.global = q.choice("global", {"none", "mlsl", "crs", "multistart"}, "none");
  o.evaluations = static_cast<int>(q.integer("evaluations", 1, 100000, 60));
  if (o.global == "multistart") {
    o.starts = static_cast<int>(q.integer("starts", 2, 256, 4));
    if (const std::string problem = BudgetProblem(o); !problem.empty())
      q.fail("evaluations", "is " + std::to_string(o.evaluations) + ": " + problem);
  } else if (q.has("starts")) {
    q.fail("starts",
           "is read only with \"global\": \"multistart\" (this design's global stage is \"" + o.global + "\")");
  }
  if (q.has("seconds")) {
    const double s = q.quantity("seconds", Dimension::kTime);
    if (!(s > 0)) q.fail("seconds", "must be positive");
    o.seconds = s;
  }
  o.seed = static_cast<unsigned>(q.integer("seed", 0, 4294967295LL, 1));
  q.check_all_read();
  return o;
}

// The run section of each evaluation: the work the metrics need, and for a focal-stack metric the
// retinal metric listed (the base scene's settings otherwise).
void CheckWork(Params& p, DesignSpec* spec) {
  for (const DesignMetric& m : spec->metrics) {
    spec->work_solve |= m.solve;
    spec->work_retina |= m.retina;
    spec->work_contrast |= m.contrast;
  }
  const ordered_json* solve = spec->base.contains("solve") ? &spec->base["solve"] : nullptr;
  if (spec->work_solve && spec->targets.empty() &&
      !(solve && (solve->contains("target") || solve->contains("target_scene"))))
    p.fail("objective", "its metrics need a solve, and the base scene " + spec->scene +
                            " has no /solve/target or /solve/target_scene (or give \"targets\")");
  // Without states of its own, run.retina looks at the layers' depths: a mean over them would move
  // with the very depths being optimized.
  const ordered_json* run = spec->base.contains("run") ? &spec->base["run"] : nullptr;
  const ordered_json* retina = run && run->is_object() && run->contains("retina") ? &(*run)["retina"] : nullptr;
  if (spec->work_retina &&
      !(retina && retina->is_object() && (retina->contains("accommodation") || retina->contains("focal_stack"))))
    p.fail("objective",
           "a retinal metric is a mean over the retinal states, and the base scene " + spec->scene +
               " names none (run.retina.accommodation or run.retina.focal_stack): they would be the layers' depths, "
               "which the optimizer moves. Give them in the scene or in \"fixed\": {\"/run\": {\"retina\": "
               "{\"focal_stack\": {\"from\": \"0 D\", \"to\": \"2.6 D\", \"step\": \"0.1 D\"}}}}");
}

}  // namespace

std::string DesignVariable::column() const { return unit.empty() ? name : name + " (" + unit + ")"; }

nlohmann::ordered_json DesignVariable::SceneValue(double x) const {
  if (unit.empty()) return x;
  char text[64];
  std::snprintf(text, sizeof text, "%.17g %s", x, unit.c_str());
  return text;
}

std::string DesignSpec::objective_column() const {
  if (objective.size() == 1) return metrics[objective[0].metric].column();
  return "weighted sum (1)";
}

DesignSpec ReadDesignSpec(const std::string& path) {
  DesignSpec spec;
  spec.file = path;
  const nlohmann::json document = ReadJsonFile(path);
  if (!document.is_object()) throw Error(Location{path, ""}, "a design file is a JSON object");
  Params p(document, Location{path, ""});
  if (const std::string format = p.string("format"); format != kDesignFormat)
    p.fail("format", "is \"" + format + "\"; a design file is \"" + kDesignFormat + "\"");
  spec.name = p.string("name", fs::path(path).stem().string());
  spec.description = p.string("description", "");
  const std::string scene = p.string("scene");
  spec.scene =
      fs::path(scene).is_absolute() ? scene : (fs::path(path).parent_path() / scene).lexically_normal().string();
  try {
    ParamsKeyRecorder scene_keys;  // the scene's keys are its own tables', as in a sweep (analysis/sweep_spec.cpp)
    LoadScene(spec.scene);
  } catch (const Error& e) {
    throw Error(p.where("scene"), "the base scene is not usable: " + std::string(e.what()));
  }
  spec.base = ReadDocumentInOrder(spec.scene);

  const nlohmann::json& variables = p.raw("variables");
  if (!variables.is_array() || variables.empty()) p.fail("variables", "must be a non-empty array of variables");
  if (variables.size() > kMaxDesignVariables)
    p.fail("variables", "has " + std::to_string(variables.size()) +
                            " variables; a derivative-free search of more than " + std::to_string(kMaxDesignVariables) +
                            " is surely a mistake");
  std::set<std::string> names;
  for (size_t i = 0; i < variables.size(); ++i) {
    const Location at = p.where("variables").child(i);
    if (!variables[i].is_object()) throw Error(at, "a variable is an object (name, pointer, min, max)");
    Params q(variables[i], at);
    spec.variables.push_back(ReadVariable(q, spec));
    q.check_all_read();
    if (!names.insert(spec.variables.back().name).second)
      throw Error(at.child("name"), "\"" + spec.variables.back().name + "\" names two variables");
  }
  if (p.has("fixed")) ReadFixed(p, &spec);
  CheckStartScene(p, spec);
  ReadObjective(p, &spec);
  if (p.has("constraints")) {
    const nlohmann::json& constraints = p.raw("constraints");
    if (!constraints.is_array()) p.fail("constraints", "must be an array of constraints");
    if (constraints.size() > kMaxDesignConstraints)
      p.fail("constraints", "has " + std::to_string(constraints.size()) + " constraints; more than " +
                                std::to_string(kMaxDesignConstraints) + " is surely a mistake");
    for (size_t i = 0; i < constraints.size(); ++i) {
      const Location at = p.where("constraints").child(i);
      if (!constraints[i].is_object()) throw Error(at, "a constraint is an object (name, terms or metric, min, max)");
      Params q(constraints[i], at);
      spec.constraints.push_back(ReadConstraint(q, &spec));
      q.check_all_read();
    }
  }
  if (p.has("targets")) {
    const nlohmann::json& targets = p.raw("targets");
    if (!targets.is_array() || targets.empty()) p.fail("targets", "must be a non-empty array of target scene paths");
    for (size_t i = 0; i < targets.size(); ++i) {
      if (!targets[i].is_string()) throw Error(p.where("targets").child(i), "must be a path (a string)");
      const fs::path t = targets[i].get<std::string>();
      std::error_code absolute_error;  // written into each job's scene, whose folder is elsewhere
      const fs::path target = fs::absolute(t.is_absolute() ? t : fs::path(path).parent_path() / t, absolute_error);
      if (absolute_error)
        throw Error(p.where("targets").child(i), "cannot resolve the path: " + absolute_error.message());
      spec.targets.push_back(target.lexically_normal().string());
      std::error_code ec;
      if (!fs::is_regular_file(spec.targets.back(), ec))
        throw Error(p.where("targets").child(i), "\"" + spec.targets.back() + "\" is not a file");
    }
  }
  if (p.has("iterations")) spec.iterations = static_cast<int>(p.integer("iterations", 1, 1000000));
  spec.threads = static_cast<int>(p.integer("threads", 0, 1024, 0));
  spec.warm_start = p.boolean("warm_start", true);
  spec.optimizer = ReadOptimizer(p);
  if (spec.optimizer.local == "slsqp")
    if (const std::string problem = GradientProblem(spec); !problem.empty())
      p.fail("optimizer",
             "\"local\": \"slsqp\" follows the exact gradient of the solve's PSNR, which needs more: " + problem);
  CheckWork(p, &spec);
  p.check_all_read();
  return spec;
}

}  // namespace layerlab
