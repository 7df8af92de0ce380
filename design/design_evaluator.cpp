#include "layerlab/design/design_evaluator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <system_error>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/units.h"
#include "layerlab/systems/scene_document.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

// The base scene as each evaluation runs it: for a focal-stack metric, its
// retinal metric among run.retina.metrics (psnr is always measured).
ordered_json BaseWithMetrics(const DesignSpec& spec) {
  ordered_json base = spec.base;
  for (const DesignMetric& m : spec.metrics) {
    if (m.retinal_metric.empty() || m.retinal_metric == "psnr") continue;
    if (!base.contains("run") || !base["run"].is_object()) base["run"] = ordered_json::object();
    ordered_json& run = base["run"];
    if (!run.contains("retina") || !run["retina"].is_object()) run["retina"] = ordered_json::object();
    ordered_json& retina = run["retina"];
    std::string list =
        retina.contains("metrics") && retina["metrics"].is_string() ? retina["metrics"].get<std::string>() : "psnr";
    std::string padded = "," + list + ",";
    padded.erase(std::remove(padded.begin(), padded.end(), ' '), padded.end());
    if (padded.find("," + m.retinal_metric + ",") == std::string::npos && padded != ",all,")
      list += "," + m.retinal_metric;
    retina["metrics"] = list;
  }
  return base;
}

SweepSpec SweepFor(const DesignSpec& spec, const ordered_json& base, const std::string& target) {
  SweepSpec s;
  s.file = spec.file;
  s.name = spec.name;
  s.scene = spec.scene;
  s.base = base;
  s.solve = spec.work_solve;
  s.retina = spec.work_retina;
  s.contrast = spec.work_contrast;
  s.threads = spec.threads;
  if (spec.iterations && spec.work_solve) {  // in the scene, so that its digest, which marks a job stale, covers it
    if (!s.base.contains("solve") || !s.base["solve"].is_object()) s.base["solve"] = ordered_json::object();
    s.base["solve"]["iterations"] = *spec.iterations;
  }
  if (!target.empty()) {
    if (!s.base.contains("solve") || !s.base["solve"].is_object()) s.base["solve"] = ordered_json::object();
    s.base["solve"].erase("target");
    s.base["solve"]["target_scene"] = target;
  }
  return s;
}

}  // namespace

DesignEvaluator::DesignEvaluator(const DesignSpec& spec, std::string out, std::string start)
    : spec_(spec), out_(std::move(out)), start_(std::move(start)) {
  log_ = start_.empty() ? (fs::path(out_) / "evaluations.jsonl").string()
                        : (fs::path(out_) / "starts" / start_ / "evaluations.jsonl").string();
  const ordered_json base = BaseWithMetrics(spec);
  if (spec.targets.empty())
    sweeps_.push_back(SweepFor(spec, base, ""));
  else
    for (const std::string& target : spec.targets) sweeps_.push_back(SweepFor(spec, base, target));
}

std::string DesignEvaluator::IdOf(size_t index) const {
  char text[32];
  std::snprintf(text, sizeof text, "e%04zu", index);
  return start_.empty() ? text : start_ + "-" + text;
}

std::vector<SceneValue> DesignEvaluator::ValuesOf(const std::vector<double>& x) const {
  std::vector<SceneValue> values;
  for (size_t k = 0; k < spec_.variables.size(); ++k) {
    const DesignVariable& v = spec_.variables[k];
    for (const DesignWrite& w : v.writes)
      values.push_back({w.pointer, v.SceneValue(w.scale * x[k] + w.offset),
                        Location{spec_.file, "/variables/" + std::to_string(k)}});
  }
  return values;
}

std::vector<SweepJob> DesignEvaluator::JobsOf(const DesignEvaluation& e) const {
  std::string labels;
  for (size_t k = 0; k < spec_.variables.size(); ++k)
    labels +=
        (k ? ", " : "") + spec_.variables[k].name + " = " + ordered_json(spec_.variables[k].SceneValue(e.x[k])).dump();
  std::vector<SweepJob> jobs;
  for (size_t t = 0; t < sweeps_.size(); ++t) {
    const std::string id = sweeps_.size() == 1 ? e.id : e.id + "-t" + std::to_string(t);
    jobs.push_back(MakeSweepJob(sweeps_[t], out_, id, ValuesOf(e.x),
                                "Evaluation " + e.id + " of the design " + spec_.file + ": the scene " + spec_.scene +
                                    " with " + labels + (spec_.warm_start ? "" : "; solved cold")));
  }
  return jobs;
}

