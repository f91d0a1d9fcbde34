// A calibration file with Xu et al.'s camera and floor pose (height 1.05 m, pitch 2.0595 rad,
// yaw 0.0698, roll 0.0262), for services whose point answers a test checks.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "service/geometry/test_scenes.h"
#include "service/io/calibration_file.h"

namespace monocle::testing {

inline void WritePaperFloorCalibration(const std::string& path) {
  CameraCalibration cal;
  cal.intrinsics = PaperCamera();
  cal.floor = FloorCalibration{};
  cal.floor->pose = FloorPose{1.05, 2.0595, 0.0698, 0.0262};
  cal.floor->covariance = FloorCovariance::Identity() * 1e-8;
  ASSERT_TRUE(SaveCalibrationFileAtomically(path, cal).ok()) << path;
}

}  // namespace monocle::testing
