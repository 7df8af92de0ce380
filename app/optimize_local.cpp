// `layerlab optimize --local -j N`: a multistart's starts as child processes.
#include <sys/wait.h>

#include <cctype>
#include <csignal>
#include <filesystem>

#include "layerlab/app/optimize_runners.h"
#include "layerlab/design/design_starts.h"
#include "layerlab/framework/interrupt.h"
#include "layerlab/framework/progress.h"

namespace layerlab::app {

std::vector<std::string> RunStartsLocally(const DesignSpec& spec, const std::string& out,
                                          const std::vector<std::string>& arguments, int processes) {
  InstallInterruptHandler();
  const std::string exe = SelfExecutable();
  std::vector<std::vector<std::string>> commands;
  for (int k = 0; k < spec.optimizer.starts; ++k) {
    std::vector<std::string> c = {exe, "optimize", spec.file, "--out", out, "--start", std::to_string(k), "--quiet"};
    c.insert(c.end(), arguments.begin(), arguments.end());
    commands.push_back(std::move(c));
  }
  std::vector<std::string> failed;
  RunProcessPool(commands, processes, [&](size_t k, int status) {
    const std::string id = StartId(static_cast<int>(k));
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      Note("optimize: start " + id + " ended");
    } else if (Interrupted() && EndedByInterrupt(status)) {
      Note("optimize: start " + id + " interrupted; it resumes on the next run");
    } else {
      const std::string why = WIFSIGNALED(status) ? "was killed by signal " + std::to_string(WTERMSIG(status))
                                                  : "exited with status " + std::to_string(WEXITSTATUS(status));
      Note("optimize: start " + id + " " + why);
      failed.push_back(id + " " + why);
    }
  });
  if (Interrupted())
    throw InterruptedError(
        "optimize: interrupted; the finished evaluations are kept, run the same command again to resume");
  return failed;
}

SlurmArrayCommand OptimizeArrayCommand(const DesignSpec& spec, const std::vector<std::string>& arguments) {
  SlurmArrayCommand c;
  c.command = "optimize";
  c.file = spec.file;
  c.file_what = "DESIGN (the design file's path)";
  c.kind = "design";
  // The design's name is a title (spaces, colons): the job is named from the file's stem, made safe.
  c.name_at = Location{spec.file, ""};
  c.name_note = " (the job is named from the design file's stem: rename the file)";
  c.name = "optimize-";
  for (char ch : std::filesystem::path(spec.file).stem().string())
    if (c.name.size() < 120)
      c.name += std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '-' ? ch : '_';
  c.threads = spec.threads;
  c.arguments = arguments;
  c.task_flag = "--start";
  c.task = "start of the multistart";
  c.tasks = "starts";
  c.gathered = "the best design, the history and the report from every start's log";
  c.empty = Location{spec.file, "/optimizer/starts"};
  return c;
}

}  // namespace layerlab::app
