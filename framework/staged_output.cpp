#include "layerlab/framework/staged_output.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <regex>
#include <set>

#include <nlohmann/json.hpp>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/file_lock.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/progress.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

constexpr const char* kManifestFormat = "layerlab-files/1";
constexpr const char* kJournalFormat = "layerlab-switch/1";
constexpr const char* kLockName = ".layerlab-lock";

// Every command that stages its output: a reader looks for their journals by name.
constexpr const char* kStagedCommands[] = {"run",
                                           "solve",
                                           "retina",
                                           "eyebox",
                                           "compare",
                                           "contrast",
                                           "render-target",
                                           "photograph",
                                           "calibration-patterns",
                                           "camera-patterns",
                                           "sweep",
                                           "optimize",
                                           "tolerance",
                                           "psf"};

// Links and ".." resolved as far as the path exists; what does not exist yet is appended as spelled.
fs::path RealPath(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) throw Error(path + ": cannot resolve the path: " + ec.message());
  return p.lexically_normal();
}

// True if `p` is `root` or inside it (both normal and absolute).
bool Under(const fs::path& p, const fs::path& root) {
  auto r = root.begin(), q = p.begin();
  for (; r != root.end(); ++r, ++q) {
    if (r->empty() && std::next(r) == root.end()) return true;  // "dir/" ends in an empty element
    if (q == p.end() || *q != *r) return false;
  }
  return true;
}

// What lstat sees at `p`, for messages; "" when nothing is there.
std::string KindAt(const fs::path& p, bool* is_dir = nullptr, bool* is_file = nullptr) {
  struct stat st;
  if (::lstat(p.c_str(), &st) != 0) return "";
  if (is_dir) *is_dir = S_ISDIR(st.st_mode);
  if (is_file) *is_file = S_ISREG(st.st_mode);
  if (S_ISDIR(st.st_mode)) return "a folder";
  if (S_ISREG(st.st_mode)) return "a file";
  if (S_ISLNK(st.st_mode)) return "a symbolic link";
  if (S_ISFIFO(st.st_mode)) return "a FIFO";
  if (S_ISSOCK(st.st_mode)) return "a socket";
  return "a device";
}

int end_after_steps = 0;   // EndProcessAfterSwitchOverStepsForTesting
int fail_after_steps = 0;  // FailSwitchOverAfterStepsForTesting

// Fault injection: a step of a switch-over (`done`) is complete.
void AfterSwitchOverStep(const fs::path& done) {
  if (end_after_steps > 0 && --end_after_steps == 0) ::_exit(86);
  if (fail_after_steps > 0 && --fail_after_steps == 0)
    throw Error(done.string() + ": the switch-over fails here (FailSwitchOverAfterStepsForTesting)");
}

bool ProcessAlive(long pid) { return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM); }

// A relative path a manifest or journal may name: inside the folder, no "..".
bool SafeRelative(const std::string& rel) {
  if (rel.empty()) return false;
  fs::path p(rel);
  if (p.is_absolute()) return false;
  return std::none_of(p.begin(), p.end(), [](const fs::path& part) { return part == ".." || part == "."; });
}

std::string JournalName(const std::string& command) { return ".layerlab-" + command + "-switch.json"; }

// True if every folder between `folder` and `rel`'s file is a real folder (no link to elsewhere).
bool ParentsAreFolders(const fs::path& folder, const std::string& rel) {
  fs::path at = folder;
  const fs::path p(rel);
  for (auto it = p.begin(); it != p.end() && std::next(it) != p.end(); ++it) {
    at /= *it;
    bool dir = false;
    if (KindAt(at, &dir).empty()) return true;  // nothing further down exists
    if (!dir) return false;
  }
  return true;
}

