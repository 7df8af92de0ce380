#include "framework/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace layerlab {

bool Progress::Terminal() { return ::isatty(2) == 1; }

Progress::Progress(std::string label, size_t total)
    : label_(std::move(label)),
      total_(std::max<size_t>(total, 1)),
      tty_(Terminal()),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() {
  if (open_line_) std::fputc('\n', stderr);
}

void Progress::Draw(size_t done, const std::string& detail) {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (tty_) {
    constexpr int kWidth = 24;
    const int filled = static_cast<int>(std::min(done, total_) * kWidth / total_);
    std::string bar(filled, '#');
    bar.resize(kWidth, ' ');
    std::fprintf(stderr, "\r%s [%s] %zu/%zu  %5.1f s  %s\x1b[K", label_.c_str(), bar.c_str(), done, total_, seconds,
                 detail.c_str());
    open_line_ = true;
  } else {
    std::fprintf(stderr, "%s: %zu/%zu  %.1f s  %s\n", label_.c_str(), done, total_, seconds, detail.c_str());
  }
  std::fflush(stderr);
}

void Progress::Update(size_t done, const std::string& detail) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_ || done < last_done_) return;
  last_done_ = done;
  if (tty_) {  // redraws at most 20 times a second, and always the last
    const auto now = std::chrono::steady_clock::now();
    if (done < total_ && now - last_draw_ < std::chrono::milliseconds(50)) return;
    last_draw_ = now;
  } else {
    const size_t tenths = std::min(done, total_) * 10 / total_;
    if (tenths <= printed_tenths_ && done < total_) return;
    if (done >= total_ && printed_tenths_ == 10) return;
    printed_tenths_ = tenths;
  }
  Draw(done, detail);
}

void Progress::Finish(const std::string& summary) {
  std::lock_guard<std::mutex> lock(mutex_);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (open_line_) std::fputs("\r\x1b[K", stderr);
  std::fprintf(stderr, "%s: done in %.1f s: %s\n", label_.c_str(), seconds, summary.c_str());
  std::fflush(stderr);
  open_line_ = false;
  finished_ = true;
}

}  // namespace layerlab
