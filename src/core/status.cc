#include "core/status.h"

namespace semvox {

std::string FileError(const std::string& path, const std::string& what, const std::string& hint) {
  std::string s = path + ": " + what;
  if (!hint.empty()) s += " (hint: " + hint + ")";
  return s;
}

}  // namespace semvox