// Removes `rel`'s folders that are empty now, deepest first, never `folder` itself.
void PruneEmptyParents(const fs::path& folder, const std::string& rel) {
  std::error_code ec;
  for (fs::path dir = fs::path(rel).parent_path(); !dir.empty(); dir = dir.parent_path()) {
    const fs::path at = folder / dir;
    bool is_dir = false;
    KindAt(at, &is_dir);
    if (!is_dir || !fs::is_empty(at, ec) || ec) return;
    fs::remove(at, ec);
  }
}

// Carries out a switch-over: the moves in order (those already made are
// skipped), then the removals, then the staging folder and the journal go.
void RunJournal(const fs::path& folder, const fs::path& journal, const nlohmann::json& doc) {
  const fs::path staging = folder / doc.at("staging").get<std::string>();
  std::error_code ec;
  std::set<std::string> changed_folders = {folder.string()};
  for (const auto& item : doc.at("move")) {
    const std::string rel = item.get<std::string>();
    if (!SafeRelative(rel)) throw Error(journal.string() + ": /move: \"" + rel + "\" is not a path inside the folder");
    const fs::path from = staging / rel, to = folder / rel;
    if (KindAt(from).empty()) continue;  // moved before the interruption
    fs::create_directories(to.parent_path(), ec);
    if (ec) throw Error(to.parent_path().string() + ": cannot create the folder: " + ec.message());
    if (std::rename(from.c_str(), to.c_str()) != 0)
      throw Error(to.string() + ": cannot move the finished file into place: " + std::strerror(errno));
    for (fs::path at = to.parent_path(); at != folder && Under(at, folder); at = at.parent_path())
      changed_folders.insert(at.string());
    AfterSwitchOverStep(to);
  }
  for (const std::string& changed : changed_folders) SyncFolder(changed);  // the renames reach the disk first
  for (const auto& item : doc.at("remove")) {
    const std::string rel = item.get<std::string>();
    if (!SafeRelative(rel) || !ParentsAreFolders(folder, rel)) continue;
    bool dir = false;
    if (KindAt(folder / rel, &dir).empty() || dir) continue;
    fs::remove(folder / rel, ec);
    PruneEmptyParents(folder, rel);
  }
  fs::remove_all(staging, ec);  // first: no staging folder is left without the journal that clears it
  AfterSwitchOverStep(staging);
  fs::remove(journal, ec);
  SyncFolder(folder.string());
}

// Every file and folder in `staging`, flushed to disk: what the journal will move must be there whole.
void SyncTree(const fs::path& staging) {
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(staging, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (it->is_directory())
      SyncFolder(it->path().string());
    else
      SyncFile(it->path().string());
  }
  if (ec) throw Error(staging.string() + ": cannot list the staging folder: " + ec.message());
  SyncFolder(staging.string());
}

// Whether what a layerlab process left in `owner` (its staging folder, a
// temporary file) belongs to a process still at work there: the folder's
// lock says so, whatever the pid; without a lock file (a temporary file of a
// writer that takes none) the pid decides.
bool OwnerAtWork(const fs::path& owner, long pid) {
  const fs::path lock = owner / kLockName;
  if (!KindAt(lock).empty()) return FileLock::HeldElsewhere(lock.string());
  return ProcessAlive(pid);
}

std::vector<std::string> ReadManifestFiles(const fs::path& manifest) {
  std::vector<std::string> files;
  bool is_file = false;
  if (KindAt(manifest, nullptr, &is_file).empty() || !is_file) return files;
  try {
    nlohmann::json doc = ReadJsonFile(manifest.string());
    if (doc.value("format", "") != kManifestFormat) return files;
    for (const auto& f : doc.at("files"))
      if (f.is_string() && SafeRelative(f.get<std::string>())) files.push_back(f.get<std::string>());
  } catch (const std::exception&) {  // a damaged manifest records nothing: nothing is removed on its word
    files.clear();
  }
  return files;
}

}  // namespace

std::string OutputManifestName(const std::string& command) { return ".layerlab-" + command + "-files.json"; }

