#include "layerlab/analysis/sweep_jobs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "layerlab/analysis/run_pipeline.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/content_digest.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/interrupt.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/systems/scene_document.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string Digest(const std::string& text) { return ContentDigest().add(text).hex(); }

std::string JobStatePath(const std::string& out, const SweepJob& job) {
  return (fs::path(JobFolder(out, job)) / "job.json").string();
}

std::string Number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// The job's row of the table, from what the pipeline returned.
std::vector<SweepResult> Results(const RunOutcome& outcome) {
  std::vector<SweepResult> r;
  auto add = [&](std::string column, nlohmann::json value, std::optional<double> ideal = std::nullopt) {
    SweepResult& result = r.emplace_back();
    result.column = std::move(column);
    result.value = std::move(value);
    result.ideal = ideal;
  };
  if (outcome.solved) {
    add(kPsnrColumn, outcome.report.final_psnr_db);
    add(kSolveTimeColumn, outcome.report.seconds);
    add("iterations", outcome.report.iterations);
  }
  for (const RetinaStateResult& s : outcome.retina)
    add(kRetinalMeanColumn + Number(s.diopters) + " D (cd/m2)", s.display_mean_cd_m2);
  // Each metric of run.retina.metrics against natural viewing, the mean over the states (the focal stack's).
  for (const MeanScore& s : MeanScoresOverStates(outcome.retina))
    add(FocalStackColumn(s.metric->name, s.metric->unit), s.mean);
  std::string own;  // the swept display's curves, not natural viewing's or a listed scene's
  for (const ContrastCurve& c : outcome.contrast) {
    if (c.display == "natural") continue;
    if (own.empty()) own = c.display;
    if (c.display != own) continue;
    const std::string at = Number(c.target_diopters) + " D, " + Number(c.frequency) + " cpd";
    add(kPeakContrastColumn + at + " (1)", c.peak.value);
    add(kPeakAccommodationColumn + at + " (D)", c.peak.at_parabola, c.target_diopters);
  }
  return r;
}

void WriteState(const std::string& path, const SweepJob& job, const std::string& state, const std::string& error,
                const std::string& runner, double seconds, const std::vector<std::string>& outputs,
                const std::vector<SweepResult>& results) {
  ordered_json doc = {{"format", kSweepJobFormat}, {"id", job.id}, {"state", state}};
  if (!error.empty()) doc["error"] = error;
  doc["scene_digest"] = Digest(job.scene_text);
  doc["runner"] = runner;
  doc["seconds"] = seconds;
  doc["outputs"] = outputs;
  ordered_json rows = ordered_json::array();
  for (const SweepResult& r : results) {
    rows.push_back({{"column", r.column}, {"value", r.value}});
    if (r.ideal) rows.back()["ideal"] = *r.ideal;
  }
  doc["results"] = rows;
  WriteFileAtomically(path, doc.dump(2) + "\n");
}

void WriteSceneIfChanged(const std::string& out, const SweepJob& job, size_t* written) {
  const fs::path folder = JobFolder(out, job);
  const std::string scene = (folder / "scene.json").string();
  if (ReadText(scene) == job.scene_text) return;
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw Error(folder.string() + ": cannot create the job folder: " + ec.message());
  fs::remove(folder / "job.json", ec);  // its entry was for another scene
  WriteFileAtomically(scene, job.scene_text);
  if (written) ++*written;
}

}  // namespace

std::string FocalStackColumn(const std::string& metric, const std::string& unit) {
  return "focal-stack " + metric + ", mean over the retinal states (" + (unit.empty() ? "1" : unit) + ")";
}

std::string JobFolder(const std::string& out, const SweepJob& job) {
  return (fs::path(out) / "jobs" / job.id).string();
}

namespace {

// The base scene with only the declared work in its run section, with the base scene's settings for it.
ordered_json BaseForWork(const SweepSpec& spec) {
  ordered_json base = spec.base;
  ordered_json run = ordered_json::object();
  for (const char* step : {"retina", "contrast"}) {
    if ((std::string(step) == "retina" && !spec.retina) || (std::string(step) == "contrast" && !spec.contrast))
      continue;
    const bool given = base.contains("run") && base["run"].is_object() && base["run"].contains(step);
    run[step] = given ? base["run"][step] : ordered_json::object();
  }
  if (run.empty())
    base.erase("run");
  else
    base["run"] = run;
  if (!spec.solve && base.contains("solve")) {
    base["solve"].erase("target");
    base["solve"].erase("target_scene");
  }
  return base;
}

SweepJob MakeJob(const SweepSpec& spec, const ordered_json& base, const std::string& out, std::string id,
                 const std::vector<SceneValue>& values, const std::string& description) {
  SweepJob job;
  job.id = std::move(id);
  job.scene = base;
  for (const SceneValue& v : values) {
    const ordered_json::json_pointer at(v.pointer);
    if (!job.scene.contains(at))
      throw Error(v.where, "\"" + v.pointer + "\" is in a part of the scene the work does not run");
    job.scene[at] = v.value;
  }
  job.scene["description"] = description;
  RebaseRelativePaths(job.scene, spec.scene, (fs::path(JobFolder(out, job)) / "scene.json").string());
  job.scene_text = job.scene.dump(2) + "\n";
  return job;
}

}  // namespace

