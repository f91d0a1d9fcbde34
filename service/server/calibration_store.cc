#include "service/server/calibration_store.h"

namespace monocle {

void CalibrationStore::Add(const std::string& camera_id, const CameraCalibration& calibration) {
  std::unique_lock<std::shared_mutex> lock(mutex_);
  calibrations_[camera_id] = calibration;
  revisions_[camera_id] = 1;
}

std::optional<CameraCalibration> CalibrationStore::Get(const std::string& camera_id) const {
  std::shared_lock<std::shared_mutex> lock(mutex_);
  const auto it = calibrations_.find(camera_id);
  if (it == calibrations_.end()) return std::nullopt;
  return it->second;
}

uint64_t CalibrationStore::Revision(const std::string& camera_id) const {
  std::shared_lock<std::shared_mutex> lock(mutex_);
  const auto it = revisions_.find(camera_id);
  return it == revisions_.end() ? 0 : it->second;
}

Result<uint64_t> CalibrationStore::Replace(const std::string& camera_id, const std::string& path,
                                           const CameraCalibration& calibration) {
  std::lock_guard<std::mutex> one_change(replace_mutex_);
  if (auto saved = SaveCalibrationFileAtomically(path, calibration); !saved) return saved.error();
  std::unique_lock<std::shared_mutex> lock(mutex_);
  calibrations_[camera_id] = calibration;
  return ++revisions_[camera_id];
}

}  // namespace monocle
