// Progress of the pipeline's stages on stderr: a bar with ETA when stderr is a terminal, one plain
// "STAGE done in S s" line per finished stage otherwise, nothing when quiet. Stages report through a ProgressCallback so that
// their code does not depend on how progress is shown.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <string>

namespace semvox {

// Called by a stage with units done so far and the total (thread-safe callers may call concurrently).
using ProgressCallback = std::function<void(size_t done, size_t total)>;

enum class ProgressMode { kAuto, kBar, kLines, kQuiet };

class ProgressReporter {
 public:
  explicit ProgressReporter(ProgressMode mode = ProgressMode::kAuto);
  ~ProgressReporter();
  void Begin(const std::string& stage);
  // A callback for the running stage.
  ProgressCallback Callback();
  void End();

 private:
  void Draw(size_t done, size_t total, bool force);
  ProgressMode mode_;
  std::string stage_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  std::mutex mutex_;
  bool drawn_ = false;
};

}  // namespace semvox
