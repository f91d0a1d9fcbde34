#include "service/server/point_query_handler.h"

#include <malloc.h>

#include <iostream>

#include "service/pipeline/point_queries.h"

static_assert(monocle::kMaxPointsPerRequest == monocle::wire::kMaxPointsPerRequest,
              "the core answers as many points as the wire carries");

namespace monocle {

Result<std::unique_ptr<PointQueryHandler>> PointQueryHandler::Start(
    const std::shared_ptr<dds::Entity>& participant, const std::vector<CameraSetup>& cameras,
    const CalibrationStore& calibrations) {
  std::unique_ptr<PointQueryHandler> h(new PointQueryHandler(calibrations));
  auto server = Server::Start(
      participant, CamerasWith(cameras, &CameraSetup::floor),
      &monocle_msgs_srv_dds__MeasurePoints_Request__desc,
      &monocle_msgs_srv_dds__MeasurePoints_Response__desc, wire::kMeasurePoints,
      &PointQueryHandler::Parse,
      [self = h.get()](Server::Incoming&& in) { self->Answer(std::move(in)); },
      // Up to 1000 points take under a millisecond: answered as they arrive.
      [](const Query& q) { return !q.pixels || q.pixels->size() <= kQuickPoints; });
  if (!server) return server.error();
  h->server_ = std::move(server).value();
  return h;
}

PointQueryHandler::Query PointQueryHandler::Parse(
    const monocle_msgs_srv_dds__MeasurePoints_Request_& r) {
  // Too many points is refused before their copies cost memory.
  if (r.u._length > kMaxPointsPerRequest) {
    return Query{MakeError(ErrorCode::kInvalidArgument,
                           "too many points in one request (" + std::to_string(r.u._length) +
                               " > " + std::to_string(kMaxPointsPerRequest) + "): split it"),
                 r.pixel_sigma_px};
  }
  return Query{wire::FromSample(r), r.pixel_sigma_px};
}

void PointQueryHandler::AnswerInto(const Query& query, const std::string& camera_id,
                                   const CalibrationStore& calibrations, Reply* reply) {
  auto status = monocle_msgs_msg_dds__REQUEST_OK;
  std::string& error = reply->error;
  std::vector<MeasuredPoint>& points = reply->points;
  if (!query.pixels) {
    status = monocle_msgs_msg_dds__REQUEST_INVALID;
    error = query.pixels.error().message;
  } else {
    RequestAnswer answer = calibrations.Read([&](const auto& cameras) {
      return AnswerPointRequest(cameras, camera_id, *query.pixels, query.pixel_sigma_px);
    });
    if (answer.status != RequestStatus::kAnswered) {
      status = monocle_msgs_msg_dds__REQUEST_INVALID;
      error = answer.error;
    }
    points = std::move(answer.points);
  }
  wire::ToSample(status, error, points, &reply->columns, &reply->sample);
}

void PointQueryHandler::Answer(Server::Incoming&& in) {
  {
    Reply reply;
    AnswerInto(in.value, in.camera->id, calibrations_, &reply);
    if (auto s = in.server->SendReply(reply.sample, in.header); !s)
      std::cerr << "monocled: " << s.error() << "\n";
  }
  // A large request's memory (its copy, the answer, the reply's columns: tens of MB) is free
  // now, but glibc keeps freed memory in the arena of the thread that took it, for good: eight
  // clients' large requests at once left monocled hundreds of MB bigger. Given back here.
  if (in.value.pixels && in.value.pixels->size() > kQuickPoints) {
    in.value.pixels = std::vector<PixelQuery>();  // the request's copy, freed first
    malloc_trim(0);
  }
}

}  // namespace monocle
