#include "app/output_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <utility>

namespace apiclab {
namespace {

// errno of a failed call; EIO when it failed without saying why.
int last_error() { return errno != 0 ? errno : EIO; }

int open_for_writing(const std::string& path) {
  errno = 0;
  return ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
}

// Writes every byte (a short write continues where it stopped); 0, or the errno that stopped it.
int write_all(int fd, std::string_view bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    errno = 0;
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return last_error();
    done += std::size_t(n);
  }
  return 0;
}

}  // namespace

WriteError::WriteError(const std::string& file, int errno_value)
    : std::runtime_error("cannot write " + file + ": " + std::strerror(errno_value)) {}

std::string temporary_name_of(const std::string& path) { return path + ".part"; }

void write_file_whole(const std::string& path, const std::string& bytes) {
  const std::initializer_list<std::string_view> whole = {bytes};
  write_file_whole(path, whole);
}

void write_file_whole(const std::string& path, std::initializer_list<std::string_view> pieces) {
  const std::string temp = temporary_name_of(path);
  const int fd = open_for_writing(temp);
  if (fd < 0) throw WriteError(path, last_error());
  int error = 0;
  for (auto piece = pieces.begin(); piece != pieces.end() && error == 0; ++piece)
    error = write_all(fd, *piece);
  errno = 0;
  if (::close(fd) != 0 && error == 0) error = last_error();
  errno = 0;
  if (error == 0 && std::rename(temp.c_str(), path.c_str()) != 0) error = last_error();
  if (error != 0) {
    std::remove(temp.c_str());
    throw WriteError(path, error);
  }
}

void write_file_whole(const std::string& path, const std::function<void(std::ostream&)>& fill) {
  std::ostringstream bytes(std::ios::binary);
  fill(bytes);
  write_file_whole(path, bytes.str());
}

RowFile::RowFile(std::string path) : path_(std::move(path)), fd_(open_for_writing(path_)) {
  if (fd_ < 0) throw WriteError(path_, last_error());
}

RowFile::RowFile(std::string path, std::size_t keep) : path_(std::move(path)), size_(keep) {
  errno = 0;
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd_ < 0) throw WriteError(path_, last_error());
  if (::ftruncate(fd_, off_t(keep)) != 0 || ::lseek(fd_, off_t(keep), SEEK_SET) < 0) {
    const int error = last_error();
    ::close(fd_);
    fd_ = -1;
    throw WriteError(path_, error);
  }
}

RowFile::RowFile(RowFile&& other) noexcept
    : path_(std::move(other.path_)),
      fd_(std::exchange(other.fd_, -1)),
      size_(std::exchange(other.size_, 0)) {}

RowFile& RowFile::operator=(RowFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(other.path_);
    fd_ = std::exchange(other.fd_, -1);
    size_ = std::exchange(other.size_, 0);
  }
  return *this;
}

RowFile::~RowFile() {
  if (fd_ >= 0) ::close(fd_);
}

void RowFile::write_row(const std::string& row) {
  if (fd_ < 0) return;
  if (const int error = write_all(fd_, row); error != 0) {
    // A row the disk took only in part is cut off again: the file ends after its last whole row.
    if (::ftruncate(fd_, off_t(size_)) == 0) ::lseek(fd_, off_t(size_), SEEK_SET);
    throw WriteError(path_, error);
  }
  size_ += row.size();
}

}  // namespace apiclab
