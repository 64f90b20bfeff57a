// Input files (scenes, meshes) are opened only when they are regular, readable files: a
// directory or a fifo would otherwise block or read as garbage.
#pragma once
#include <string>
#include <system_error>

namespace apiclab {

// Reads the whole file. Throws SceneError "<path>: <what> ..." when the path does not exist, is a
// directory, is not a regular file (fifo, socket, device) or cannot be read. `what` names the
// file's role ("scene file", "mesh file").
std::string read_input_file(const std::string& path, const std::string& what);

// The same checks without reading; empty when the file can be read, else the reason.
std::string input_file_problem(const std::string& path, const std::string& what);

// Why a path could not be used, in the project's words: the system's own text ("File name too
// long") names no limit, and a 30 kB name is its usual cause.
std::string path_error_text(const std::error_code& ec, const std::string& path);

}  // namespace apiclab
