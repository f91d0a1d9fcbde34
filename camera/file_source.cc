#include "camera/file_source.h"

#include <algorithm>
#include <filesystem>

#include "service/io/image_file.h"

namespace monocle {

Result<std::unique_ptr<FileSource>> FileSource::Open(const std::vector<std::string>& paths,
                                                     bool loop) {
  std::unique_ptr<FileSource> src(new FileSource());
  src->loop_ = loop;
  std::error_code ec;
  if (paths.size() == 1 && std::filesystem::is_directory(paths[0], ec)) {
    for (const auto& e : std::filesystem::directory_iterator(paths[0], ec)) {
      if (e.is_regular_file() && LooksLikeImageFile(e.path().string()))
        src->files_.push_back(e.path().string());
    }
    std::sort(src->files_.begin(), src->files_.end());
    src->id_ = paths[0];
  } else {
    src->files_ = paths;
    src->id_ = paths.empty() ? "" : paths[0];
  }
  if (src->files_.empty()) {
    return MakeError(ErrorCode::kNotFound, "no images to replay in '" + src->id_ + "'");
  }
  return src;
}

Result<Frame> FileSource::Next(std::chrono::milliseconds) {
  if (next_ >= files_.size()) {
    if (!loop_) return MakeError(ErrorCode::kNotFound, "end of the replayed images");
    next_ = 0;
  }
  const std::string& path = files_[next_++];
  Frame f;
  auto grey = ReadGreyImageFile(path);
  f.sequence = sequence_++;
  if (!grey) return grey.error();
  f.grey = std::move(grey).value();
  f.camera_id = id_;
  f.capture_time_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                          std::chrono::system_clock::now().time_since_epoch())
                          .count();
  f.time_source = TimeSource::kHost;
  return f;
}

}  // namespace monocle
