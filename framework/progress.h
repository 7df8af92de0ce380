// Progress of a long step on stderr. On a terminal (isatty(2)) one line is
// redrawn with \r: "solve [##########          ]  15/30  PSNR 28.41 dB";
// otherwise (logs, CI) plain lines at every tenth of the work and at the end.
#pragma once

#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace layerlab {

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

 private:
  void Draw(size_t done, const std::string& detail);

  std::mutex mutex_;
  std::string label_;
  size_t total_;
  size_t printed_tenths_ = 0;
  size_t last_done_ = 0;  // counts from many threads may arrive out of order: never drawn backwards
  std::chrono::steady_clock::time_point last_draw_{};
  bool tty_, open_line_ = false, finished_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace layerlab