void RefuseOutputOverlappingInputs(const std::string& output, const std::vector<NamedInput>& inputs) {
  const fs::path out = RealPath(output);
  for (const NamedInput& in : inputs) {
    if (in.path.empty()) continue;
    const fs::path real = RealPath(in.path);
    const char* relation = out == real        ? "is"
                           : Under(out, real) ? "lies inside"
                           : Under(real, out) ? "contains"
                                              : nullptr;
    if (!relation) continue;
    std::string resolved;
    if (real.string() != fs::absolute(in.path).lexically_normal().string() ||
        out.string() != fs::absolute(output).lexically_normal().string())
      resolved = " (real paths " + out.string() + " and " + real.string() + ")";
    throw Error(output + ": the output " + relation + " " + in.what + " " + in.path + resolved +
                ", which would be overwritten or removed; write elsewhere. Nothing was read or written");
  }
}

StagedOutput::StagedOutput(std::string folder, std::string command, std::vector<std::string> roots,
                           std::vector<NamedInput> inputs)
    : folder_(std::move(folder)), command_(std::move(command)), roots_(std::move(roots)), inputs_(std::move(inputs)) {
  if (std::none_of(std::begin(kStagedCommands), std::end(kStagedCommands),
                   [&](const char* c) { return command_ == c; }))
    throw Error("internal error: the command " + command_ + " stages output but is not in kStagedCommands");
  const fs::path dir(folder_);
  for (const std::string& root : roots_) RefuseOutputOverlappingInputs((dir / root).string(), inputs_);
  // Nor may the folder contain an input (a scene beside its results would share their fate: the
  // stale-file sweep, a user's `rm -r` of the results) or lie inside one.
  RefuseOutputOverlappingInputs(folder_, inputs_);

  struct stat st;
  if (::stat(folder_.c_str(), &st) == 0) {
    if (!S_ISDIR(st.st_mode))
      throw Error(folder_ + ": the output folder is " + KindAt(dir) + ", not a folder; nothing was written");
  } else if (errno == ENOENT) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw Error(folder_ + ": cannot create the output folder: " + ec.message());
    created_folder_ = true;
  } else {
    throw Error(folder_ + ": cannot use the output folder: " + std::strerror(errno));
  }
  for (const std::string& root : roots_) {
    bool is_dir = false, is_file = false;
    const std::string kind = KindAt(dir / root, &is_dir, &is_file);
    if (!kind.empty() && !is_dir && !is_file)
      throw Error((dir / root).string() + ": is " + kind +
                  " where layerlab writes its output; it is not followed or replaced, "
                  "move it away. Nothing was written");
  }

  // One writer at a time, for the life of the staging folder.
  std::string holder;
  lock_ = FileLock::TryLock((dir / kLockName).string(), &holder);
  if (!lock_) {
    if (created_folder_) RemoveCreatedFolder();
    throw Error(folder_ + ": another layerlab " + (holder.empty() ? "process" : holder) +
                " is writing into this folder; wait for it to end or give another output folder. Nothing was written");
  }

  try {
    ClearWhatKilledRunsLeft();
    std::error_code ec;
    staging_ = (dir / (".layerlab-staging-" + command_ + "-" + std::to_string(::getpid()))).string();
    fs::remove_all(staging_, ec);
    fs::create_directory(staging_, ec);
    if (ec) throw Error(staging_ + ": cannot create the staging folder: " + ec.message());
  } catch (...) {
    ReleaseLock();
    if (created_folder_) RemoveCreatedFolder();
    throw;
  }
}

