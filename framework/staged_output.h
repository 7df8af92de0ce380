// Nothing lost: a command builds its new results in a staging folder inside
// its output folder (so the same file system) and switches them into place
// only once every file is complete. Until then the folder holds the earlier
// results byte for byte; a command that fails, runs out of disk or is killed
// leaves them so.
//
// The switch-over is journaled: the list of renames and removals is written
// (atomically) before the first rename, and the next command into the folder,
// or the next reader of anything in it (FinishPendingSwitchOvers), finishes a
// switch-over that a kill interrupted. A writer holds the folder's lock
// (.layerlab-lock, flock, with its pid and host) for the life of its staging
// folder: a second writer is refused naming it, and what a dead writer left
// is told from a live one's work by the lock, not by a pid. Durable: the
// staged files, the journal and every folder the renames change are flushed
// (fsync) before the step that trusts them. Each folder keeps a
// manifest of the files each command wrote there (.layerlab-<command>-files.json);
// files an earlier run recorded and this one did not write are removed at
// the switch-over, never a file the manifest does not list, never an input,
// never through a symbolic link.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "layerlab/framework/error.h"
#include "layerlab/framework/file_lock.h"

namespace layerlab {

// A file or folder a command reads, named for messages ("the target").
struct NamedInput {
  std::string path;
  std::string what;
};

// Refuses (layerlab::Error naming both) an output path that is, contains or
// lies inside one of the inputs. Real paths are compared: symbolic links and
// ".." are resolved; `output` need not exist yet.
void RefuseOutputOverlappingInputs(const std::string& output, const std::vector<NamedInput>& inputs);

class StagedOutput {
 public:
  // `roots`: the files and folders (relative to `folder`) the command writes;
  // each must not overlap an input, nor be a symbolic link or special file.
  // `folder` itself must neither contain an input nor lie inside one. Before the staging folder
  // is made, an interrupted switch-over is finished and what killed layerlab
  // processes left (their staging folders, temporary files) is removed;
  // recovered() says what was done. Throws layerlab::Error before anything
  // is written when a check fails or another process writes into `folder`.
  StagedOutput(std::string folder, std::string command, std::vector<std::string> roots, std::vector<NamedInput> inputs);
  // Without Commit(): removes the staging folder, and the output folder if
  // this object created it and it is empty again.
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;

  const std::string& folder() const { return folder_; }
  // Where the new results go, laid out as they will be in folder().
  const std::string& staging() const { return staging_; }
  const std::vector<std::string>& recovered() const { return recovered_; }

  // `e` with the staging folder's paths named as they would be in folder(),
  // and that the earlier results are unchanged: for a failure before Commit().
  Error Explain(const Error& e) const;

  struct Switched {
    std::vector<std::string> written;  // relative to folder(), sorted
    std::vector<std::string> removed;  // files an earlier run recorded and this one did not write
  };
  // Every file in staging() moves into place; then the stale files go and
  // the manifest is updated. Throws layerlab::Error (folder unchanged) when
  // a path the results need is taken by a folder, a link or a special file.
  Switched Commit();

 private:
  std::string folder_, command_, staging_;
  std::vector<std::string> roots_;
  std::vector<NamedInput> inputs_;
  std::vector<std::string> recovered_;
  std::optional<FileLock> lock_;
  bool created_folder_ = false, committed_ = false;

  void ClearWhatKilledRunsLeft();
  void ReleaseLock();
  void RemoveCreatedFolder();
};

// Before reading anything under `path`: a switch-over that a killed layerlab
// run left half done in `path` or a folder above it is finished (the folder
// then holds the new results whole), and what was done is returned. Throws
// layerlab::Error naming the folder and the process when a live process is
// switching it over, or when the switch-over cannot be finished.
std::vector<std::string> FinishPendingSwitchOvers(const std::string& path);

// Fault injection for tests. The steps of a switch-over are its moves, one
// per file, then the removal of its staging folder. This process ends
// (_exit(86)) after `steps` steps of a later switch-over, as a kill there would
// end it; or the switch-over throws layerlab::Error there, as a failed rename
// would. 0: never.
void EndProcessAfterSwitchOverStepsForTesting(int steps);
void FailSwitchOverAfterStepsForTesting(int steps);

// The name of the manifest `command` keeps in an output folder.
std::string OutputManifestName(const std::string& command);

}  // namespace layerlab
