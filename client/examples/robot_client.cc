// What a robot's own software does with monocle: asks which cameras the service has, follows
// the corner camera's poses, and measures floor points — all over DDS via monocle::Client.
//
//   monocle_client_example [--domain D] [--corner CAMERA] [--floor CAMERA] [--poses N]
#include <monocle/client.h>

#include <condition_variable>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <string>

int main(int argc, char** argv) {
  int domain = 0, wanted_poses = 3;
  std::string corner_camera = "sim-corner", floor_camera = "sim-floor";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--domain")
      domain = std::atoi(value.c_str());
    else if (flag == "--corner")
      corner_camera = value;
    else if (flag == "--floor")
      floor_camera = value;
    else if (flag == "--poses")
      wanted_poses = std::atoi(value.c_str());
  }

  auto client = monocle::Client::open({domain, std::chrono::seconds(20)});
  if (!client) {
    std::cerr << "cannot open the client: " << client.error() << "\n";
    return 1;
  }

  // 1. Follow the robot's pose: the callback runs on the subscription's own thread.
  std::mutex mutex;
  std::condition_variable done;
  int poses = 0;
  auto subscription = client->subscribe_poses(
      [&](const monocle::Pose& p) {
        std::lock_guard<std::mutex> lock(mutex);
        if (p.valid) {
          std::cout << "pose frame " << p.frame_sequence << ": x " << p.x_m << " m, y " << p.y_m
                    << " m, pan " << p.pan_rad << " rad\n";
        }
        if (++poses >= wanted_poses) done.notify_one();
      },
      corner_camera);
  if (!subscription) {
    std::cerr << subscription.error() << "\n";
    return 1;
  }
  {
    std::unique_lock<std::mutex> lock(mutex);
    if (!done.wait_for(lock, std::chrono::seconds(20), [&] { return poses >= wanted_poses; })) {
      std::cerr << "no poses from camera " << corner_camera << "\n";
      return 1;
    }
  }
  subscription->stop();

  // 2. The service's cameras (the corner camera streams by now).
  const auto status = client->status();
  if (!status) {
    std::cerr << status.error() << "\n";
    return 1;
  }
  for (const auto& s : *status) {
    std::cout << "camera " << s.camera_id << " (" << s.role << "): " << ToString(s.state) << ", "
              << s.fps << " fps\n";
  }

  // 3. Where is the point on the floor at pixel (640, 900), and how high is the top of the box
  //    whose foot is there?
  const auto points = client->measure(
      floor_camera, {{640, 900, std::nullopt}, {482, 544, std::array<double, 2>{484, 674}}});
  if (!points) {
    std::cerr << points.error() << "\n";
    return 1;
  }
  for (const auto& p : *points) {
    if (!p.ok()) {
      std::cerr << "point not measured: " << p.error << "\n";
      return 1;
    }
    std::cout << "point x " << p.p_robot_m[0] << " y " << p.p_robot_m[1] << " z " << p.p_robot_m[2]
              << " m (1 sigma " << p.sigma_m[0] << " " << p.sigma_m[1] << " " << p.sigma_m[2]
              << " m)\n";
  }

  // 4. A typed error, as a robot would handle it.
  const auto wrong = client->pose("no-such-camera");
  if (wrong || wrong.error().code != monocle::ClientError::Code::kInvalidRequest) {
    std::cerr << "expected an invalid-request error for an unknown camera\n";
    return 1;
  }
  std::cout << "unknown camera: " << wrong.error() << "\n";
  return 0;
}