// What interrupted or killed runs left: finish their switch-overs, then clear their staging and temporary files.
void StagedOutput::ClearWhatKilledRunsLeft() {
  const fs::path dir(folder_);
  std::error_code ec;
  static const std::regex journal_name(R"(\.layerlab-(.+)-switch\.json)");
  static const std::regex staging_name(R"(\.layerlab-staging-(.+)-([0-9]{1,9}))");
  static const std::regex temp_name(R"(\..+\.tmp-([0-9]{1,9})-[0-9]+)");
  std::vector<fs::path> journals, dead;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    std::smatch m;
    if (std::regex_match(name, m, journal_name)) journals.push_back(entry.path());
  }
  for (const fs::path& journal : journals) {
    try {
      RunJournal(dir, journal, ReadJsonFile(journal.string()));
      recovered_.push_back("finished the switch-over that an interrupted run began (" + journal.filename().string() +
                           ")");
    } catch (const nlohmann::json::exception& e) {
      throw Error(journal.string() + ": not a valid switch-over journal (" + e.what() + "); remove it to go on");
    }
  }
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::smatch m;
    const bool staging = std::regex_match(name, m, staging_name);
    if (staging || std::regex_match(name, m, temp_name)) {
      // In this folder, whose lock this object holds, nothing is another process's work.
      if (it.depth() == 0 || !OwnerAtWork(it->path().parent_path(), std::stol(m[staging ? 2 : 1])))
        dead.push_back(it->path());
      if (staging && it->is_directory()) it.disable_recursion_pending();
    } else if (it.depth() == 0 && it->is_directory() && std::find(roots_.begin(), roots_.end(), name) == roots_.end()) {
      it.disable_recursion_pending();  // the user's folders beside the outputs are not searched
    }
  }
  for (const fs::path& p : dead) {
    fs::remove_all(p, ec);
    recovered_.push_back("removed " + p.string() + ", left by a layerlab process that no longer works there");
  }
}

StagedOutput::~StagedOutput() {
  std::error_code ec;
  const bool journaled = fs::exists(fs::path(folder_) / JournalName(command_), ec);
  if (!committed_ && !journaled) fs::remove_all(staging_, ec);  // a journaled switch-over is finished by the next run
  ReleaseLock();
  if (created_folder_) RemoveCreatedFolder();
}

void StagedOutput::ReleaseLock() {
  // The lock file goes while still held: a process that opened it meanwhile finds it unlinked and tries again.
  std::error_code ec;
  if (lock_) fs::remove(fs::path(folder_) / kLockName, ec);
  lock_.reset();
}

void StagedOutput::RemoveCreatedFolder() {
  std::error_code ec;
  if (fs::is_empty(folder_, ec) && !ec) fs::remove(folder_, ec);
}

Error StagedOutput::Explain(const Error& e) const {
  std::string text = e.what();
  for (size_t at; (at = text.find(staging_)) != std::string::npos;) text.replace(at, staging_.size(), folder_);
  return Error(text + "; the earlier results in " + folder_ + " are unchanged");
}

