// The jobs of a sweep (analysis/sweep_spec.h): the grid expanded into job
// folders, each job run with the main job's pipeline (analysis/run_pipeline.h),
// and its state kept beside it so that a sweep resumes where it stopped.
//
//   DIR/manifest.json        the grid: every job's folder and parameter labels
//   DIR/jobs/<id>/scene.json the base scene with the job's values written in
//   DIR/jobs/<id>/out/       what `layerlab run` writes for that scene
//   DIR/jobs/<id>/job.json   the job's manifest entry: complete or failed (with
//                            the error), the scene's digest, its outputs, its results
//   DIR/sweep.lock           held by the runner that writes the job folders
//   DIR/jobs/<id>/job.lock   held by the process running that job
//   DIR/targets/<key>/       a target scene's render, shared by the jobs whose
//                            target is the same (analysis/target_cache.h)
//
// manifest.json: layerlab-sweep-manifest/1, written by the runner that expands the grid
//
// | key | type | default | meaning |
// | --- | --- | --- | --- |
// | format | string | required | `"layerlab-sweep-manifest/1"` |
// | sweep | path | required | the sweep file, absolute |
// | scene | path | required | the base scene, absolute |
// | work | array of strings | required | `"solve"`, `"retina"`, `"contrast"` as declared |
// | parameters | array of `{name, column, pointers, labels}` | required | each axis: its name, its table column (with the unit), the pointers it sets, a label per value |
// | jobs | array of `{id, folder, values}` | required | each job: its id, its folder relative to DIR, its parameter labels by name |
//
// job.json: layerlab-sweep-job/1
//
// | key | type | default | meaning |
// | --- | --- | --- | --- |
// | format | string | required | `"layerlab-sweep-job/1"` |
// | id | string | required | the job's folder name under `jobs/` |
// | state | `"complete"` or `"failed"` | required | |
// | error | string | none | why a failed job failed |
// | scene_digest | string | required | of the scene.json it ran; another digest marks the entry stale |
// | runner | string | required | `"local"`, `"mpi rank R of N"`, `"slurm task T"` |
// | seconds | number | required | wall time of the job (s) |
// | outputs | array of paths | required | what it wrote, relative to `out/`; all must exist for the job to count as complete |
// | results | array of `{column, value, ideal}` | required | the job's row of the table; `ideal` (where there is one) is what a perfect display gives, drawn in the plots as a reference |
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/analysis/sweep_spec.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/file_lock.h"

namespace layerlab {

inline constexpr const char* kSweepManifestFormat = "layerlab-sweep-manifest/1";
inline constexpr const char* kSweepJobFormat = "layerlab-sweep-job/1";

struct SweepJob {
  size_t index = 0;
  std::string id;                // "007": the folder under DIR/jobs
  std::vector<size_t> choice;    // the value index of each parameter
  nlohmann::ordered_json scene;  // the job's scene document, paths rebased to its folder
  std::string scene_text;        // as written to scene.json
};

// The columns of a job's row that other code reads back (design/design_metrics.h).
inline constexpr const char* kPsnrColumn = "PSNR (dB)";
inline constexpr const char* kSolveTimeColumn = "solve time (s)";
inline constexpr const char* kRetinalMeanColumn = "retinal mean at ";            // "<D> D (cd/m2)" follows
inline constexpr const char* kPeakContrastColumn = "peak contrast, ";            // "<D> D, <f> cpd (1)" follows
inline constexpr const char* kPeakAccommodationColumn = "peak accommodation, ";  // "<D> D, <f> cpd (D)" follows
// "focal-stack ssim, mean over the retinal states (1)"
std::string FocalStackColumn(const std::string& metric, const std::string& unit);

struct SweepResult {
  std::string column;  // with its unit: "PSNR (dB)"
  nlohmann::json value;
  std::optional<double> ideal;  // what a perfect display gives (a peak accommodation: the target's depth)
};

struct SweepJobState {
  bool complete = false, failed = false;  // neither: not run, or stale
  bool busy = false;                      // another process is running it (error says which)
  std::string error, runner;
  double seconds = 0;
  bool warm_started = false;  // in this process: its solve began from RunSweepJob's warm_start
  std::vector<SweepResult> results;
};

// A scene value a job writes at a JSON pointer; `where` names what asked for it, for the error
// when the pointer is in a part of the scene the work leaves out.
struct SceneValue {
  std::string pointer;
  nlohmann::ordered_json value;
  Location where;
};

// One job: the base scene with only the declared work in its run section,
// the values written in, its description, and its relative paths rebased to
// DIR/jobs/<id>/. What ExpandSweep makes for each point, and `optimize` for
// each design it evaluates (design/design_evaluator.h).
SweepJob MakeSweepJob(const SweepSpec& spec, const std::string& out, std::string id,
                      const std::vector<SceneValue>& values, const std::string& description);

// Every point of the grid, in order (the last parameter fastest), in memory.
std::vector<SweepJob> ExpandSweep(const SweepSpec& spec, const std::string& out);

std::string JobFolder(const std::string& out, const SweepJob& job);

// Locks DIR for one runner: a second sweep into the same folder is refused,
// naming the process that holds it. Creates DIR; refuses one that overlaps an input.
FileLock LockSweepFolder(const SweepSpec& spec, const std::string& out);

// Writes DIR/manifest.json and every job's scene.json that is missing or
// differs (removing that job's stale job.json); returns how many scenes were
// written. Refuses an output folder that overlaps an input.
size_t WriteSweepFolders(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out);

// The job's state as its job.json says; complete only while the scene it ran
// is the one in `job` and every output it listed is present.
SweepJobState ReadJobState(const std::string& out, const SweepJob& job);

// Runs one job unless it is complete (then returns its state): writes its
// scene if needed, runs the pipeline into jobs/<id>/out and records the
// outcome in job.json. A failure is recorded and returned, not thrown. A job
// that another process is running is left to it (busy, not run).
// `ran` (optional) says whether it ran. `warm_start`: RunRequest::warm_start
// (an earlier job's out/solve), and the state's `warm_started` says whether it took.
SweepJobState RunSweepJob(const SweepSpec& spec, const SweepJob& job, const std::string& out, const std::string& runner,
                          bool* ran = nullptr, const std::string& warm_start = "");

// The job with this id or index ("7", "007"); throws layerlab::Error listing the range.
const SweepJob& FindSweepJob(const std::vector<SweepJob>& jobs, const std::string& id);

}  // namespace layerlab
