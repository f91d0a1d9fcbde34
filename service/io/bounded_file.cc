#include "service/io/bounded_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace monocle {
namespace {

// The descriptor, closed on every path out.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

std::string Megabytes(size_t bytes) { return std::to_string(bytes >> 20) + " MB"; }

}  // namespace

Result<size_t> ReadBoundedFileInto(const std::string& path, const std::string& what,
                                   size_t max_bytes,
                                   const std::function<char*(size_t size)>& buffer_of_size) {
  // O_NONBLOCK: opening a FIFO nobody writes to must not hang; regular files ignore it.
  FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK));
  if (fd.get() < 0) {
    return MakeError(ErrorCode::kNotFound,
                     "cannot read " + what + " '" + path + "': " +
                         (errno == ENOENT ? "no such file" : std::string(std::strerror(errno))));
  }
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) {
    return MakeError(ErrorCode::kIo,
                     "cannot read " + what + " '" + path + "': " + std::strerror(errno));
  }
  if (!S_ISREG(st.st_mode)) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "cannot read " + what + " '" + path +
                         "': not a regular file (a device, FIFO or directory); name a file");
  }
  if (static_cast<uint64_t>(st.st_size) > max_bytes) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "cannot read " + what + " '" + path + "': " + std::to_string(st.st_size) +
                         " bytes is more than the " + Megabytes(max_bytes) + " a " + what +
                         " may have");
  }
  const size_t size = static_cast<size_t>(st.st_size);
  char* buffer = buffer_of_size(size);
  size_t done = 0;
  // Never more than the size checked above, even if the file grows while we read.
  while (done < size) {
    const ssize_t n = ::read(fd.get(), buffer + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      return MakeError(ErrorCode::kIo,
                       "cannot read " + what + " '" + path + "': " + std::strerror(errno));
    }
    if (n == 0) break;  // shrank meanwhile: what is there
    done += static_cast<size_t>(n);
  }
  return done;
}

Result<std::string> ReadBoundedFile(const std::string& path, const std::string& what,
                                    size_t max_bytes) {
  std::string text;
  const auto read = ReadBoundedFileInto(path, what, max_bytes, [&](size_t size) {
    text.resize(size);
    return text.data();
  });
  if (!read) return read.error();
  text.resize(*read);
  return text;
}

}  // namespace monocle
