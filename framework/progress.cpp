#include "layerlab/framework/progress.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>

namespace layerlab {
namespace {

std::atomic<Verbosity> verbosity{Verbosity::kNormal};

// Without a terminal, long work says where it is this often.
constexpr std::chrono::seconds kPlainLineEvery{10};

std::string Seconds(double s) {
  char text[32];
  if (s < 10)
    std::snprintf(text, sizeof text, "%.1f s", s);
  else if (s < 60)
    std::snprintf(text, sizeof text, "%.0f s", s);
  else if (s < 3600)
    std::snprintf(text, sizeof text, "%.1f min", s / 60);
  else
    std::snprintf(text, sizeof text, "%.1f h", s / 3600);
  return text;
}

}  // namespace

void SetVerbosity(Verbosity v) { verbosity = v; }
Verbosity CurrentVerbosity() { return verbosity; }

void Note(const std::string& line) {
  if (verbosity == Verbosity::kQuiet) return;
  std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

void Detail(const std::string& line) {
  if (verbosity != Verbosity::kVerbose) return;
  std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

bool Progress::Terminal() { return ::isatty(2) == 1; }

std::string Progress::Eta(size_t done, size_t total, double seconds) {
  if (done == 0 || done >= total) return "";
  return Seconds(seconds * double(total - done) / double(done));
}

Progress::Progress(std::string label, size_t total)
    : label_(std::move(label)),
      total_(std::max<size_t>(total, 1)),
      tty_(Terminal() && CurrentVerbosity() == Verbosity::kNormal),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() {
  if (open_line_) std::fputc('\n', stderr);
}

void Progress::Draw(size_t done, const std::string& detail, double seconds) {
  const std::string eta = Eta(done, total_, seconds);
  const std::string left = eta.empty() ? "" : "  ETA " + eta;
  if (tty_) {
    constexpr int kWidth = 24;
    const int filled = static_cast<int>(std::min(done, total_) * kWidth / total_);
    std::string bar(filled, '#');
    bar.resize(kWidth, ' ');
    std::fprintf(stderr, "\r%s [%s] %zu/%zu  %.1f s%s  %s\x1b[K", label_.c_str(), bar.c_str(), done, total_, seconds,
                 left.c_str(), detail.c_str());
    open_line_ = true;
  } else {
    std::fprintf(stderr, "%s: %zu/%zu  %.1f s%s  %s\n", label_.c_str(), done, total_, seconds, left.c_str(),
                 detail.c_str());
  }
  std::fflush(stderr);
}

void Progress::Update(size_t done, const std::string& detail) {
  const Verbosity v = CurrentVerbosity();
  if (v == Verbosity::kQuiet) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_ || done < last_done_) return;
  last_done_ = done;
  const auto now = std::chrono::steady_clock::now();
  if (v == Verbosity::kNormal) {
    // A terminal line is redrawn at most 20 times a second (and always at the end);
    // plain lines come every ten seconds of long work, the end being Finish's.
    if (tty_ ? (done < total_ && now - last_draw_ < std::chrono::milliseconds(50))
             : (done >= total_ || now - std::max(last_draw_, start_) < kPlainLineEvery))
      return;
  }
  last_draw_ = now;
  Draw(done, detail, std::chrono::duration<double>(now - start_).count());
}

void Progress::Finish(const std::string& summary) {
  if (CurrentVerbosity() == Verbosity::kQuiet) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (open_line_) std::fputs("\r\x1b[K", stderr);
  std::fprintf(stderr, "%s: done in %.1f s: %s\n", label_.c_str(), seconds, summary.c_str());
  std::fflush(stderr);
  open_line_ = false;
  finished_ = true;
}

}  // namespace layerlab
