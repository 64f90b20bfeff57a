// `gui --heartbeat FILE`: after every pass of its event loop (a displayed frame, or a wait for
// events when nothing new is to be drawn) the viewer rewrites FILE with one line, "FRAME
// SECONDS" (frames drawn since start, monotonic wall clock), so a watchdog (tests/gui/gui_soak.sh)
// sees that the window thread is alive: answering events and drawing what changed. Written to
// FILE.tmp and renamed, so a reader never sees half a line.
#pragma once
#include <cstdio>
#include <filesystem>
#include <string>

namespace apiclab::gui {

class Heartbeat {
 public:
  explicit Heartbeat(std::string path) : path_(std::move(path)), tmp_(path_ + ".tmp") {}
  bool enabled() const { return !path_.empty(); }
  // A file that cannot be written is reported once on stderr; the viewer goes on without.
  void beat(long frame, double seconds) {
    if (path_.empty() || failed_) return;
    std::FILE* f = std::fopen(tmp_.c_str(), "w");
    bool ok = f && std::fprintf(f, "%ld %.6f\n", frame, seconds) > 0;
    if (f) ok = std::fclose(f) == 0 && ok;
    std::error_code ec;
    if (ok) std::filesystem::rename(tmp_, path_, ec);
    if (!ok || ec) {
      std::fprintf(stderr, "apiclab: --heartbeat: cannot write %s; no more heartbeats\n",
                   path_.c_str());
      failed_ = true;
    }
  }

 private:
  std::string path_, tmp_;
  bool failed_ = false;
};

}  // namespace apiclab::gui
