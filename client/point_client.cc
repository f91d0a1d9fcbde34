#include "client/point_client.h"

#include <unistd.h>

#include <chrono>
#include <optional>

#include "idl/monocle.h"
#include "service/server/dds.h"

namespace monocle::client {

Result<RequestAnswer> MeasurePoints(const std::string& camera, const std::vector<PixelPair>& points,
                                    double sigma, int domain, double timeout_s) {
  auto replies = dds::Endpoint<monocle_dds_PointReply>::Open(
      domain, &monocle_dds_PointReply_desc, dds::kPointReplyTopic, false, true, {1, true});
  if (!replies) return replies.error();
  auto requests = dds::Endpoint<monocle_dds_PointRequest>::Open(
      domain, &monocle_dds_PointRequest_desc, dds::kPointRequestTopic, true, false, {64, false});
  if (!requests) return requests.error();
  const auto timeout = std::chrono::milliseconds(static_cast<int64_t>(timeout_s * 1000));
  const Error no_service = MakeError(
      ErrorCode::kNotFound,
      "no answer from the monocle service on DDS domain " + std::to_string(domain) + " within " +
          std::to_string(static_cast<int>(timeout_s)) + " s: is monocled running?");
  if (!requests->WaitForReader(timeout)) return no_service;
  std::string client_id =
      "monocle-cli-" + std::to_string(::getpid()) + "-" +
      std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
  std::vector<monocle_dds_PixelQuery> queries;
  for (const auto& p : points) queries.push_back({p.u, p.v, p.paired, p.floor_u, p.floor_v});
  monocle_dds_PointRequest request{};
  request.client_id = client_id.data();
  request.request_id = 1;
  request.camera_id = const_cast<char*>(camera.c_str());
  request.pixel_sigma_px = sigma;
  request.points._buffer = queries.data();
  request.points._length = request.points._maximum = static_cast<uint32_t>(queries.size());
  request.points._release = false;
  if (auto w = requests->Write(request); !w) return w.error();
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    auto taken = replies->Take<std::optional<RequestAnswer>>(
        std::chrono::milliseconds(200),
        [&](const monocle_dds_PointReply& r) -> std::optional<RequestAnswer> {
          if (r.client_id == nullptr || client_id != r.client_id || r.request_id != 1)
            return std::nullopt;
          RequestAnswer a;
          a.status = static_cast<RequestStatus>(r.status);
          a.error = r.error != nullptr ? r.error : "";
          for (uint32_t i = 0; i < r.points._length; ++i) {
            const auto& q = r.points._buffer[i];
            PointAnswer p;
            p.status = static_cast<PointStatus>(q.status);
            p.error = q.error != nullptr ? q.error : "";
            p.measurement.p_robot_m = Eigen::Vector3d(q.x, q.y, q.z);
            p.measurement.covariance =
                Eigen::Vector3d(q.sigma[0], q.sigma[1], q.sigma[2]).cwiseAbs2().asDiagonal();
            a.points.push_back(std::move(p));
          }
          return a;
        });
    if (!taken) return taken.error();
    for (auto& a : *taken) {
      if (a) return std::move(*a);
    }
  }
  return no_service;
}

}  // namespace monocle::client
