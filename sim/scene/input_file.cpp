#include "sim/scene/input_file.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sim/scene/message_text.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {

std::string path_error_text(const std::error_code& ec, const std::string& path) {
  if (ec == std::errc::filename_too_long)
    return "the path is too long (" + std::to_string(path.size()) +
           " characters; a name may hold 255, a path 4096)";
  return ec.message();
}

std::string input_file_problem(const std::string& path, const std::string& what) {
  namespace fs = std::filesystem;
  if (path.empty()) return "no " + what + " given (an empty path)";
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec == std::errc::filename_too_long) return path_error_text(ec, path);
  if (!fs::exists(st)) return "no such " + what;
  if (fs::is_directory(st)) return "is a directory, not a " + what;
  if (!fs::is_regular_file(st)) {
    const char* kind = fs::is_fifo(st)             ? "a fifo"
                       : fs::is_socket(st)         ? "a socket"
                       : fs::is_character_file(st) ? "a character device"
                       : fs::is_block_file(st)     ? "a block device"
                                                   : "a special file";
    return std::string("is ") + kind + ", not a regular " + what;
  }
  std::ifstream probe(path);
  if (!probe) return "cannot read " + what + ": " + std::strerror(errno);
  return "";
}

std::string read_input_file(const std::string& path, const std::string& what) {
  if (std::string problem = input_file_problem(path, what); !problem.empty())
    throw SceneError(path.empty() ? problem : message_text(path) + ": " + problem);
  std::ifstream in(path);
  std::stringstream buf;
  buf << in.rdbuf();
  if (in.bad())
    throw SceneError(message_text(path) + ": cannot read " + what + ": " + std::strerror(errno));
  return buf.str();
}

}  // namespace apiclab
