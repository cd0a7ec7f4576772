// Where the semvox binary finds its model files. The libraries never look for models themselves: the CLI
// resolves the directory once here and passes paths down.
//
//   Result<std::string> dir = ResolveModelsDir(args.models_dir, argv0);
//
// The search, first that applies:
//   1. --models DIR, as given;
//   2. $SEMVOX_MODELS, as given;
//   3. <directory of the executable>/../share/semvox/models when it is a directory: the layout `cmake --install`
//      writes (PREFIX/bin/semvox, PREFIX/share/semvox/models/), which the build tree repeats with a link
//      BUILD/share/semvox/models -> the source tree's models/ (the top CMakeLists.txt).
#pragma once

#include <string>

#include "core/status.h"

namespace semvox {

// The models directory, or one error line naming what was searched with the hint (--models DIR or
// SEMVOX_MODELS). `argv0` is the process's argv[0], used only when /proc/self/exe cannot be read. A directory
// found beside the executable is returned canonical (the build tree's link resolved); the others as given.
Result<std::string> ResolveModelsDir(const std::string& models_flag, const std::string& argv0);

// The running executable's absolute path: /proc/self/exe, else argv0 (made absolute, or looked up in $PATH
// when it has no '/'); "" when neither gives a file.
std::string ExecutablePath(const std::string& argv0);

// <directory of `executable`>/../share/semvox/models, lexically normalised.
std::string ModelsDirBesideExecutable(const std::string& executable);

}  // namespace semvox
