// Minimal leveled logging to stderr. Warnings and errors always print; notes (what a user of `semvox run` reads:
// its summary) print unless --quiet; info (each step's detail) prints by default in the other commands and with
// --verbose in `semvox run`.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace semvox {

enum class LogLevel { kDebug = 0, kInfo = 1, kNote = 2, kWarning = 3, kError = 4 };

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
#define SEMVOX_NOTE(expr) SEMVOX_LOG(kNote, expr)
#define SEMVOX_WARN(expr) SEMVOX_LOG(kWarning, expr)

}  // namespace semvox
