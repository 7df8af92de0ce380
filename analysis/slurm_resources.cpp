#include "layerlab/analysis/slurm_resources.h"

#include <algorithm>
#include <cctype>
#include <regex>

#include <nlohmann/json.hpp>

namespace layerlab {

bool SbatchSeesHetJob(const std::string& line) {
  std::string text = line;
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text.find("hetjob") != std::string::npos || text.find("packjob") != std::string::npos;
}

void SlurmResources::Override(const SlurmResources& over) {
  for (auto [to, from] : {std::pair{&time, &over.time}, std::pair{&mem, &over.mem},
                          std::pair{&partition, &over.partition}, std::pair{&account, &over.account}})
    if (!from->empty()) *to = *from;
  if (over.cpus_per_task > 0) cpus_per_task = over.cpus_per_task;
}

std::string SlurmValueProblem(const std::string& key, const std::string& given) {
  // JSON-quoted: a newline in the value shows as \n.
  const std::string value = nlohmann::json(given).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  static const std::regex time(
      R"([0-9]{1,9}(:[0-9]{1,9}){0,2}|[0-9]{1,9}-[0-9]{1,9}(:[0-9]{1,9}){0,2}|UNLIMITED|INFINITE)");
  static const std::regex mem(R"([0-9]{1,15}[KMGTkmgt]?)");
  static const std::regex partitions(R"([A-Za-z0-9_.-]+(,[A-Za-z0-9_.-]+)*)");
  static const std::regex account(R"([A-Za-z0-9_.-]+)");
  // Longer than any real value, and std::regex recurses per character.
  if (given.size() > 256)
    return "is " + std::to_string(given.size()) + " characters long; a Slurm value here is at most 256";
  if (key == "time") {
    if (!std::regex_match(given, time))
      return value +
             " is not a Slurm time (minutes, minutes:seconds, hours:minutes:seconds, days-hours, "
             "days-hours:minutes, days-hours:minutes:seconds; e.g. \"2:00:00\" or \"1-12\")";
  } else if (key == "mem") {
    if (!std::regex_match(given, mem))
      return value + " is not a Slurm memory size (an integer with an optional unit K, M, G or T; e.g. \"4G\")";
  } else if (key == "partition") {
    if (!std::regex_match(given, partitions))
      return value +
             " is not a Slurm partition list (names of letters, digits, _ . -, separated by commas; e.g. \"gpu\")";
  } else if (key == "account") {
    if (!std::regex_match(given, account)) return value + " is not a Slurm account name (letters, digits, _ . -)";
  } else {
    return "is not a Slurm resource layerlab writes";
  }
  if (SbatchSeesHetJob(given)) return value + " holds \"hetjob\" or \"packjob\", which sbatch reads as a new job";
  return "";
}

std::string SlurmJobNameProblem(const std::string& name) {
  static const std::regex form(R"([A-Za-z0-9 _.+-]+)");
  if (name.empty() || name.size() > 200 || !std::regex_match(name, form))
    return "cannot be a Slurm job name: use letters, digits, spaces and _ . + - (at most 200 characters)";
  if (SbatchSeesHetJob(name)) return "holds \"hetjob\" or \"packjob\", which sbatch reads as a new job";
  return "";
}

SlurmResources ReadSlurmResources(Params& p) {
  SlurmResources r;
  for (auto [key, field] : {std::pair{"time", &r.time}, std::pair{"mem", &r.mem}, std::pair{"partition", &r.partition},
                            std::pair{"account", &r.account}}) {
    if (!p.has(key)) continue;
    *field = p.string(key);
    if (const std::string problem = SlurmValueProblem(key, *field); !problem.empty()) p.fail(key, problem);
  }
  if (p.has("cpus-per-task")) r.cpus_per_task = static_cast<int>(p.integer("cpus-per-task", 1, kMaxSlurmCpusPerTask));
  p.check_all_read();
  return r;
}

}  // namespace layerlab
