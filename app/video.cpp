#include "app/video.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <sstream>

#include "cli.hpp"

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

int run_program(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void encode_video(const std::string& ffmpeg, const std::string& dir, double fps,
                  const std::string& file) {
  const int status =
      run_program({ffmpeg, "-y", "-loglevel", "error", "-framerate", std::to_string(fps), "-i",
                   dir + "/frame_%04d.png", "-c:v", "libx264", "-pix_fmt", "yuv420p", "-vf",
                   "pad=ceil(iw/2)*2:ceil(ih/2)*2", file});
  if (status != 0)
    throw UsageError("ffmpeg failed (exit " + std::to_string(status) + ") encoding " + file);
}

}  // namespace apiclab::cli
