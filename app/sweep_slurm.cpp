// `layerlab sweep --slurm` and `layerlab optimize --slurm`: the scripts of a
// Slurm job array. The array task id selects the job (`--job
// $SLURM_ARRAY_TASK_ID`) or the start (`--start ...`), so a task that is
// requeued or run again finds its job complete and skips it; the gather step
// runs after the whole array (afterany: also when some tasks failed).
//
// No text of the user's is ever run as a command. In the scripts' bodies the
// paths are single-quoted for the shell. The `#SBATCH` lines are parsed by
// sbatch itself (a line each, double quotes group, a backslash escapes, an
// unquoted `#` ends the line, "hetjob" anywhere starts another job): there
// the job name is of a safe character set, the resources of Slurm's forms
// (analysis/slurm_resources.h), and the log path is double-quoted with `"`
// escaped and `%` doubled. What cannot be carried is refused, naming where it
// came from: a control character (a newline) in a path, a backslash or
// "hetjob" in the output folder. The comments hold no text of the user's.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "layerlab/app/sweep_runners.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"

namespace layerlab::app {
namespace {

namespace fs = std::filesystem;

// For the shell: '...' with each ' as '\''.
std::string ShellQuoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// For an #SBATCH line: "..." with each " escaped.
std::string SbatchQuoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\\\"") : std::string(1, c);
  return q + "\"";
}

// A folder in a Slurm file name pattern, where `%` starts a field and `%%` is a `%`.
std::string PatternLiteral(const std::string& s) {
  std::string p;
  for (char c : s) p += c == '%' ? std::string("%%") : std::string(1, c);
  return p;
}

