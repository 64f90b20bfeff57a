// Encoding rendered frames into a video with ffmpeg, run as a program (no shell).
#pragma once
#include <string>
#include <vector>

namespace apiclab::cli {

// The full path of an executable on PATH, or empty.
std::string find_on_path(const std::string& name);
// Runs a program without a shell; returns its exit status (-1 when it could not start). With
// `err_fd` >= 0 the program's stderr goes there.
int run_program(const std::vector<std::string>& args, int err_fd = -1);
// DIR/frame_0000.png, ... at `fps` into an H.264 MP4 `file`; throws UsageError when ffmpeg fails,
// with ffmpeg's last line quoted as the cause (its own lines are not printed).
void encode_video(const std::string& ffmpeg, const std::string& dir, double fps,
                  const std::string& file);

}  // namespace apiclab::cli
