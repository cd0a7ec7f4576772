#include "core/progress.h"

#include <unistd.h>

#include <cstdio>

namespace semvox {

ProgressReporter::ProgressReporter(ProgressMode mode) : mode_(mode) {
  if (mode_ == ProgressMode::kAuto) mode_ = ::isatty(2) ? ProgressMode::kBar : ProgressMode::kLines;
}

ProgressReporter::~ProgressReporter() {
  // A stage left unfinished (an error return): end the bar's line so the error starts on its own.
  if (!stage_.empty() && mode_ == ProgressMode::kBar && drawn_) std::fprintf(stderr, "\n");
}

void ProgressReporter::Begin(const std::string& stage) {
  std::lock_guard<std::mutex> lock(mutex_);
  stage_ = stage;
  start_ = last_draw_ = std::chrono::steady_clock::now();
  drawn_ = false;
}

ProgressCallback ProgressReporter::Callback() {
  return [this](size_t done, size_t total) { Draw(done, total, false); };
}

void ProgressReporter::Draw(size_t done, size_t total, bool force) {
  if (mode_ != ProgressMode::kBar || total == 0) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const double f = std::min(1.0, double(done) / double(total));
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const int width = 30, filled = int(f * width + 0.5);
  std::string bar(size_t(filled), '#');
  bar.append(size_t(width - filled), '-');
  char eta[32] = "";
  if (f > 0.02) std::snprintf(eta, sizeof(eta), " ETA %.0f s", elapsed * (1.0 - f) / f);
  std::fprintf(stderr, "\r%-12s [%s] %3.0f%%%s   ", stage_.c_str(), bar.c_str(), 100 * f, eta);
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressReporter::End() {
  std::lock_guard<std::mutex> lock(mutex_);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (mode_ == ProgressMode::kBar) {
    std::fprintf(stderr, "\r%-12s done in %.1f s%40s\n", stage_.c_str(), elapsed, "");
  } else if (mode_ == ProgressMode::kLines) {
    std::fprintf(stderr, "semvox: %s done in %.2f s\n", stage_.c_str(), elapsed);
  }
  stage_.clear();
}

}  // namespace semvox