// JSON-quoted for a message: a newline shows as \n.
std::string Shown(const std::string& text) {
  return nlohmann::json(text).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// A path for a script's body: single quotes carry anything but a control
// character, which would split the line (a newline) or make sbatch refuse
// the script (a carriage return before a newline).
void CheckScriptPath(const std::string& path, const std::string& field) {
  for (unsigned char c : path)
    if (c < 0x20 || c == 0x7f)
      throw Error(field + ": " + Shown(path) +
                  " holds a control character (a newline, a tab, a carriage return), which a Slurm script cannot "
                  "carry; rename it");
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

SlurmArrayCommand SweepArrayCommand(const SweepSpec& spec) {
  SlurmArrayCommand c;
  c.command = "sweep";
  c.file = spec.file;
  c.file_what = "SWEEP (the sweep file's path)";
  c.kind = "sweep";
  c.name = spec.name;
  c.name_at = Location{spec.file, "/name"};
  if (!spec.named) c.name_note = " (without \"name\", the name is the sweep file's stem: give one)";
  c.threads = spec.threads;
  c.task_flag = "--job";
  c.task = "job of the sweep";
  c.tasks = "jobs";
  c.gathered = "the table and plots from every job's record";
  c.empty = Location{spec.file, "/parameters"};
  return c;
}

SlurmScripts MakeSlurmScripts(const SlurmArrayCommand& c, size_t job_count, const std::string& out,
                              const SlurmResources& resources) {
  if (job_count == 0) throw Error(c.empty, "the " + c.kind + " has no " + c.tasks + ": nothing to submit");
  if (const std::string problem = SlurmJobNameProblem(c.name); !problem.empty())
    throw Error(c.name_at, Shown(c.name) + " " + problem + c.name_note);
  for (const auto& [key, value] :
       {std::pair{"time", &resources.time}, std::pair{"mem", &resources.mem},
        std::pair{"partition", &resources.partition}, std::pair{"account", &resources.account}})
    if (!value->empty())
      if (const std::string problem = SlurmValueProblem(key, *value); !problem.empty())
        throw Error(std::string("slurm ") + key + ": " + problem);
  const std::string exe = SelfExecutable(), file = Absolute(c.file), to = Absolute(out);
  CheckScriptPath(exe, "the layerlab executable's path");
  CheckScriptPath(file, c.file_what);
  CheckScriptPath(to, "--out");
  const fs::path dir = fs::path(to) / "slurm";
  const std::string logs = (dir / "logs").string();
  if (logs.find('\\') != std::string::npos)
    throw Error("--out: " + Shown(to) +
                " holds a backslash, which turns off the %a in Slurm's log file names (#SBATCH --output); rename it");
  if (SbatchSeesHetJob(logs))
    throw Error("--out: " + Shown(to) +
                " holds \"hetjob\" or \"packjob\", which sbatch reads in an #SBATCH line as the start of another job; "
                "rename it");

  const int cpus = resources.cpus_per_task > 0 ? resources.cpus_per_task : c.threads > 0 ? c.threads : 1;
  std::string asked;  // what both scripts ask; the array's tasks also their CPUs
  if (!resources.time.empty()) asked += "#SBATCH --time=" + resources.time + "\n";
  if (!resources.mem.empty()) asked += "#SBATCH --mem=" + resources.mem + "\n";
  if (!resources.partition.empty()) asked += "#SBATCH --partition=" + resources.partition + "\n";
  if (!resources.account.empty()) asked += "#SBATCH --account=" + resources.account + "\n";
  std::string run =
      "exec " + ShellQuoted(exe) + " " + c.command + " " + ShellQuoted(file) + " --out " + ShellQuoted(to);
  for (const std::string& a : c.arguments) run += " " + ShellQuoted(a);
  const std::string last = std::to_string(job_count - 1);

  SlurmScripts s;
  s.folder = dir.string();
  s.logs = logs;
  s.array = (dir / "array.sbatch").string();
  s.gather = (dir / "gather.sbatch").string();
  s.submit = (dir / "submit.sh").string();
  s.array_text = "#!/bin/bash\n#SBATCH --job-name=" + SbatchQuoted(c.name) + "\n#SBATCH --array=0-" + last +
                 "\n#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=" + std::to_string(cpus) + "\n" + asked +
                 "#SBATCH --output=" + SbatchQuoted(PatternLiteral(logs) + "/job-%a.out") +
                 "\n"
                 "# One task per " +
                 c.task + " (" + std::to_string(job_count) + " " + c.tasks + "), written by layerlab " + c.command +
                 " --slurm and submitted by submit.sh.\n"
                 "# To run one task here: set SLURM_ARRAY_TASK_ID (0 to " +
                 last +
                 ") and run this script.\n"
                 "set -euo pipefail\n"
                 ": \"${SLURM_ARRAY_TASK_ID:?runs as a task of the Slurm array (sbatch), or with "
                 "SLURM_ARRAY_TASK_ID set}\"\n" +
                 run + " " + c.task_flag + " \"$SLURM_ARRAY_TASK_ID\"\n";
  s.gather_text = "#!/bin/bash\n#SBATCH --job-name=" + SbatchQuoted(c.name + "-gather") + "\n#SBATCH --ntasks=1\n" +
                  asked + "#SBATCH --output=" + SbatchQuoted(PatternLiteral(logs) + "/gather.out") +
                  "\n"
                  "# The gather step of the " +
                  c.kind + ": " + c.gathered +
                  ".\n"
                  "set -euo pipefail\n" +
                  run + " --gather\n";
  s.submit_text =
      "#!/bin/sh\n"
      "# Submits the array and, once every task has ended, the gather step.\n"
      "set -eu\n"
      "array=$(sbatch --parsable " +
      ShellQuoted(s.array) +
      ")\n"
      "sbatch --dependency=afterany:\"${array%%;*}\" " +
      ShellQuoted(s.gather) + "\n";
  return s;
}

std::vector<CLI::Option*> AddSlurmResourceFlags(CLI::App* cmd, CLI::Option* slurm, SlurmResources* r,
                                                const std::string& cpus) {
  const std::vector<CLI::Option*> flags = {
      cmd->add_option("--slurm-time", r->time,
                      "With --slurm: each task's wall time (minutes, hours:minutes:seconds, days-hours, ...)"),
      cmd->add_option("--slurm-mem", r->mem,
                      "With --slurm: each task's memory (an integer, unit K, M (default), G or T: 4G)"),
      cmd->add_option("--slurm-partition", r->partition, "With --slurm: the partition(s)"),
      cmd->add_option("--slurm-account", r->account, "With --slurm: the account charged"),
      cmd->add_option("--slurm-cpus-per-task", r->cpus_per_task,
                      "With --slurm: each task's CPUs (default: " + cpus + ")")
          ->check(CLI::Range(1, kMaxSlurmCpusPerTask))};
  for (CLI::Option* f : flags) f->needs(slurm);
  return flags;
}

void CheckSlurmFlags(const std::vector<CLI::Option*>& flags) {
  for (const CLI::Option* f : flags)
    if (f->count() && f->as<std::string>().empty()) throw Error(f->get_name() + ": is empty");
}

std::vector<std::string> WriteSlurmScripts(const SlurmScripts& s) {
  std::error_code ec;
  fs::create_directories(s.logs, ec);  // sbatch does not create the folder of --output
  if (ec) throw Error(s.logs + ": cannot create the folder: " + ec.message());
  WriteScript(s.array, s.array_text);
  WriteScript(s.gather, s.gather_text);
  WriteScript(s.submit, s.submit_text);
  return {s.array, s.gather, s.submit};
}

}  // namespace layerlab::app
