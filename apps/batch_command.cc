// `semvox batch MANIFEST -o ROOT [-j N]`: many scans, one `semvox run` child process each.
//
// Each scan's outputs go to ROOT/<name>/; a scan whose summary.json exists (written last by `semvox run`)
// is complete and skipped, so an interrupted batch resumes where it stopped. A failed scan does not stop
// the others. ROOT/index.csv and ROOT/index.json list every scan with its status, exit code, seconds and
// error line; each child's stderr is kept in ROOT/logs/<name>.log.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <cctype>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "apps/commands.h"
#include "core/file_util.h"
#include "core/log.h"

extern char** environ;

namespace semvox {
namespace fs = std::filesystem;

namespace {

struct Job {
  std::string name, input;
  std::string status = "pending";  // ok | skipped | failed
  int exit_code = 0;
  double seconds = 0;
  std::string error;
  pid_t pid = -1;
  std::chrono::steady_clock::time_point start;
};

std::string SafeName(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.') ? c : '_';
  return out.empty() ? "scan" : out;
}

Result<std::vector<Job>> ReadManifest(const std::string& path) {
  std::string text;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &text));
  std::vector<Job> jobs;
  std::set<std::string> names;
  std::istringstream is(text);
  std::string line;
  int line_no = 0;
  const fs::path base = fs::path(path).parent_path();
  while (std::getline(is, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream ls(line.substr(first));
    std::string a, b, extra;
    ls >> a >> b >> extra;
    if (!extra.empty())
      return Status::InvalidInput(FileError(path, "line " + std::to_string(line_no) + " has more than two fields",
                                            "one scan per line: 'INPUT' or 'NAME INPUT' (no spaces in paths)"));
    Job j;
    j.input = b.empty() ? a : b;
    if (fs::path(j.input).is_relative()) j.input = (base / j.input).string();
    j.name = SafeName(b.empty() ? fs::path(a).stem().string() : a);
    std::string unique = j.name;
    for (int k = 2; names.count(unique); ++k) unique = j.name + "_" + std::to_string(k);
    j.name = unique;
    names.insert(j.name);
    jobs.push_back(j);
  }
  if (jobs.empty()) return Status::InvalidInput(FileError(path, "manifest lists no scans", "one input path per line"));
  return jobs;
}

std::string LastErrorLine(const std::string& log_path) {
  std::string text;
  if (!ReadFileBytes(log_path, &text).ok()) return "";
  std::istringstream is(text);
  std::string line, last;
  while (std::getline(is, line))
    if (line.rfind("semvox: error: ", 0) == 0) last = line.substr(15);
  return last;
}

Status WriteIndex(const std::string& root, const std::vector<Job>& jobs) {
  nlohmann::ordered_json j = nlohmann::json::array();
  std::string csv = "name,input,status,exit_code,seconds,error\n";
  auto quote = [](std::string s) {
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  };
  for (const Job& job : jobs) {
    j.push_back({{"name", job.name}, {"input", job.input}, {"status", job.status}, {"exit_code", job.exit_code},
                 {"seconds", job.seconds}, {"output", job.name + "/"}, {"error", job.error}});
    std::ostringstream row;
    row << quote(job.name) << ',' << quote(job.input) << ',' << job.status << ',' << job.exit_code << ','
        << job.seconds << ',' << quote(job.error) << '\n';
    csv += row.str();
  }
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic((fs::path(root) / "index.json").string(), j.dump(2) + "\n"));
  return WriteFileAtomic((fs::path(root) / "index.csv").string(), csv);
}

}  // namespace

Status RunBatch(const BatchArgs& args) {
  if (args.jobs < 1) return Status::InvalidInput("batch: -j = " + std::to_string(args.jobs) + ". Violated constraint: -j >= 1");
  Result<std::vector<Job>> jobs_or = ReadManifest(args.manifest);
  if (!jobs_or.ok()) return jobs_or.status();
  std::vector<Job> jobs = std::move(jobs_or).value();
  SEMVOX_RETURN_IF_ERROR(EnsureWritableDirectory(args.root));
  SEMVOX_RETURN_IF_ERROR(EnsureWritableDirectory((fs::path(args.root) / "logs").string()));
  const std::string self = fs::read_symlink("/proc/self/exe").string();

  size_t next = 0, running = 0, done = 0;
  std::map<pid_t, size_t> by_pid;
  auto start_job = [&](Job& job) -> Status {
    const fs::path out = fs::path(args.root) / job.name;
    if (fs::exists(out / "summary.json")) {
      job.status = "skipped";
      SEMVOX_NOTE("batch: " << job.name << " already complete, skipped");
      return Status::Ok();
    }
    const std::string log = (fs::path(args.root) / "logs" / (job.name + ".log")).string();
    std::vector<std::string> argv_s = {self, "run", job.input, "-o", out.string(), "-q"};
    if (!args.config_path.empty()) argv_s.insert(argv_s.end(), {"--config", fs::absolute(args.config_path).string()});
    std::vector<char*> argv;
    for (auto& s : argv_s) argv.push_back(s.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid;
    const int rc = posix_spawn(&pid, self.c_str(), &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) return Status::Internal("batch: cannot start a child process: " + std::string(std::strerror(rc)));
    job.pid = pid;
    job.start = std::chrono::steady_clock::now();
    by_pid[pid] = size_t(&job - jobs.data());
    ++running;
    return Status::Ok();
  };
  while (done < jobs.size()) {
    while (running < size_t(args.jobs) && next < jobs.size()) {
      Job& job = jobs[next++];
      SEMVOX_RETURN_IF_ERROR(start_job(job));
      if (job.status == "skipped") ++done;
    }
    if (running == 0) continue;
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) return Status::Internal("batch: waitpid failed");
    auto it = by_pid.find(pid);
    if (it == by_pid.end()) continue;
    Job& job = jobs[it->second];
    by_pid.erase(it);
    --running;
    ++done;
    job.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - job.start).count();
    job.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    if (job.exit_code == 0) {
      job.status = "ok";
    } else {
      job.status = "failed";
      job.error = LastErrorLine((fs::path(args.root) / "logs" / (job.name + ".log")).string());
      if (job.error.empty()) job.error = "exit code " + std::to_string(job.exit_code);
    }
    SEMVOX_NOTE("batch: [" << done << "/" << jobs.size() << "] " << job.name << " " << job.status << " in "
                           << job.seconds << " s" << (job.error.empty() ? "" : ": " + job.error));
    SEMVOX_RETURN_IF_ERROR(WriteIndex(args.root, jobs));  // Kept current, so a killed batch leaves an index.
  }
  SEMVOX_RETURN_IF_ERROR(WriteIndex(args.root, jobs));
  size_t failed = 0;
  for (const Job& j : jobs) failed += j.status == "failed";
  SEMVOX_NOTE("batch: " << jobs.size() - failed << " of " << jobs.size() << " scans complete; index in " << args.root
                        << "/index.csv");
  if (failed > 0)
    return Status::Internal("batch: " + std::to_string(failed) + " of " + std::to_string(jobs.size()) +
                            " scans failed (see " + args.root + "/index.csv and logs/)");
  return Status::Ok();
}

}  // namespace semvox
