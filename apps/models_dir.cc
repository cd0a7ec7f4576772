#include "apps/models_dir.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

namespace semvox {
namespace fs = std::filesystem;

std::string ExecutablePath(const std::string& argv0) {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec && !self.empty()) return self.string();
  if (argv0.empty()) return "";
  auto resolved = [&ec](const fs::path& p) -> std::string {
    if (!fs::is_regular_file(p, ec) || ::access(p.c_str(), X_OK) != 0) return "";
    const fs::path c = fs::canonical(p, ec);  // As /proc/self/exe: links resolved.
    return ec ? "" : c.string();
  };
  if (argv0.find('/') != std::string::npos) return resolved(argv0);
  // A bare name: the shell found it through $PATH (an empty entry is the working directory).
  const char* env = std::getenv("PATH");
  const std::string dirs = env ? env : "";
  for (size_t start = 0; start <= dirs.size();) {
    const size_t colon = std::min(dirs.find(':', start), dirs.size());
    const std::string dir = dirs.substr(start, colon - start);
    if (std::string p = resolved(fs::path(dir.empty() ? "." : dir) / argv0); !p.empty()) return p;
    start = colon + 1;
  }
  return "";
}

std::string ModelsDirBesideExecutable(const std::string& executable) {
  return (fs::path(executable).parent_path() / ".." / "share" / "semvox" / "models").lexically_normal().string();
}

Result<std::string> ResolveModelsDir(const std::string& models_flag, const std::string& argv0) {
  if (!models_flag.empty()) return models_flag;
  if (const char* env = std::getenv("SEMVOX_MODELS"); env && *env) return std::string(env);
  const std::string searched = "no models directory: --models not given, SEMVOX_MODELS not set, and ";
  const std::string hint = " (hint: pass --models DIR or set SEMVOX_MODELS)";
  const std::string exe = ExecutablePath(argv0);
  if (exe.empty())
    return Status::InvalidInput(searched + "the executable's own path is unknown (/proc/self/exe unreadable, argv[0] '" + argv0 +
                                "' not found)" + hint);
  const std::string beside = ModelsDirBesideExecutable(exe);
  std::error_code ec;
  if (!fs::is_directory(beside, ec))
    return Status::InvalidInput(searched + beside + " (relative to the executable " + exe + ") is not a directory" + hint);
  const fs::path canonical = fs::canonical(beside, ec);  // The build tree's link -> the source tree's models/.
  return ec ? beside : canonical.string();
}

}  // namespace semvox