ordered_json DesignEvaluator::SceneWith(const std::vector<double>& x) const {
  ordered_json scene = spec_.base;
  for (const SceneValue& v : ValuesOf(x)) scene[ordered_json::json_pointer(v.pointer)] = v.value;
  return scene;
}

const DesignEvaluation* DesignEvaluator::Nearest(const std::vector<double>& x) const {
  const DesignEvaluation* nearest = nullptr;
  double best = INFINITY;
  for (const DesignEvaluation* e : asked_) {
    if (e->failed) continue;
    double d = 0;
    for (size_t k = 0; k < x.size(); ++k) {
      const double u = (x[k] - e->x[k]) / (spec_.variables[k].max - spec_.variables[k].min);
      d += u * u;
    }
    if (d < best) best = d, nearest = e;  // the first asked among equals
  }
  return nearest;
}

void DesignEvaluator::Score(DesignEvaluation* e, const std::vector<SweepJobState>& states) const {
  e->metrics.assign(spec_.metrics.size(), std::numeric_limits<double>::quiet_NaN());
  e->seconds = 0;
  for (const SweepJobState& s : states) {
    e->seconds += s.seconds;
    if (s.failed && !e->failed) {
      e->failed = true;
      e->error = s.error;
    }
  }
  if (e->failed) return;
  for (size_t m = 0; m < spec_.metrics.size(); ++m) {
    double sum = 0;
    for (const SweepJobState& s : states) {
      const std::optional<double> v = MetricValue(spec_.metrics[m], s.results);
      if (!v || !std::isfinite(*v)) {
        e->failed = true;
        e->error = "its run gave no finite " + spec_.metrics[m].column();
        return;
      }
      sum += *v;
    }
    e->metrics[m] = sum / static_cast<double>(states.size());
  }
  e->loss = 0;
  for (const DesignTerm& t : spec_.objective) {
    const DesignMetric& m = spec_.metrics[t.metric];
    e->loss += t.weight * (m.higher_is_better ? -e->metrics[t.metric] : e->metrics[t.metric]);
  }
}

double DesignEvaluator::FailedLoss() const {
  double worst = -std::numeric_limits<double>::infinity(), best = std::numeric_limits<double>::infinity();
  for (const DesignEvaluation* e : asked_)
    if (!e->failed) {
      worst = std::max(worst, e->loss);
      best = std::min(best, e->loss);
    }
  if (!std::isfinite(worst)) return 1e3;
  return worst + 1 + (worst - best);
}

size_t DesignEvaluator::Resume() {
  if (!asked_.empty()) throw Error("internal error: DesignEvaluator::Resume after an evaluation");
  const fs::path path = log_;
  std::string text;
  {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream all;
    all << in.rdbuf();
    text = all.str();
  }
  // A run killed while appending leaves a line without its end: cut it, so that the next line
  // appended starts a line of its own.
  if (const size_t end = text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1; end < text.size()) {
    text.resize(end);
    std::error_code ec;
    fs::resize_file(path, end, ec);
    if (ec) throw Error(path.string() + ": cannot cut the unfinished last line: " + ec.message());
  }
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    nlohmann::json entry;
    try {
      entry = nlohmann::json::parse(line);
    } catch (const nlohmann::json::exception&) {
      continue;  // edited by hand: its design runs again when asked
    }
    if (!entry.is_object() || !entry.contains("index") || !entry["index"].is_number_unsigned() ||
        !entry.contains("x") || !entry["x"].is_array() || entry["x"].size() != spec_.variables.size())
      continue;
    DesignEvaluation e;
    e.index = entry["index"].get<size_t>();
    e.id = IdOf(e.index);
    e.start = start_;
    if (entry.contains("warm_start") && entry["warm_start"].is_string()) e.warm_start = entry["warm_start"];
    bool numbers = true;
    for (const auto& v : entry["x"]) numbers = numbers && v.is_number();
    if (!numbers) continue;
    for (const auto& v : entry["x"]) e.x.push_back(v.get<double>());
    next_index_ = std::max(next_index_, e.index + 1);
    logged_index_[e.x] = e.index;
    std::vector<SweepJobState> states;
    bool finished = true;
    for (const SweepJob& job : JobsOf(e)) {
      states.push_back(ReadJobState(out_, job));
      finished = finished && (states.back().complete || states.back().failed);
    }
    if (!finished) continue;  // its jobs were removed or are for another scene: run again, as this index, when asked
    Score(&e, states);
    e.from_log = true;
    done_[e.x] = e;
  }
  return done_.size();
}

