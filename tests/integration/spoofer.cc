// A participant that pretends, on plain DDS, to be what it is not: it publishes a camera
// status claiming a camera namespace, or corner poses on a camera's topic, as a spoofer on
// the robot's network would. For the tests of what clients and the service make of it.
//   spoofer --domain D status NAMESPACE CAMERA_ID SERVICE_ID SECONDS
//   spoofer --domain D poses NAMESPACE CAMERA_ID SECONDS
//   spoofer --domain D replies NAMESPACE SECONDS      (answers every point query: 42 m)
//   spoofer --domain D calibration NAMESPACE CAMERA_ID SECONDS
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <string>
#include <thread>

#include "idl/monocle_msgs.h"
#include "idl/protocol/convert.h"
#include "idl/protocol/dds.h"
#include "idl/protocol/service_endpoints.h"
#include "idl/protocol/wire.h"

namespace {

using namespace std::chrono_literals;

int Usage() {
  std::cerr << "usage: spoofer --domain D status NAMESPACE CAMERA SERVICE SECONDS\n"
               "       spoofer --domain D poses NAMESPACE CAMERA SECONDS\n"
               "       spoofer --domain D replies NAMESPACE SECONDS\n"
               "       spoofer --domain D calibration NAMESPACE CAMERA SECONDS\n";
  return 2;
}

int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Every 250 ms, as a service's status period: a streaming floor+corner camera.
int Status(const std::shared_ptr<monocle::dds::Entity>& p, const std::string& ns,
           const std::string& camera, const std::string& service, double seconds) {
  auto w = monocle::dds::Endpoint<monocle_msgs_msg_dds__CameraStatus_>::Open(
      p, &monocle_msgs_msg_dds__CameraStatus__desc, monocle::wire::kCamerasTopic, true, false,
      monocle::dds::EndpointQos{1, true});
  if (!w) return 1;
  monocle::CameraStatus s;
  s.camera_id = camera;
  s.device = camera;
  s.role = "corner+floor";
  s.ros_namespace = ns;
  s.service = service;
  s.state = monocle::CameraState::kStreaming;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    s.stamp_ns = NowNs();
    monocle_msgs_msg_dds__CameraStatus_ sample;
    monocle::wire::ToSample(s, "", &sample);
    (void)w->Write(sample);
    std::this_thread::sleep_for(250ms);
  }
  std::cerr << "done" << std::endl;  // the log a test waits for
  return 0;
}

// At 30 Hz: x = y = z = 42 m, a pose no real camera reports.
int Poses(const std::shared_ptr<monocle::dds::Entity>& p, const std::string& ns,
          const std::string& camera, double seconds) {
  auto w = monocle::dds::Endpoint<monocle_msgs_msg_dds__CornerPose_>::Open(
      p, &monocle_msgs_msg_dds__CornerPose__desc, monocle::wire::CornerPoseTopic(ns).c_str(), true,
      false, monocle::wire::kRosDefaultQos);
  if (!w) return 1;
  monocle::Pose pose;
  pose.camera_id = camera;
  pose.frame_id = "corner";
  pose.valid = true;
  pose.x_m = pose.y_m = pose.z_m = 42;
  pose.quaternion_wxyz = {1, 0, 0, 0};
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    ++pose.frame_sequence;
    pose.capture_time_ns = NowNs();
    monocle_msgs_msg_dds__CornerPose_ sample;
    monocle::wire::ToSample(pose, &sample);
    (void)w->Write(sample);
    std::this_thread::sleep_for(33ms);
  }
  std::cerr << "done" << std::endl;  // the log a test waits for
  return 0;
}

// Every point query on the namespace answered at once (on the receive thread, as monocled
// answers), every point at x = y = z = 42 m.
using ReplyServer = monocle::dds::ServiceServer<monocle_msgs_srv_dds__MeasurePoints_Request_,
                                                monocle_msgs_srv_dds__MeasurePoints_Response_>;

void AnswerWith42(dds_entity_t, void* arg) {
  auto* server = static_cast<ReplyServer*>(arg);
  auto taken = server->TakeRequests<std::pair<size_t, monocle::dds::RequestHeader>>(
      [](const monocle_msgs_srv_dds__MeasurePoints_Request_& r,
         const monocle::dds::RequestHeader& h) { return std::make_pair(size_t{r.u._length}, h); });
  if (!taken) return;
  for (const auto& [n, header] : *taken) {
    monocle::MeasuredPoint fake;
    fake.p_robot_m = {42, 42, 42};
    fake.SetCovariance({1e-6, 0, 0, 0, 1e-6, 0, 0, 0, 1e-6});
    const std::vector<monocle::MeasuredPoint> points(n, fake);
    monocle::wire::PointReplyColumns columns;
    monocle_msgs_srv_dds__MeasurePoints_Response_ reply;
    monocle::wire::ToSample(monocle_msgs_msg_dds__REQUEST_OK, "", points, &columns, &reply);
    (void)server->SendReply(reply, header);
  }
}

int Replies(const std::shared_ptr<monocle::dds::Entity>& p, const std::string& ns, double seconds) {
  auto server = ReplyServer::Open(p, &monocle_msgs_srv_dds__MeasurePoints_Request__desc,
                                  &monocle_msgs_srv_dds__MeasurePoints_Response__desc, ns,
                                  monocle::wire::kMeasurePoints);
  if (!server) return 1;
  if (!monocle::dds::SetDataAvailableListener(server->request_reader(), &AnswerWith42, &*server))
    return 1;
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  monocle::dds::SetDataAvailableListener(server->request_reader());
  std::cerr << "done" << std::endl;
  return 0;
}

// A calibration of the camera at a revision far ahead of the service's, every 250 ms.
int Calibration(const std::shared_ptr<monocle::dds::Entity>& p, const std::string& ns,
                const std::string& camera, double seconds) {
  auto w = monocle::dds::Endpoint<monocle_msgs_msg_dds__Calibration_>::Open(
      p, &monocle_msgs_msg_dds__Calibration__desc, monocle::wire::kCalibrationsTopic, true, false,
      monocle::wire::kDirectoryWriterQos);
  if (!w) return 1;
  monocle::Calibration c;
  c.camera_id = camera;
  c.ros_namespace = ns;
  c.revision = 1000;
  c.width_px = 1280;
  c.height_px = 1024;
  c.fx = c.fy = 42;
  c.cx = 640;
  c.cy = 512;
  c.file = "/evil.pbtxt";
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    c.updated_ns = NowNs();
    monocle_msgs_msg_dds__Calibration_ sample;
    monocle::wire::ToSample(c, &sample);
    (void)w->Write(sample);
    std::this_thread::sleep_for(250ms);
  }
  std::cerr << "done" << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5 || std::string(argv[1]) != "--domain") return Usage();
  const int domain = std::atoi(argv[2]);
  const std::string mode = argv[3];
  auto participant = monocle::dds::CreateParticipant(domain);
  if (!participant) {
    std::cerr << participant.error() << "\n";
    return 1;
  }
  if (mode == "status" && argc == 8)
    return Status(*participant, argv[4], argv[5], argv[6], std::atof(argv[7]));
  if (mode == "poses" && argc == 7)
    return Poses(*participant, argv[4], argv[5], std::atof(argv[6]));
  if (mode == "replies" && argc == 6) return Replies(*participant, argv[4], std::atof(argv[5]));
  if (mode == "calibration" && argc == 7)
    return Calibration(*participant, argv[4], argv[5], std::atof(argv[6]));
  return Usage();
}
