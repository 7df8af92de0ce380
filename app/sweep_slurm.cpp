// `layerlab sweep --slurm`: the scripts of a Slurm job array. The array task
// id selects the job (`--job $SLURM_ARRAY_TASK_ID`), so a task that is
// requeued or run again finds its job complete and skips it; the gather step
// runs after the whole array (afterany: also when some tasks failed).
#include <filesystem>
#include <string>

#include "app/sweep_runners.h"
#include "framework/atomic_file.h"
#include "framework/error.h"

namespace layerlab::app {
namespace {

namespace fs = std::filesystem;

std::string Quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string Absolute(const std::string& path) { return fs::absolute(path).lexically_normal().string(); }

void WriteScript(const std::string& path, const std::string& text) {
  WriteFileAtomically(path, text);
  std::error_code ec;
  fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec, fs::perm_options::add,
                  ec);
  if (ec) throw Error(path + ": cannot make it executable: " + ec.message());
}

}  // namespace

std::vector<std::string> WriteSlurmScripts(const SweepSpec& spec, const std::vector<SweepJob>& jobs,
                                           const std::string& out) {
  const fs::path dir = fs::path(Absolute(out)) / "slurm";
  std::error_code ec;
  fs::create_directories(dir / "logs", ec);  // sbatch does not create the folder of --output
  if (ec) throw Error((dir / "logs").string() + ": cannot create the folder: " + ec.message());
  const std::string exe = Quoted(SelfExecutable()), sweep = Quoted(Absolute(spec.file)), to = Quoted(Absolute(out));
  const std::string name = spec.name.empty() ? "layerlab-sweep" : spec.name;
  const int cpus = spec.threads > 0 ? spec.threads : 1;

  const std::string array = (dir / "array.sbatch").string();
  WriteScript(array,
              "#!/bin/bash\n"
              "# One task per job of the sweep " +
                  spec.file + " (" + std::to_string(jobs.size()) +
                  " jobs); written by layerlab sweep --slurm.\n"
                  "# Submit with submit.sh; to run one task here: SLURM_ARRAY_TASK_ID=3 " +
                  array +
                  "\n"
                  "#SBATCH --job-name=" +
                  name +
                  "\n"
                  "#SBATCH --array=0-" +
                  std::to_string(jobs.size() - 1) +
                  "\n"
                  "#SBATCH --ntasks=1\n"
                  "#SBATCH --cpus-per-task=" +
                  std::to_string(cpus) +
                  "\n"
                  "#SBATCH --output=" +
                  (dir / "logs").string() +
                  "/job-%a.out\n"
                  "set -euo pipefail\n"
                  ": \"${SLURM_ARRAY_TASK_ID:?runs as a task of the Slurm array (sbatch), or with "
                  "SLURM_ARRAY_TASK_ID set}\"\n"
                  "exec " +
                  exe + " sweep " + sweep + " --out " + to + " --job \"$SLURM_ARRAY_TASK_ID\"\n");
  const std::string gather = (dir / "gather.sbatch").string();
  WriteScript(gather,
              "#!/bin/bash\n"
              "# The gather step of the sweep " +
                  spec.file +
                  ": the table and plots from every job's record.\n"
                  "#SBATCH --job-name=" +
                  name +
                  "-gather\n"
                  "#SBATCH --ntasks=1\n"
                  "#SBATCH --output=" +
                  (dir / "logs").string() +
                  "/gather.out\n"
                  "set -euo pipefail\n"
                  "exec " +
                  exe + " sweep " + sweep + " --out " + to + " --gather\n");
  const std::string submit = (dir / "submit.sh").string();
  WriteScript(submit,
              "#!/bin/sh\n"
              "# Submits the array and, once every task has ended, the gather step.\n"
              "set -eu\n"
              "array=$(sbatch --parsable " +
                  Quoted(array) +
                  ")\n"
                  "sbatch --dependency=afterany:\"${array%%;*}\" " +
                  Quoted(gather) + "\n");
  return {array, gather, submit};
}

}  // namespace layerlab::app
