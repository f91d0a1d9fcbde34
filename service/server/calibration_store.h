// The calibrations of the service's cameras while it runs: read by point queries (many at
// once), replaced by floor calibration commands (one at a time, written to the camera's file
// atomically before anyone sees it), each change numbered by a revision.
#pragma once

#include <map>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>

#include "service/io/calibration_file.h"

namespace monocle {

class CalibrationStore {
 public:
  void Add(const std::string& camera_id, const CameraCalibration& calibration);

  std::optional<CameraCalibration> Get(const std::string& camera_id) const;
  uint64_t Revision(const std::string& camera_id) const;

  // Runs `read` on the calibrations by camera id, under a shared lock (no copy per query).
  template <typename Reader>
  auto Read(Reader read) const {
    std::shared_lock<std::shared_mutex> lock(mutex_);
    return read(calibrations_);
  }

  // Saves `calibration` to `path` atomically, then makes it current; returns its revision.
  Result<uint64_t> Replace(const std::string& camera_id, const std::string& path,
                           const CameraCalibration& calibration);

 private:
  mutable std::shared_mutex mutex_;
  std::mutex replace_mutex_;  // one change at a time: file, then map, then revision
  std::map<std::string, CameraCalibration> calibrations_;
  std::map<std::string, uint64_t> revisions_;
};

}  // namespace monocle
