// Fuzz target: monocled's request handlers fed with samples decoded from fuzz bytes the way
// Cyclone DDS decodes a received sample (dds_stream_normalize_data checks the CDR, then
// dds_stream_read builds the C sample), then the handler's own code (point queries, pose
// queries, floor calibration) and its reply, which is serialized as the reply writer would
// and decoded again as the client library would.
//
// Input: byte 0 picks the service (points, pose, floor calibration); byte 1 picks raw CDR
// (the rest is the XCDR1 little-endian body of a request) or a well-formed request built
// from the rest (deep coverage without a seed corpus of binary samples).
#include <dds/dds.h>
#include <dds/ddsi/ddsi_cdrstream.h>
#include <dds/ddsi/q_protocol.h>

#include <cstdint>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "service/server/floor_calibration_handler.h"
#include "service/server/point_query_handler.h"
#include "service/server/pose_query_handler.h"
#include "tests/fuzz/fuzz_input.h"

namespace monocle {
namespace {

// A C sample of `desc`'s type, freed with Cyclone's own free (as dds_return_loan would).
template <typename Sample>
struct Decoded {
  explicit Decoded(const dds_topic_descriptor_t* d) : desc(d) { std::memset(&s, 0, sizeof(s)); }
  ~Decoded() {
    if (ok) dds_stream_free_sample(&s, desc->m_ops);
  }
  Decoded(const Decoded&) = delete;
  Decoded& operator=(const Decoded&) = delete;
  const dds_topic_descriptor_t* desc;
  Sample s;
  bool ok = false;
};

// The receive path: CDR checked (bounds, string terminators, sequence lengths) and decoded.
template <typename Sample>
bool Decode(std::vector<unsigned char> cdr, Decoded<Sample>* out) {
  // Cyclone hands on no empty payload (a sample has at least its encapsulation header).
  if (cdr.empty() || cdr.size() > (1u << 24)) return false;
  uint32_t end = 0;
  const auto size = static_cast<uint32_t>(cdr.size());
  if (dds_stream_normalize_data(reinterpret_cast<char*>(cdr.data()), &end, size, false,
                                CDR_ENC_VERSION_1, out->desc->m_ops) == nullptr)
    return false;
  dds_istream_t is;
  dds_istream_init(&is, size, cdr.data(), CDR_ENC_VERSION_1);
  dds_stream_read(&is, reinterpret_cast<char*>(&out->s), out->desc->m_ops);
  dds_istream_fini(&is);
  out->ok = true;
  return true;
}

// The rest of the fuzz bytes as a received sample's CDR body.
template <typename Sample>
bool DecodeRest(fuzz::Bytes& in, Decoded<Sample>* out) {
  const std::string rest = in.Rest();
  return Decode(std::vector<unsigned char>(rest.begin(), rest.end()), out);
}

// The send path: the sample as the writer serializes it.
template <typename Sample>
std::vector<unsigned char> Encode(const Sample& s, const dds_topic_descriptor_t* desc) {
  dds_ostream_t os;
  dds_ostream_init(&os, 0, CDR_ENC_VERSION_1);
  dds_stream_write(&os, reinterpret_cast<const char*>(&s), desc->m_ops);
  std::vector<unsigned char> out(os.m_buffer, os.m_buffer + os.m_index);
  dds_ostream_fini(&os);
  return out;
}

const CalibrationStore& Store() {
  static const CalibrationStore* store = [] {
    auto* s = new CalibrationStore();
    s->Add("floor", fuzz::FloorCamera());
    return s;
  }();
  return *store;
}

const CameraSetup& Camera() {
  static const CameraSetup camera = [] {
    CameraSetup c;
    c.id = "floor";
    c.ros_parent_frame = "corner";
    return c;
  }();
  return camera;
}

// A small floor camera (320 x 256) and a chessboard of 11 x 8 squares (16 px) in its frame:
// board detection on the full 1280 x 1024 frame held the target to ~20 inputs a second.
const CameraCalibration& SmallCamera() {
  static const CameraCalibration camera = [] {
    CameraCalibration c = fuzz::FloorCamera();
    c.intrinsics.width_px = 320;
    c.intrinsics.height_px = 256;
    c.intrinsics.fx /= 4;
    c.intrinsics.fy /= 4;
    c.intrinsics.cx = 160;
    c.intrinsics.cy = 128;
    return c;
  }();
  return camera;
}

const Frame& BoardFrame() {
  static const Frame frame = [] {
    Frame f;
    f.grey = cv::Mat(256, 320, CV_8UC1, cv::Scalar(128));
    for (int r = 0; r < 8; ++r)
      for (int c = 0; c < 11; ++c)
        cv::rectangle(f.grey, cv::Rect(72 + 16 * c, 64 + 16 * r, 16, 16),
                      cv::Scalar((r + c) % 2 ? 230 : 20), cv::FILLED);
    f.sequence = 7;
    return f;
  }();
  return frame;
}

void PointRequest(fuzz::Bytes& in, bool raw) {
  Decoded<monocle_msgs_srv_dds__MeasurePoints_Request_> request(
      &monocle_msgs_srv_dds__MeasurePoints_Request__desc);
  if (raw) {
    if (!DecodeRest(in, &request)) return;
  } else {
    std::vector<double> cols[4];
    const size_t n = in.Byte() % 40;
    for (auto& col : cols) {
      col.resize(in.Byte() % 3 == 0 ? in.Byte() % 40 : n);  // columns that disagree, sometimes
      for (auto& x : col) x = in.Byte() % 4 == 0 ? in.Double() : 1280.0 * in.Byte() / 255.0;
    }
    monocle_msgs_srv_dds__MeasurePoints_Request_ built{};
    built.guid = in.U64();
    built.seq = static_cast<int64_t>(in.U64());
    built.pixel_sigma_px = in.Byte() % 2 ? in.Double() : 0.5;
    dds_sequence_double* seqs[4] = {&built.u, &built.v, &built.foot_u, &built.foot_v};
    for (int i = 0; i < 4; ++i) {
      seqs[i]->_length = seqs[i]->_maximum = static_cast<uint32_t>(cols[i].size());
      seqs[i]->_buffer = cols[i].data();
    }
    FUZZ_CHECK(Decode(Encode(built, request.desc), &request));  // ours must decode
  }
  const auto query = PointQueryHandler::Parse(request.s);
  PointQueryHandler::Reply reply;
  PointQueryHandler::AnswerInto(query, "floor", Store(), &reply);
  Decoded<monocle_msgs_srv_dds__MeasurePoints_Response_> received(
      &monocle_msgs_srv_dds__MeasurePoints_Response__desc);
  FUZZ_CHECK(Decode(Encode(reply.sample, received.desc), &received));
  if (received.s.status == monocle_msgs_msg_dds__REQUEST_OK) {
    const auto points = wire::FromSample(received.s);
    FUZZ_CHECK(query.pixels && points && points->size() == query.pixels->size());
    for (const auto& p : *points)  // what the client receives says why a point failed
      FUZZ_CHECK(p.status == MeasuredPoint::Status::kMeasured || !p.error.empty());
  } else {
    FUZZ_CHECK(received.s.error != nullptr && received.s.error[0] != 0);  // a refusal says why
  }
}

void PoseRequest(fuzz::Bytes& in, bool raw) {
  Decoded<monocle_msgs_srv_dds__GetPose_Request_> request(
      &monocle_msgs_srv_dds__GetPose_Request__desc);
  if (raw) {
    if (!DecodeRest(in, &request)) return;
  } else {
    monocle_msgs_srv_dds__GetPose_Request_ built{};
    built.guid = in.U64();
    // Any 32 bits, as a sender may put there (copied: an enum may not hold other values).
    const uint32_t which = in.U32();
    static_assert(sizeof(built.which) == sizeof(which));
    std::memcpy(&built.which, &which, sizeof(which));
    // Cyclone refuses an enum value outside the IDL's on receive: never reaches the handler.
    if (!Decode(Encode(built, request.desc), &request)) {
      FUZZ_CHECK(which > 1);
      return;
    }
  }
  const uint32_t which = PoseQueryHandler::Parse(request.s);
  const std::string invalid = PoseQueryHandler::InvalidWhich(which);
  FUZZ_CHECK(invalid.empty() == (which <= 1));
  // A pose as the corner tracker makes it, with whatever values (NaN too) the bytes give.
  Pose pose = PoseQueryHandler::NoPose(Camera());
  pose.x_m = in.Double();
  pose.pan_rad = in.Double();
  pose.error = in.String(64);
  pose.valid = in.Byte() % 2;
  monocle_msgs_srv_dds__GetPose_Response_ reply;
  PoseQueryHandler::ReplyInto(
      invalid.empty() ? monocle_msgs_msg_dds__REQUEST_OK : monocle_msgs_msg_dds__REQUEST_INVALID,
      invalid, pose, &reply);
  Decoded<monocle_msgs_srv_dds__GetPose_Response_> received(
      &monocle_msgs_srv_dds__GetPose_Response__desc);
  FUZZ_CHECK(Decode(Encode(reply, received.desc), &received));
  FUZZ_CHECK(wire::FromSample(received.s.pose).camera_id == "floor");
}

void FloorCalibrationRequest(fuzz::Bytes& in, bool raw) {
  Decoded<monocle_msgs_srv_dds__CalibrateFloor_Request_> request(
      &monocle_msgs_srv_dds__CalibrateFloor_Request__desc);
  if (raw) {
    if (!DecodeRest(in, &request)) return;
  } else {
    monocle_msgs_srv_dds__CalibrateFloor_Request_ built{};
    built.board_cols = in.Byte() % 2 ? in.I32() : in.Byte() % 16;
    built.board_rows = in.Byte() % 2 ? in.I32() : in.Byte() % 16;
    built.square_m = in.Byte() % 2 ? in.Double() : 0.05;
    FUZZ_CHECK(Decode(Encode(built, request.desc), &request));
  }
  const auto board =
      FloorCalibrationHandler::CheckRequest(FloorCalibrationHandler::Parse(request.s));
  if (!board) {
    FUZZ_CHECK(!board.error().message.empty());
    return;
  }
  // Finding a chessboard costs tens of milliseconds: only for boards that could be on it.
  if (board->cols > 16 || board->rows > 16) return;
  const auto result = FloorCalibrationHandler::CalibrateFrame(BoardFrame(), SmallCamera(), *board);
  FUZZ_CHECK(result || !result.error().message.empty());
}

}  // namespace
}  // namespace monocle

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  monocle::fuzz::Bytes in(data, size);
  const uint8_t kind = in.Byte();
  const bool raw = in.Byte() % 2 == 0;
  switch (kind % 3) {
    case 0:
      monocle::PointRequest(in, raw);
      break;
    case 1:
      monocle::PoseRequest(in, raw);
      break;
    default:
      monocle::FloorCalibrationRequest(in, raw);
      break;
  }
  return 0;
}