SweepJob MakeSweepJob(const SweepSpec& spec, const std::string& out, std::string id,
                      const std::vector<SceneValue>& values, const std::string& description) {
  return MakeJob(spec, BaseForWork(spec), out, std::move(id), values, description);
}

std::vector<SweepJob> ExpandSweep(const SweepSpec& spec, const std::string& out) {
  const size_t n = spec.job_count();
  if (n == 0 || n > kMaxSweepPoints)
    throw Error(Location{spec.file, "/parameters"},
                "the grid has " + std::to_string(n) + " points; a sweep has 1 to " + std::to_string(kMaxSweepPoints));
  const size_t digits = std::max<size_t>(3, std::to_string(n - 1).size());
  const ordered_json base = BaseForWork(spec);
  std::vector<SweepJob> jobs(n);
  for (size_t index = 0; index < n; ++index) {
    std::string id = std::to_string(index);
    id.insert(0, static_cast<size_t>(digits) - std::min<size_t>(id.size(), digits), '0');
    std::vector<size_t> choice(spec.parameters.size());
    size_t rest = index;
    for (size_t k = spec.parameters.size(); k-- > 0;) {
      choice[k] = rest % spec.parameters[k].values.size();
      rest /= spec.parameters[k].values.size();
    }
    std::vector<SceneValue> values;
    std::string labels;
    for (size_t k = 0; k < spec.parameters.size(); ++k) {
      const SweepParameter& p = spec.parameters[k];
      const ordered_json& value = p.values[choice[k]];
      for (size_t i = 0; i < p.pointers.size(); ++i)
        values.push_back({p.pointers[i], p.pointers.size() > 1 ? value[i] : value,
                          Location{spec.file, "/parameters/" + std::to_string(k)}});
      labels += (k ? ", " : "") + p.name + " = " + p.labels[choice[k]];
    }
    const std::string description =
        "Job " + id + " of the sweep " + spec.file + ": the scene " + spec.scene + " with " + labels;
    jobs[index] = MakeJob(spec, base, out, std::move(id), values, description);
    jobs[index].index = index;
    jobs[index].choice = std::move(choice);
  }
  return jobs;
}

namespace {

// What the jobs read: the sweep file, the base scene, the files and folders
// it names (its target light field, target scene, compared scenes) and the
// paths among the parameters' values.
std::vector<NamedInput> SweepInputs(const SweepSpec& spec) {
  std::vector<NamedInput> inputs = {{spec.file, "the sweep file"}, {spec.scene, "the base scene"}};
  const fs::path scene_folder = fs::absolute(spec.scene).parent_path();
  const std::vector<std::string> path_pointers = ScenePathPointers(spec.base);
  for (const std::string& pointer : path_pointers) {
    const fs::path path = spec.base[ordered_json::json_pointer(pointer)].get<std::string>();
    inputs.push_back({(scene_folder / path).lexically_normal().string(), "the base scene's " + pointer});
  }
  for (const SweepParameter& p : spec.parameters)
    for (size_t k = 0; k < p.pointers.size(); ++k) {
      if (std::find(path_pointers.begin(), path_pointers.end(), p.pointers[k]) == path_pointers.end()) continue;
      for (size_t i = 0; i < p.values.size(); ++i) {
        const ordered_json& v = p.pointers.size() > 1 ? p.values[i][k] : p.values[i];
        if (v.is_string())
          inputs.push_back({v.get<std::string>(), "the value \"" + p.labels[i] + "\" of the parameter " + p.name});
      }
    }
  return inputs;
}

void CreateSweepFolder(const SweepSpec& spec, const std::string& out) {
  RefuseOutputOverlappingInputs(out, SweepInputs(spec));
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw Error(out + ": cannot create the output folder: " + ec.message());
}

}  // namespace

FileLock LockSweepFolder(const SweepSpec& spec, const std::string& out) {
  CreateSweepFolder(spec, out);
  std::string holder;
  std::optional<FileLock> lock = FileLock::TryLock((fs::path(out) / "sweep.lock").string(), &holder);
  if (!lock)
    throw Error(out + ": another layerlab sweep" + (holder.empty() ? "" : " (" + holder + ")") +
                " is running into this folder; wait for it to end or give another --out");
  return std::move(*lock);
}

