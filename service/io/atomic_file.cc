#include "service/io/atomic_file.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>
#include <regex>

namespace monocle {
namespace {

namespace fs = std::filesystem;

std::string Why() { return std::strerror(errno); }

fs::path DirectoryOf(const fs::path& target) {
  return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

// One open file descriptor, closed once.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd = -1) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }
  bool valid() const { return fd_ >= 0; }
  // Closes now, for the error close reports (a deferred write error).
  bool Close() {
    const int fd = fd_;
    fd_ = -1;
    return ::close(fd) == 0;
  }

 private:
  int fd_;
};

// The new contents of `target`, unnamed (or named `path` when the file system has no unnamed
// files), locked while it lives; unlinked unless renamed over the target.
class TemporaryFile {
 public:
  static Result<TemporaryFile> Create(const fs::path& target) {
    TemporaryFile t;
    t.target_ = target;
    const fs::path dir = DirectoryOf(target);
    t.fd_ = std::make_unique<FileDescriptor>(::open(dir.c_str(), O_TMPFILE | O_WRONLY, 0644));
    if (!t.fd_->valid()) {
      if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL)
        return MakeError(ErrorCode::kIo, "cannot write in '" + dir.string() + "': " + Why());
      std::string name = (dir / ("." + target.filename().string() + ".XXXXXX")).string();
      t.fd_ = std::make_unique<FileDescriptor>(mkstemp(name.data()));
      if (!t.fd_->valid())
        return MakeError(ErrorCode::kIo, "cannot create a temporary file next to '" +
                                             target.string() + "': " + Why());
      t.named_ = name;
    }
    // Held until the descriptor closes, also by the kernel for a writer that is killed.
    ::flock(t.fd_->get(), LOCK_EX);
    return t;
  }
  TemporaryFile(TemporaryFile&&) = default;
  ~TemporaryFile() {
    if (!named_.empty()) ::unlink(named_.c_str());
  }

  Status Write(const std::string& contents) {
    size_t written = 0;
    while (written < contents.size()) {
      const ssize_t n = ::write(fd_->get(), contents.data() + written, contents.size() - written);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0)
        return MakeError(ErrorCode::kIo, "cannot write '" + target_.string() + "': " + Why());
      written += static_cast<size_t>(n);
    }
    fchmod(fd_->get(), 0644);
    if (::fsync(fd_->get()) != 0)
      return MakeError(ErrorCode::kIo, "cannot flush '" + target_.string() + "': " + Why());
    return Ok{};
  }

  // Names the file (if unnamed) and renames it over the target, then lets the lock go.
  Status Commit() {
    if (named_.empty()) {
      if (Status s = GiveName(); !s) return s;
    }
    if (std::rename(named_.c_str(), target_.c_str()) != 0)
      return MakeError(ErrorCode::kIo, "cannot replace '" + target_.string() + "': " + Why());
    named_.clear();
    if (!fd_->Close())
      return MakeError(ErrorCode::kIo, "cannot close '" + target_.string() + "': " + Why());
    return Ok{};
  }

 private:
  TemporaryFile() = default;

  Status GiveName() {
    const std::string fd_path = "/proc/self/fd/" + std::to_string(fd_->get());
    std::random_device random;
    static const char kLetters[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    for (int attempt = 0; attempt < 100; ++attempt) {
      std::string suffix(6, 'X');
      for (char& c : suffix) c = kLetters[random() % (sizeof kLetters - 1)];
      const fs::path name =
          DirectoryOf(target_) / ("." + target_.filename().string() + "." + suffix);
      if (::linkat(AT_FDCWD, fd_path.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0) {
        named_ = name.string();
        return Ok{};
      }
      if (errno != EEXIST) break;
    }
    return MakeError(ErrorCode::kIo, "cannot name the new '" + target_.string() + "': " + Why());
  }

  fs::path target_;
  std::unique_ptr<FileDescriptor> fd_;
  std::string named_;  // the temporary's name while it has one
};

}  // namespace

Status WriteFileAtomically(const std::string& path, const std::string& contents) {
  RemoveStaleTemporaries(path);
  auto file = TemporaryFile::Create(path);
  if (!file) return file.error();
  if (Status s = file->Write(contents); !s) return s;
  return file->Commit();
}

int RemoveStaleTemporaries(const std::string& path) {
  const fs::path target(path);
  std::error_code error;
  fs::directory_iterator it(DirectoryOf(target), error);
  if (error) return 0;
  const std::regex temporary("\\." +
                             std::regex_replace(target.filename().string(),
                                                std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") +
                             "\\.[A-Za-z0-9]{6}");
  int removed = 0;
  for (const fs::directory_entry& entry : it) {
    if (!std::regex_match(entry.path().filename().string(), temporary)) continue;
    FileDescriptor fd(::open(entry.path().c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC));
    // Nobody holds it: its writer was killed before renaming it.
    if (fd.valid() && ::flock(fd.get(), LOCK_EX | LOCK_NB) == 0 &&
        ::unlink(entry.path().c_str()) == 0)
      ++removed;
  }
  return removed;
}

}  // namespace monocle
