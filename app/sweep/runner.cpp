#include "app/sweep/runner.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "app/cli.hpp"
#include "app/output_file.hpp"
#include "app/sweep/record.hpp"

namespace apiclab::sweep {
namespace {

namespace fs = std::filesystem;

pid_t spawn(const std::vector<std::string>& args, const std::string& log) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      ::close(fd);
    }
    execv(argv[0], argv.data());
    _exit(127);
  }
  if (pid < 0) throw cli::UsageError("cannot start a run process (fork failed)");
  return pid;
}

// The last non-empty line of a run's log: its refusal, "apiclab: CAUSE".
std::string last_line_of(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty() && line.find_first_not_of(" \r\t") != std::string::npos) last = line;
  return last;
}

}  // namespace

std::string self_executable() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw cli::UsageError("cannot find this executable (/proc/self/exe)");
  return p.string();
}

RunnerReport run_plan(const Plan& plan, const std::string& out_dir, int jobs, bool quiet) {
  RunnerReport report;
  const fs::path runs = fs::path(out_dir) / "runs", logs = fs::path(out_dir) / "logs";
  fs::create_directories(runs);
  fs::create_directories(logs);
  for (const auto& entry : fs::directory_iterator(runs))  // half-written runs of a killed sweep
    if (entry.path().filename().string().find(".tmp-") != std::string::npos)
      fs::remove_all(entry.path());
  std::vector<const PlannedRun*> todo;
  std::size_t old_frames = 0;
  for (const PlannedRun& r : plan.runs) {
    const std::string dir = run_dir(out_dir, r);
    const bool dumped = plan.dump_formats.empty() || fs::is_directory(dir + "/dump");
    const bool complete = record_complete(dir);
    const bool current = !complete || frames_current(dir);  // no float frames beside double ones
    old_frames += !current;
    if (complete && dumped && current)
      ++report.skipped;
    else
      todo.push_back(&r);
  }
  if (!quiet && report.skipped)
    std::fprintf(stderr, "apiclab: sweep: %zu of %zu runs already complete in %s, skipped\n",
                 report.skipped, plan.runs.size(), out_dir.c_str());
  std::size_t resuming = 0;
  if (plan.checkpoints.on())
    for (const PlannedRun* r : todo)
      resuming += fs::exists(fs::path(run_checkpoint_dir(out_dir, *r, plan.checkpoints)) /
                             "checkpoint.bin");
  if (!quiet && resuming)
    std::fprintf(stderr,
                 "apiclab: sweep: %zu unfinished runs resume from their checkpoints (logs/ID.log "
                 "says where)\n",
                 resuming);
  if (!quiet && old_frames)
    std::fprintf(stderr,
                 "apiclab: sweep: %zu runs recorded by an older apiclab (positions as 32-bit "
                 "floats) run again\n",
                 old_frames);
  const std::string exe = self_executable();
  std::map<pid_t, const PlannedRun*> running;
  std::size_t next = 0, done = 0;
  const double start = now_seconds();
  const bool terminal = isatty(fileno(stderr));
  while (next < todo.size() || !running.empty()) {
    while (next < todo.size() && int(running.size()) < std::max(1, jobs)) {
      const PlannedRun* r = todo[next++];
      running[spawn(r->command(exe, out_dir, plan.dump_formats, plan.checkpoints),
                    (logs / (r->id + ".log")).string())] = r;
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) break;
    auto it = running.find(pid);
    if (it == running.end()) continue;
    const PlannedRun* r = it->second;
    running.erase(it);
    ++done;
    ++report.ran;
    if (!record_complete(run_dir(out_dir, *r))) {
      ++report.failed_to_record;
      const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      const std::string log = (logs / (r->id + ".log")).string();
      write_refusal(run_dir(out_dir, *r), code, last_line_of(log));
      std::fprintf(stderr, "%sapiclab: sweep: run %s (%s) refused, no record (exit %d); see %s\n",
                   quiet || !terminal ? "" : "\n", r->id.c_str(), r->label().c_str(), code,
                   log.c_str());
    }
    if (!quiet) {
      const double elapsed = now_seconds() - start;
      // A terminal gets one line rewritten in place; a log file or pipe plain lines, no \r.
      std::fprintf(stderr,
                   terminal ? "\rapiclab: sweep: %zu/%zu runs, %.0f s, ETA %.0f s   "
                            : "apiclab: sweep: %zu/%zu runs, %.0f s, ETA %.0f s\n",
                   done, todo.size(), elapsed, elapsed / double(done) * double(todo.size() - done));
    }
  }
  if (!quiet && terminal && !todo.empty()) std::fprintf(stderr, "\n");
  return report;
}

void export_jobs(const Plan& plan, const std::string& out_dir, const std::string& file) {
  cli::ensure_writable_file(file);
  std::ostringstream out;  // written whole (app/output_file.hpp)
  const std::string exe = self_executable();
  const std::string dir = fs::absolute(out_dir).string();
  SweepCheckpoints checkpoints = plan.checkpoints;  // a line runs from any folder
  if (!checkpoints.dir.empty()) checkpoints.dir = fs::absolute(checkpoints.dir).string();
  for (const PlannedRun& r : plan.runs) {
    std::string line;
    for (const std::string& a : r.command(exe, dir, plan.dump_formats, checkpoints))
      line += (line.empty() ? "" : " ") + shell_quote(a);
    out << line << '\n';
  }
  write_file_whole(file, out.str());
}

}  // namespace apiclab::sweep
