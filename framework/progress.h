// Progress of a long step on stderr, in one style for every command.
// On a terminal (isatty(2)) one line is redrawn with \r:
//   "solve hybrid [##########          ]  15/30  4.1 s  ETA 4.1 s  PSNR 28.41 dB"
// otherwise (logs, CI) plain lines: one every ten seconds of long work, with
// the estimated time left, and the summary at the end.
//
// How much is said is set once per process (the --quiet and --verbose flags of
// every command): quiet silences progress and notes (never errors or
// warnings); verbose prints every update as a line of its own.
#pragma once

#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace layerlab {

enum class Verbosity { kQuiet, kNormal, kVerbose };
void SetVerbosity(Verbosity v);
Verbosity CurrentVerbosity();

// A line of information on stderr ("loading dice"), silenced by --quiet.
void Note(const std::string& line);
// A line only --verbose shows (each iteration of each run).
void Detail(const std::string& line);

class Progress {
 public:
  Progress(std::string label, size_t total);
  ~Progress();  // ends a half-drawn terminal line
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // `done` of `total` units; `detail` is shown after the count. Safe from many threads.
  void Update(size_t done, const std::string& detail = "");
  // The last line: the step's summary and its wall time.
  void Finish(const std::string& summary);

  static bool Terminal();

  // "12 s", "3.4 min", "1.2 h": the estimated time left after `done` of `total` in `seconds`; "" before any.
  static std::string Eta(size_t done, size_t total, double seconds);

 private:
  void Draw(size_t done, const std::string& detail, double seconds);

  std::mutex mutex_;
  std::string label_;
  size_t total_;
  size_t last_done_ = 0;  // counts from many threads may arrive out of order: never drawn backwards
  std::chrono::steady_clock::time_point last_draw_{};
  bool tty_, open_line_ = false, finished_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace layerlab