StagedOutput::Switched StagedOutput::Commit() {
  const fs::path dir(folder_), staging(staging_);
  Switched result;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(staging, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (it->is_directory()) continue;
    const std::string rel = it->path().lexically_relative(staging).string();
    if (!it->is_regular_file()) throw Error(it->path().string() + ": internal error: not a file in the staging folder");
    result.written.push_back(rel);
  }
  if (ec) throw Error(staging_ + ": cannot list the staging folder: " + ec.message());
  std::sort(result.written.begin(), result.written.end());
  SyncTree(staging);

  // Nothing is moved unless every file can be.
  for (const std::string& rel : result.written) {
    fs::path at = dir;
    const fs::path p(rel);
    for (auto it = p.begin(); it != p.end(); ++it) {
      at /= *it;
      bool is_dir = false, is_file = false;
      const std::string kind = KindAt(at, &is_dir, &is_file);
      const bool last = std::next(it) == p.end();
      if (kind.empty()) break;
      if (!last && !is_dir)
        throw Error(at.string() + ": is " + kind +
                    " where the output needs a folder; it is not followed or replaced. "
                    "The earlier results are unchanged");
      if (last && !is_file && kind != "a symbolic link")
        throw Error(at.string() + ": is " + kind + " where the output file " + rel +
                    " belongs. The earlier results are unchanged");
    }
  }

  const std::set<std::string> now(result.written.begin(), result.written.end());
  const fs::path manifest = dir / OutputManifestName(command_);
  std::vector<fs::path> protected_paths;
  for (const NamedInput& in : inputs_)
    if (!in.path.empty())
      protected_paths.push_back(RealPath(in.path)), protected_paths.push_back(fs::absolute(in.path).lexically_normal());
  for (const std::string& rel : ReadManifestFiles(manifest)) {
    if (now.count(rel)) continue;
    if (std::none_of(roots_.begin(), roots_.end(),
                     [&](const std::string& r) { return Under(fs::path(rel), fs::path(r)); }))
      continue;
    const fs::path at = fs::absolute(dir / rel).lexically_normal();
    if (!ParentsAreFolders(dir, rel)) continue;
    bool is_dir = false;
    if (KindAt(at, &is_dir).empty() || is_dir) continue;
    const fs::path real = RealPath(at.string());
    if (std::any_of(protected_paths.begin(), protected_paths.end(),
                    [&](const fs::path& p) { return Under(at, p) || Under(real, p) || Under(p, real); }))
      continue;
    result.removed.push_back(rel);
  }

  nlohmann::json files = result.written;
  WriteFileAtomically(
      (staging / OutputManifestName(command_)).string(),
      nlohmann::json{{"format", kManifestFormat}, {"command", command_}, {"files", files}}.dump(1) + "\n");
  nlohmann::json move = result.written;
  move.push_back(OutputManifestName(command_));
  const nlohmann::json journal = {
      {"format", kJournalFormat}, {"staging", staging.filename().string()}, {"move", move}, {"remove", result.removed}};
  const fs::path journal_path = dir / JournalName(command_);
  WriteFileAtomically(journal_path.string(), journal.dump(1) + "\n");
  RunJournal(dir, journal_path, journal);
  committed_ = true;
  return result;
}

void EndProcessAfterSwitchOverStepsForTesting(int steps) { end_after_steps = steps; }
void FailSwitchOverAfterStepsForTesting(int steps) { fail_after_steps = steps; }

std::vector<std::string> FinishPendingSwitchOvers(const std::string& path) {
  std::vector<std::string> done;
  std::error_code ec;
  fs::path at = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) return done;  // the reader names what it cannot reach
  for (;; at = at.parent_path()) {
    for (const char* command : kStagedCommands) {
      const fs::path journal = at / JournalName(command);
      bool is_file = false;
      if (KindAt(journal, nullptr, &is_file).empty() || !is_file) continue;
      const std::string unfinished =
          at.string() + ": a layerlab " + command + " was killed while switching its results into place";
      std::string holder;
      std::optional<FileLock> lock;
      try {
        lock = FileLock::TryLock((at / kLockName).string(), &holder);
      } catch (const Error& e) {
        throw Error(unfinished + ", and the switch-over cannot be finished from here (" + e.message() +
                    "); run layerlab " + command + " into that folder again");
      }
      if (!lock)
        throw Error(at.string() + ": layerlab " + (holder.empty() ? "process" : holder) +
                    " is switching its results into place; read them once it has ended");
      if (KindAt(journal).empty()) continue;  // its writer finished it meanwhile
      try {
        RunJournal(at, journal, ReadJsonFile(journal.string()));
      } catch (const nlohmann::json::exception& e) {
        throw Error(journal.string() + ": not a valid switch-over journal (" + e.what() + "); " + unfinished);
      }
      fs::remove(at / kLockName, ec);  // while held, as the writer does
      done.push_back(unfinished + "; the switch-over is now finished (" + journal.filename().string() + ")");
    }
    if (!at.has_relative_path()) break;  // the root
  }
  return done;
}

}  // namespace layerlab
