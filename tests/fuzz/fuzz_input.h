// Shared by the fuzz targets: a floor camera's calibration to answer queries with, and a
// reader that builds typed values from fuzz bytes (like LLVM's FuzzedDataProvider, which
// Debian ships only with clang, while the CI smoke builds these with gcc).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

#include "service/io/calibration_file.h"
#include "tests/fuzz/fuzz_check.h"

namespace monocle::fuzz {

// A 1280 x 1024 floor camera 1.05 m above the floor, pitched 35°, with covariances.
inline const CameraCalibration& FloorCamera() {
  static const CameraCalibration calibration = [] {
    auto c = ParseCalibration(R"(
intrinsics { width: 1280 height: 1024 fx: 1100.5 fy: 1101.25 cx: 640.5 cy: 512.25
             distortion: [-0.12, 0.05, 0.001, -0.0005] }
floor { height: 1.05 pitch: 0.61 yaw: 0.01 roll: 0.002
        covariance: [1e-6, 0, 0, 0, 0, 1e-6, 0, 0, 0, 0, 1e-6, 0, 0, 0, 0, 1e-6] }
)",
                              "fuzz floor camera");
    FUZZ_CHECK(c.ok());
    return *c;
  }();
  return calibration;
}

class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  size_t left() const { return size_; }
  uint8_t Byte() { return Take<uint8_t>(); }
  uint32_t U32() { return Take<uint32_t>(); }
  int32_t I32() { return Take<int32_t>(); }
  uint64_t U64() { return Take<uint64_t>(); }
  // Any double, NaN and infinities included: they are what a hostile sender sends.
  double Double() { return Take<double>(); }
  std::string String(size_t max) {
    const size_t n = std::min<size_t>(Byte() % (max + 1), size_);
    std::string s(reinterpret_cast<const char*>(data_), n);
    data_ += n;
    size_ -= n;
    return s;
  }
  std::string Rest() {
    std::string s(reinterpret_cast<const char*>(data_), size_);
    data_ += size_;
    size_ = 0;
    return s;
  }

 private:
  template <typename T>
  T Take() {
    T v{};
    const size_t n = std::min(sizeof(T), size_);
    std::memcpy(&v, data_, n);
    data_ += n;
    size_ -= n;
    return v;
  }
  const uint8_t* data_;
  size_t size_;
};

}  // namespace monocle::fuzz