size_t WriteSweepFolders(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out) {
  CreateSweepFolder(spec, out);
  size_t written = 0;
  for (const SweepJob& job : jobs) WriteSceneIfChanged(out, job, &written);
  ordered_json params = ordered_json::array();
  for (const SweepParameter& p : spec.parameters)
    params.push_back({{"name", p.name}, {"column", p.column()}, {"pointers", p.pointers}, {"labels", p.labels}});
  ordered_json list = ordered_json::array();
  for (const SweepJob& job : jobs) {
    ordered_json values = ordered_json::object();
    for (size_t k = 0; k < spec.parameters.size(); ++k)
      values[spec.parameters[k].name] = spec.parameters[k].labels[job.choice[k]];
    list.push_back({{"id", job.id}, {"folder", "jobs/" + job.id}, {"values", values}});
  }
  const ordered_json manifest = {{"format", kSweepManifestFormat},
                                 {"sweep", fs::absolute(spec.file).lexically_normal().string()},
                                 {"scene", fs::absolute(spec.scene).lexically_normal().string()},
                                 {"work", spec.work()},
                                 {"parameters", params},
                                 {"jobs", list}};
  WriteFileAtomically((fs::path(out) / "manifest.json").string(), manifest.dump(2) + "\n");
  return written;
}

SweepJobState ReadJobState(const std::string& out, const SweepJob& job) {
  SweepJobState state;
  const std::string text = ReadText(JobStatePath(out, job));
  if (text.empty()) return state;
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    return state;  // written atomically, so only a hand edit gets here: run the job again
  }
  if (!doc.is_object() || doc.value("format", "") != kSweepJobFormat ||
      doc.value("scene_digest", "") != Digest(job.scene_text))
    return state;
  state.runner = doc.value("runner", "");
  state.seconds = doc.value("seconds", 0.0);
  if (doc.value("state", "") == "failed") {
    state.failed = true;
    state.error = doc.value("error", "");
    return state;
  }
  if (doc.value("state", "") != "complete") return state;
  for (const auto& file : doc.value("outputs", nlohmann::json::array()))
    if (!file.is_string() || !fs::exists(fs::path(JobFolder(out, job)) / "out" / file.get<std::string>())) return state;
  for (const auto& r : doc.value("results", nlohmann::json::array())) {
    SweepResult& result = state.results.emplace_back();
    result.column = r.value("column", "");
    result.value = r.value("value", nlohmann::json());
    if (r.contains("ideal") && r["ideal"].is_number()) result.ideal = r["ideal"].get<double>();
  }
  state.complete = true;
  return state;
}

SweepJobState RunSweepJob(const SweepSpec& spec, const SweepJob& job, const std::string& out, const std::string& runner,
                          bool* ran, const std::string& warm_start) {
  if (ran) *ran = false;
  const fs::path folder = JobFolder(out, job);
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw Error(folder.string() + ": cannot create the job folder: " + ec.message());
  std::string holder;
  const std::optional<FileLock> lock = FileLock::TryLock((folder / "job.lock").string(), &holder);
  if (!lock) {
    SweepJobState busy;
    busy.busy = true;
    busy.error = "running in another process" + (holder.empty() ? "" : " (" + holder + ")") + "; left to it";
    return busy;
  }
  WriteSceneIfChanged(out, job, nullptr);
  SweepJobState state = ReadJobState(out, job);
  if (state.complete) return state;
  if (ran) *ran = true;
  RunRequest request;
  request.scene = (folder / "scene.json").string();
  request.out = (folder / "out").string();
  request.iterations = spec.iterations;
  request.threads = spec.threads;
  request.shared_renders = (fs::path(out) / "targets").string();
  request.warm_start = warm_start;
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  state = SweepJobState{};
  state.runner = runner;
  try {
    const RunOutcome outcome = RunPipeline(request);
    state.results = Results(outcome);
    state.warm_started = outcome.warm_started;
    state.seconds = seconds();
    WriteState(JobStatePath(out, job), job, "complete", "", runner, state.seconds, outcome.written, state.results);
    state.complete = true;
  } catch (const InterruptedError&) {
    throw;  // Ctrl-C stops the sweep; the job is not marked failed and runs again on resume
  } catch (const std::exception& e) {
    state.failed = true;
    state.error = e.what();
    state.seconds = seconds();
    WriteState(JobStatePath(out, job), job, "failed", state.error, runner, state.seconds, {}, {});
  }
  return state;
}

const SweepJob& FindSweepJob(const std::vector<SweepJob>& jobs, const std::string& id) {
  char* end = nullptr;
  const unsigned long long n = std::strtoull(id.c_str(), &end, 10);
  if (jobs.empty()) throw Error("--job " + id + ": the sweep has no jobs");
  if (id.empty() || *end != '\0' || n >= jobs.size())
    throw Error("--job " + id + ": the sweep has jobs 0 to " + std::to_string(jobs.size() - 1));
  return jobs[n];
}

}  // namespace layerlab