void DesignEvaluator::AppendLog(const DesignEvaluation& e) const {
  const std::string& path = log_;
  std::error_code ec;
  fs::create_directories(fs::path(path).parent_path(), ec);
  if (ec) throw Error(fs::path(path).parent_path().string() + ": cannot create the folder: " + ec.message());
  std::ofstream log(path, std::ios::app);
  log << nlohmann::json{{"index", e.index}, {"id", e.id}, {"x", e.x}, {"warm_start", e.warm_start}}.dump() << "\n";
  log.flush();
  if (!log) throw Error(path + ": cannot append to the evaluation log");
}

const DesignEvaluation& DesignEvaluator::Evaluate(const std::vector<double>& x) {
  if (auto it = done_.find(x); it != done_.end()) {
    if (std::find(asked_.begin(), asked_.end(), &it->second) == asked_.end()) {
      asked_.push_back(&it->second);
      if (it->second.from_log) ++replayed_;
    }
    return it->second;
  }
  DesignEvaluation e;
  const auto logged = logged_index_.find(x);
  e.index = logged != logged_index_.end() ? logged->second : next_index_++;
  e.id = IdOf(e.index);
  e.start = start_;
  e.x = x;
  // The nearest design asked so far starts this one's solves: in a resumed run the same one as in
  // an uninterrupted run, since both have asked the same designs before this one.
  const DesignEvaluation* warm = spec_.warm_start && spec_.work_solve ? Nearest(x) : nullptr;
  std::vector<SweepJob> warm_jobs;
  if (warm) warm_jobs = JobsOf(*warm);
  std::vector<SweepJobState> states;
  bool solved = false;
  {
    // The runs' own lines are --verbose's; the evaluation's line below is the progress.
    const Verbosity was = CurrentVerbosity();
    if (was == Verbosity::kNormal) SetVerbosity(Verbosity::kQuiet);
    struct Restore {
      Verbosity v;
      ~Restore() { SetVerbosity(v); }
    } restore{was};
    const std::vector<SweepJob> jobs = JobsOf(e);
    for (size_t t = 0; t < jobs.size(); ++t) {
      const std::string from = warm ? (fs::path(JobFolder(out_, warm_jobs[t])) / "out" / "solve").string() : "";
      bool ran = false;
      SweepJobState s = RunSweepJob(sweeps_.front(), jobs[t], out_, "local", &ran, from);
      if (s.busy) throw Error("optimize: evaluation " + e.id + ": " + s.error);
      if (s.warm_started) e.warm_start = warm->id;
      solved = solved || ran;
      states.push_back(std::move(s));
    }
  }
  Score(&e, states);
  if (solved) ++ran_;  // else its jobs were finished by a run killed before it logged them
  AppendLog(e);
  std::string line = "optimize: evaluation " + e.id + ":";
  for (size_t k = 0; k < spec_.variables.size(); ++k)
    line += (k ? ", " : " ") + spec_.variables[k].name + " " + FormatGeneral(x[k]) +
            (spec_.variables[k].unit.empty() ? "" : " " + spec_.variables[k].unit);
  if (!e.warm_start.empty()) line += " (from " + e.warm_start + ")";
  if (e.failed) {
    line += ": failed: " + e.error;
  } else {
    for (size_t m = 0; m < spec_.metrics.size(); ++m)
      line +=
          (m ? ", " : " -> ") + spec_.metrics[m].name + " " + FormatGeneral(e.metrics[m]) + " " + spec_.metrics[m].unit;
  }
  Note(line + " (" + FormatFixed(e.seconds, 1) + " s)");
  DesignEvaluation& stored = done_[x] = std::move(e);
  asked_.push_back(&stored);
  return stored;
}

std::vector<const DesignEvaluation*> DesignEvaluator::evaluations() const {
  std::vector<const DesignEvaluation*> list;
  for (const auto& [x, e] : done_) list.push_back(&e);
  std::sort(list.begin(), list.end(), [](const auto* a, const auto* b) { return a->index < b->index; });
  return list;
}

}  // namespace layerlab
