// Output files that are whole or absent: a frame file or a summary goes to a temporary name
// beside its final one and is renamed when complete; a row file (diagnostics CSV, frames.csv)
// takes one whole row per write and is flushed after it, so it never ends mid-row. Any failed
// write (short write, ENOSPC, EFBIG, a failed close or rename) throws WriteError:
// "cannot write FILE: REASON".
#pragma once
#include <cstddef>
#include <functional>
#include <initializer_list>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace apiclab {

struct WriteError : std::runtime_error {
  // REASON is strerror(errno_value).
  WriteError(const std::string& file, int errno_value);
  // A writer that says it in its own words: "cannot write FILE: REASON".
  explicit WriteError(const std::string& message) : std::runtime_error(message) {}
};

// The temporary name of `path` while it is written: `path.part`, in the same folder.
std::string temporary_name_of(const std::string& path);

// Writes `bytes` to path's temporary name, then renames it to `path`; on failure the temporary
// file is removed and WriteError names `path`.
void write_file_whole(const std::string& path, const std::string& bytes);
// The same with `pieces` one after another, each written from where it lies (no joined copy).
void write_file_whole(const std::string& path, std::initializer_list<std::string_view> pieces);
// The same with the bytes `fill` puts on a stream (formatted in memory first).
void write_file_whole(const std::string& path, const std::function<void(std::ostream&)>& fill);

// A file written one whole row at a time, unbuffered: each row goes to the file in one write,
// is checked, and a row written only in part is cut off again.
class RowFile {
 public:
  RowFile() = default;
  explicit RowFile(std::string path);  // truncates; WriteError when it cannot be created
  // Continues an existing file after its first `keep` bytes (a resumed run: what follows them
  // is cut off); WriteError when it cannot be opened or cut.
  RowFile(std::string path, std::size_t keep);
  RowFile(RowFile&& other) noexcept;
  RowFile& operator=(RowFile&& other) noexcept;
  RowFile(const RowFile&) = delete;
  RowFile& operator=(const RowFile&) = delete;
  ~RowFile();

  bool is_open() const { return fd_ >= 0; }
  std::size_t size() const { return size_; }  // bytes of whole rows in the file
  const std::string& path() const { return path_; }
  // Writes `row` (its newline included); WriteError when any byte is not written.
  void write_row(const std::string& row);

 private:
  std::string path_;
  int fd_ = -1;
  std::size_t size_ = 0;  // bytes of whole rows written
};

}  // namespace apiclab
