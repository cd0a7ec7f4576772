// Minimal leveled logging to stderr. Warnings and errors always print; info is silenced by --quiet.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace semvox {

enum class LogLevel { kDebug = 0, kInfo = 1, kWarning = 2, kError = 3 };

void SetLogLevel(LogLevel level);
LogLevel GetLogLevel();
void LogLine(LogLevel level, const std::string& message);
// Warnings issued so far in this process (summary.json lists them).
std::vector<std::string> TakeWarnings();

#define SEMVOX_LOG(level, expr)                                   \
  do {                                                            \
    if (::semvox::LogLevel::level >= ::semvox::GetLogLevel()) {   \
      std::ostringstream _os;                                     \
      _os << expr;                                                \
      ::semvox::LogLine(::semvox::LogLevel::level, _os.str());    \
    }                                                             \
  } while (0)
#define SEMVOX_INFO(expr) SEMVOX_LOG(kInfo, expr)
#define SEMVOX_WARN(expr) SEMVOX_LOG(kWarning, expr)

}  // namespace semvox
