// The inputs of `layerlab run`, read and checked before anything runs; every
// scene file (the scene, the compared and contrast scenes, the target scene)
// is read once.
#include <filesystem>
#include <list>
#include <map>

#include "layerlab/analysis/frame_sequence.h"
#include "layerlab/analysis/run_steps.h"
#include "layerlab/framework/error.h"
#include "layerlab/solvers/solver_option_table.h"
#include "layerlab/systems/compile.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

// The scene files of a run, each read once however many lists name it.
class SceneFiles {
 public:
  explicit SceneFiles(const std::string& file, const Scene& scene) { read_[Key(file)] = &scene; }
  const Scene& Read(const std::string& file) {
    const Scene*& scene = read_[Key(file)];
    if (!scene) scene = &owned_.emplace_back(LoadScene(file));
    return *scene;
  }

 private:
  static std::string Key(const std::string& file) { return fs::absolute(file).lexically_normal().string(); }
  std::map<std::string, const Scene*> read_;
  std::list<Scene> owned_;  // stable addresses
};

// What needs a target, refused without one; and a run with nothing to do.
void RequireWork(const RunInputs& in, const std::string& file) {
  if (in.has_target()) return;
  const Location run_at{file, "/run"};
  if (in.run.retina.enabled)
    throw Error(
        run_at.child("retina"),
        "retinal images need a target to factorize: give \"solve\": {\"target\": ...} or {\"target_scene\": ...}");
  if (in.run.compare.enabled)
    throw Error(run_at.child("compare"),
                "a comparison needs a target: give \"solve\": {\"target\": ...} or {\"target_scene\": ...}");
  if (in.run.frames.enabled)
    throw Error(run_at.child("frames"),
                "a frame sequence needs a target scene that moves: give \"solve\": "
                "{\"target_scene\": ...}");
  if (!in.run.contrast.enabled)
    throw Error(file +
                ": nothing to run: give a target in the \"solve\" section or analyses in a \"run\" section "
                "(docs/run-section.md)");
}

// The displays compared with this one, each compiled with its "solve" section.
void ReadCompared(SceneFiles& files, RunInputs* in) {
  for (const std::string& file : in->run.compare.scenes) {
    const Scene& other = files.Read(file);
    OtherDisplay d{fs::path(file).stem().string(), Compile(other), {}};
    d.config = ReadSolveConfig(other, d.system);
    // Without a "solve" section of its own, a display runs as this one does, so that the runs compare.
    if (!other.document.contains("solve") && d.config.solver == in->solve.solver) {
      d.config.options = in->solve.options;
      d.config.sampling = in->solve.sampling;
      d.own_options = false;
    }
    in->compare.push_back(std::move(d));
  }
}

// The target's geometry for the memory estimate; a target scene read here is
// rendered from later (its light field's "display" among the run's scene files).
void ReadTargetGeometry(SceneFiles& files, RunInputs* in) {
#if LAYERLAB_WITH_EMBREE
  if (in->solve.target.empty() && !in->solve.target_scene.empty()) {
    const SceneReader read_scene = [&files](const std::string& path) -> const Scene& { return files.Read(path); };
    in->target_scene = std::make_unique<TargetScene>(LoadTarget(in->solve.target_scene, read_scene));
    in->target_geometry = in->target_scene->geometry;
    return;
  }
#endif
  in->target_geometry = TargetGeometry(in->solve);
}

// run.frames: a target scene that moves and the light-field objective, checked before anything runs.
void RequireFrames(const RunInputs& in, const std::string& file) {
  if (!in.run.frames.enabled) return;
  const Location at{file, "/run/frames"};
  if (!in.solve.target.empty() || in.solve.target_scene.empty())
    throw Error(at,
                "a frame sequence needs a target scene that moves (\"solve\": {\"target_scene\": ...}); a "
                "light-field folder holds one frame");
#if LAYERLAB_WITH_EMBREE
  SolveJob job;
  job.system = &in.system;
  job.config = in.solve;
  try {
    RequireFrameSequence(job, *in.target_scene, in.run.frames.sequence());
  } catch (const Error& e) {
    throw Error(at, e.message());
  }
#else
  throw Error(at, "a frame sequence renders each frame's target, and this layerlab was built without Embree");
#endif
}

}  // namespace

RunInputs ReadRunInputs(const RunRequest& request) {
  const std::string& file = request.scene;
  RunInputs in;
  in.scene = LoadScene(file);
  in.name = fs::path(file).stem().string();
  SceneFiles files(file, in.scene);
  in.system = Compile(in.scene);
  in.solve = SolveJobConfig(in.scene, in.system);
  if (request.iterations)
    if (const std::string why = SolverOptionProblem("iterations", *request.iterations, "--iterations"); !why.empty())
      throw Error(why);
  in.solve.options.iterations = request.iterations.value_or(in.solve.options.iterations);
  in.solve.options.threads = request.threads.value_or(in.solve.options.threads);
  in.run = ReadRunConfig(in.scene, in.system);
  RequireWork(in, file);
  if (std::string why = UnsuitableSolver(in.solve.solver, in.system); !why.empty())
    throw Error(Location{file, "/solve/solver"}, "the solver " + in.solve.solver + " " + why);
  if (in.run.compare.enabled) ReadCompared(files, &in);
  if (in.run.contrast.enabled) {
    in.contrast.push_back({in.name, in.system, in.solve.solver, in.solve.options, true});
    for (const std::string& other : in.run.contrast.scenes)
      in.contrast.push_back(ContrastDisplayOf(files.Read(other), other));
    const std::string& foreign = in.run.contrast.factorized_for;
    if (!foreign.empty()) in.contrast_factorized_for = ContrastDisplayOf(files.Read(foreign), foreign);
    const ContrastDisplay* other = in.contrast_factorized_for ? &*in.contrast_factorized_for : nullptr;
    if (std::string why = ContrastDisplayProblem(in.contrast, in.run.contrast.options, other); !why.empty()) {
      const std::string key = why.substr(0, why.find(':'));  // "key: ...": refused at its key, before any solve
      throw Error(Location{file, "/run/contrast"}.child(key), why.substr(key.size() + 2));
    }
  }
  if (in.has_target()) ReadTargetGeometry(files, &in);
  RequireFrames(in, file);
  return in;
}

}  // namespace layerlab
