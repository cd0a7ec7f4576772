#include "core/log.h"

#include <cstdio>
#include <mutex>
#include <vector>

namespace semvox {
namespace {
LogLevel g_level = LogLevel::kInfo;
std::mutex g_mutex;
std::vector<std::string> g_warnings;
}  // namespace

void SetLogLevel(LogLevel level) { g_level = level; }
LogLevel GetLogLevel() { return g_level; }

void LogLine(LogLevel level, const std::string& message) {
  std::lock_guard<std::mutex> lock(g_mutex);
  const char* prefix = level == LogLevel::kWarning ? "semvox: warning: "
                       : level == LogLevel::kError ? "semvox: error: "
                                                   : "semvox: ";
  if (level == LogLevel::kWarning) g_warnings.push_back(message);
  std::fprintf(stderr, "%s%s\n", prefix, message.c_str());
}

std::vector<std::string> TakeWarnings() {
  std::lock_guard<std::mutex> lock(g_mutex);
  std::vector<std::string> w;
  w.swap(g_warnings);
  return w;
}

}  // namespace semvox
