// Frames from image files, for replay: a folder (its images in name order) or a list of
// files, optionally looping. Any format OpenCV reads; frames are 8-bit grey.
#pragma once

#include <string>
#include <vector>

#include "camera/frame_source.h"

namespace monocle {

class FileSource : public FrameSource {
 public:
  // `paths`: files, or one folder. Fails if there is no readable image among them.
  static Result<std::unique_ptr<FileSource>> Open(const std::vector<std::string>& paths, bool loop);

  const std::string& id() const override { return id_; }
  // The next image (sequence = its index from 0, host time of reading); kNotFound at the
  // end of a non-looping list; kIo for a file that cannot be read (the next call moves on).
  Result<Frame> Next(std::chrono::milliseconds timeout) override;

 private:
  std::string id_;
  std::vector<std::string> files_;
  bool loop_ = false;
  size_t next_ = 0;
  uint64_t sequence_ = 0;
};

}  // namespace monocle
