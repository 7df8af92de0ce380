// What a sweep's Slurm scripts ask of Slurm (docs/sweeps.md): the resources
// `time`, `mem`, `partition`, `account` and `cpus-per-task`, from the sweep
// file's "slurm" object or the command line (`--slurm-time` ...), which wins.
// Every value that reaches an `#SBATCH` line is checked against the form
// sbatch takes, so that the line carries that one value: never a second
// directive, never a command.
//
// sweep.slurm: what each task of the job array asks of Slurm
//
// | key | type | default | meaning |
// | --- | --- | --- | --- |
// | time | string | the partition's | wall time of each task: `minutes`, `minutes:seconds`, `hours:minutes:seconds`, `days-hours`, `days-hours:minutes`, `days-hours:minutes:seconds` |
// | mem | string | the partition's | memory of each task: an integer with an optional unit `K`, `M` (the default), `G` or `T` |
// | partition | string | the cluster's | a partition name, or several separated by commas (letters, digits, `_`, `.`, `-`) |
// | account | string | the user's | the account charged (letters, digits, `_`, `.`, `-`) |
// | cpus-per-task | integer | `threads` (1 when 0) | CPUs of each task, 1 to 4096 |
#pragma once

#include <string>

#include "layerlab/framework/params.h"

namespace layerlab {

struct SlurmResources {
  std::string time, mem, partition, account;  // empty: not asked
  int cpus_per_task = 0;                      // 0: not asked
  // Those of `over` that are set replace these.
  void Override(const SlurmResources& over);
};

inline constexpr int kMaxSlurmCpusPerTask = 4096;

// Why `value` is not a Slurm value for `key` ("time", "mem", "partition",
// "account"), or "" when it is one.
std::string SlurmValueProblem(const std::string& key, const std::string& value);

// Why `name` cannot be a Slurm job name here (letters, digits, spaces and
// `_ . + -`, at most 200 characters), or "".
std::string SlurmJobNameProblem(const std::string& name);

// Whether sbatch would read an #SBATCH line holding `text` as the start of
// another job of a heterogeneous job: "hetjob" (or the older "packjob")
// anywhere in the line, in any case, even inside a quoted value.
bool SbatchSeesHetJob(const std::string& text);

// The "slurm" object of a sweep file; throws layerlab::Error naming the key.
SlurmResources ReadSlurmResources(Params& p);

}  // namespace layerlab
