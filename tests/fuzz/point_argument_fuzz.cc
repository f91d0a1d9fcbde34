// Fuzz target: a POINT argument of `monocle floor measure` (u,v or u,v@fu,fv), parsed and
// then measured with a floor camera's calibration as the command does: every input gets a
// point with a finite 1 sigma, or an error that says why.
#include <cmath>
#include <cstdint>
#include <string>

#include "client/cli/args.h"
#include "service/pipeline/point_queries.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto point = monocle::cli::ParsePointArgument(text);
  if (!point) {
    FUZZ_CHECK(!point.error().message.empty());
    return 0;
  }
  FUZZ_CHECK(std::isfinite(point->u) && std::isfinite(point->v));  // others refused
  const std::map<std::string, monocle::CameraCalibration> cameras{
      {"floor", monocle::fuzz::FloorCamera()}};
  const auto answer =
      monocle::AnswerPointRequest(cameras, "floor", {*point}, monocle::kDefaultPixelSigmaPx);
  FUZZ_CHECK(answer.status == monocle::RequestStatus::kAnswered && answer.points.size() == 1);
  const auto& a = answer.points[0];
  if (a.status == monocle::PointStatus::kMeasured) {
    for (double v : a.p_robot_m) FUZZ_CHECK(std::isfinite(v));
    for (double v : a.covariance) FUZZ_CHECK(std::isfinite(v));
  } else {
    FUZZ_CHECK(!a.error.empty());  // every refusal says why
  }
  return 0;
}
