// File helpers: whole-file reads with clear errors and atomic writes (temporary name, then rename),
// so that no reader ever sees a half-written output.
#pragma once

#include <string>

#include "core/status.h"

namespace semvox {

// Reads a whole file. Missing files, directories and unreadable files give kInvalidInput naming the path.
Status ReadFileBytes(const std::string& path, std::string* bytes);

// Writes `bytes` to `path` through "<path>.tmp.<pid>" in the same directory, fsync, then rename.
// On failure no file named `path` is created or modified and the temporary file is removed.
Status WriteFileAtomic(const std::string& path, const std::string& bytes);

// Writes through a callback that receives a temporary path in the same directory (for libraries that
// insist on writing files themselves, such as OctoMap); renames on success, removes on failure.
template <typename WriteFn>
Status WriteViaTemporary(const std::string& path, WriteFn&& write_fn);

// Creates `dir` (and parents) if needed and checks that a file can be written in it.
Status EnsureWritableDirectory(const std::string& dir);

// Lowercase extension without the dot ("ply", "glb"); "" when there is none.
std::string LowerExtension(const std::string& path);

// Temporary files currently being written; removed by RemovePendingTemporaries() (signal handlers).
std::string RegisterTemporary(const std::string& final_path);
void UnregisterTemporary(const std::string& tmp_path);
void RemovePendingTemporaries();

// Renames tmp to path when `st` is ok, else removes tmp; returns the first failure.
Status FinishTemporary(const std::string& tmp, const std::string& path, const Status& st);

template <typename WriteFn>
Status WriteViaTemporary(const std::string& path, WriteFn&& write_fn) {
  const std::string tmp = RegisterTemporary(path);
  Status st = write_fn(tmp);
  Status commit = FinishTemporary(tmp, path, st);
  return commit;
}

}  // namespace semvox
