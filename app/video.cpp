#include "app/video.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <sstream>

#include "cli.hpp"
#include "sim/scene/message_text.hpp"

extern char** environ;

namespace apiclab::cli {

std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    std::string candidate = (dir.empty() ? "." : dir) + "/" + name;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

int run_program(const std::vector<std::string>& args, int err_fd) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (err_fd >= 0) posix_spawn_file_actions_adddup2(&actions, err_fd, STDERR_FILENO);
  pid_t pid = 0;
  const int started = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (started != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

namespace {

// The last non-empty line of what was written to `fd`, cut to one readable line.
std::string last_line_of(int fd) {
  std::string text(4096, '\0');
  const off_t size = lseek(fd, 0, SEEK_END);
  const off_t from = size > off_t(text.size()) ? size - off_t(text.size()) : 0;
  const ssize_t n = pread(fd, text.data(), text.size(), from);
  text.resize(n > 0 ? std::size_t(n) : 0);
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return message_text(text.substr(text.find_last_of("\r\n") + 1));
}

}  // namespace

void encode_video(const std::string& ffmpeg, const std::string& dir, double fps,
                  const std::string& file) {
  char log[] = "/tmp/apiclab-ffmpeg-XXXXXX";
  const int fd = mkstemp(log);
  if (fd >= 0) unlink(log);  // read back through the descriptor, gone when it closes
  const int status =
      run_program({ffmpeg, "-y", "-nostdin", "-loglevel", "error", "-framerate",
                   std::to_string(fps), "-i", dir + "/frame_%04d.png", "-c:v", "libx264",
                   "-pix_fmt", "yuv420p", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", file},
                  fd);
  const std::string cause = status != 0 && fd >= 0 ? last_line_of(fd) : "";
  if (fd >= 0) close(fd);
  if (status != 0)
    throw UsageError("ffmpeg failed (exit " + std::to_string(status) + ") encoding " + file +
                     (cause.empty() ? "" : ": " + cause));
}

}  // namespace apiclab::cli
