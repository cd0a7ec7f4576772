#include "core/file_util.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>

namespace semvox {
namespace fs = std::filesystem;

namespace {
std::mutex g_tmp_mutex;
std::set<std::string>& PendingTemporaries() {
  static auto* s = new std::set<std::string>();
  return *s;
}
// A copy readable from a signal handler without locking: fixed slots.
constexpr int kSlots = 64;
char g_slots[kSlots][4096];
std::atomic<bool> g_slot_used[kSlots];
std::atomic<uint64_t> g_counter{0};
}  // namespace

Status ReadFileBytes(const std::string& path, std::string* bytes) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    return Status::InvalidInput(FileError(path, "no such file", "check the path and the working directory"));
  if (fs::is_directory(path, ec))
    return Status::InvalidInput(FileError(path, "is a directory, expected a file", "pass the file inside it"));
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return Status::InvalidInput(FileError(path, std::string("cannot open: ") + std::strerror(errno), "check permissions"));
  bytes->clear();
  char buf[1 << 16];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof(buf), f)) > 0) bytes->append(buf, n);
  const bool err = std::ferror(f);
  std::fclose(f);
  if (err) return Status::InvalidInput(FileError(path, "read error", "check the disk"));
  return Status::Ok();
}

std::string RegisterTemporary(const std::string& final_path) {
  const std::string tmp = final_path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(g_counter++);
  std::lock_guard<std::mutex> lock(g_tmp_mutex);
  PendingTemporaries().insert(tmp);
  for (int i = 0; i < kSlots; ++i) {
    bool expected = false;
    if (!g_slot_used[i].load() && tmp.size() < sizeof(g_slots[i])) {
      std::memcpy(g_slots[i], tmp.c_str(), tmp.size() + 1);
      if (g_slot_used[i].compare_exchange_strong(expected, true)) break;
    }
  }
  return tmp;
}

void UnregisterTemporary(const std::string& tmp_path) {
  std::lock_guard<std::mutex> lock(g_tmp_mutex);
  PendingTemporaries().erase(tmp_path);
  for (int i = 0; i < kSlots; ++i)
    if (g_slot_used[i].load() && tmp_path == g_slots[i]) g_slot_used[i].store(false);
}

void RemovePendingTemporaries() {
  // Async-signal-safe: unlink only.
  for (int i = 0; i < kSlots; ++i)
    if (g_slot_used[i].load()) ::unlink(g_slots[i]);
}

Status FinishTemporary(const std::string& tmp, const std::string& path, const Status& st) {
  if (!st.ok()) {
    ::unlink(tmp.c_str());
    UnregisterTemporary(tmp);
    return st;
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(tmp.c_str());
    UnregisterTemporary(tmp);
    return Status::InvalidInput(FileError(path, "cannot rename the finished output into place: " + why,
                                          "check that the output directory is writable"));
  }
  UnregisterTemporary(tmp);
  return Status::Ok();
}

Status WriteFileAtomic(const std::string& path, const std::string& bytes) {
  return WriteViaTemporary(path, [&](const std::string& tmp) -> Status {
    int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0)
      return Status::InvalidInput(FileError(path, std::string("cannot create output: ") + std::strerror(errno),
                                            "check that the output directory exists and is writable"));
    size_t off = 0;
    while (off < bytes.size()) {
      ssize_t w = ::write(fd, bytes.data() + off, bytes.size() - off);
      if (w < 0) {
        if (errno == EINTR) continue;
        const std::string why = std::strerror(errno);
        ::close(fd);
        return Status::Internal(FileError(path, "write failed: " + why, "check free disk space"));
      }
      off += size_t(w);
    }
    if (::fsync(fd) != 0 && errno != EINVAL) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      return Status::Internal(FileError(path, "fsync failed: " + why, "check the disk"));
    }
    ::close(fd);
    return Status::Ok();
  });
}

Status EnsureWritableDirectory(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    return Status::InvalidInput(FileError(dir, "exists and is not a directory", "choose another output directory"));
  fs::create_directories(dir, ec);
  if (ec)
    return Status::InvalidInput(FileError(dir, "cannot create output directory: " + ec.message(),
                                          "choose a writable location"));
  const std::string probe = (fs::path(dir) / (".semvox_write_test." + std::to_string(::getpid()))).string();
  int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0)
    return Status::InvalidInput(FileError(dir, std::string("output directory is not writable: ") + std::strerror(errno),
                                          "choose a writable location or fix its permissions"));
  ::close(fd);
  ::unlink(probe.c_str());
  return Status::Ok();
}

std::string LowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext = ext.substr(1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

}  // namespace semvox
