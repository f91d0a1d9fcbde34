// What publishing the live image on ROS 2 costs monocled, as a user would see it: monocled
// (embedded default: sim-corner processing at 30 fps, sim-floor) in its own process, its CPU
// time read from /proc over three phases of --seconds each:
//   1. nobody subscribes to image_raw (monocled only checks for a matched reader per frame);
//   2. a ROS 2 sensor-data reader (best effort, keep-last 5, as rviz) takes every image;
//   3. that reader gone again.
// Goal (issue 13): phase 1 costs what phase 3 does, and both far less than phase 2.
//   build/bench/ros_image_cost_bench [--seconds 10] [--domain 37]
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <dds/dds.h>

#include "bench/bench_process.h"
#include "idl/ros2_messages.h"

namespace {

double CpuPerSecondOver(pid_t pid, int seconds, const std::function<void()>& during) {
  const double before = monocle::bench::CpuSeconds(pid);
  const auto t0 = std::chrono::steady_clock::now();
  const auto end = t0 + std::chrono::seconds(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (during) during();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return (monocle::bench::CpuSeconds(pid) - before) / wall;
}

}  // namespace

int main(int argc, char** argv) {
  int seconds = 10, domain = 37;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--seconds")
      seconds = std::atoi(argv[i + 1]);
    else if (flag == "--domain")
      domain = std::atoi(argv[i + 1]);
    else {
      std::cerr << "usage: ros_image_cost_bench [--seconds N] [--domain D]\n";
      return 2;
    }
  }
  const std::string source = MONOCLE_SOURCE_DIR;
  if (std::getenv("CYCLONEDDS_URI") == nullptr)
    setenv("CYCLONEDDS_URI", ("file://" + source + "/docker/cyclonedds-loopback.xml").c_str(), 1);
  const std::string monocled =
      (std::filesystem::path(argv[0]).parent_path() / "../service/monocled").string();
  const auto state = std::filesystem::temp_directory_path() / "monocle_ros_image_cost_bench";
  std::filesystem::create_directories(state);
  const pid_t pid = fork();
  if (pid == 0) {
    if (freopen((state / "monocled.log").c_str(), "w", stderr) == nullptr) _exit(126);
    execl(monocled.c_str(), monocled.c_str(), "--domain", std::to_string(domain).c_str(),
          "--state-dir", state.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  std::this_thread::sleep_for(std::chrono::seconds(3));  // cameras open, first frames

  const double idle = CpuPerSecondOver(pid, seconds, nullptr);

  const dds_entity_t participant = dds_create_participant(domain, nullptr, nullptr);
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 5);
  const dds_entity_t topic = dds_create_topic(participant, &sensor_msgs_msg_dds__Image__desc,
                                              "rt/monocle/sim_corner/image_raw", qos, nullptr);
  const dds_entity_t reader = dds_create_reader(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  long images = 0;
  const double watched = CpuPerSecondOver(pid, seconds, [&] {
    void* samples[5] = {};
    dds_sample_info_t infos[5];
    const int n = dds_take(reader, samples, infos, 5, 5);
    for (int i = 0; i < n; ++i) images += infos[i].valid_data;
    if (n > 0) dds_return_loan(reader, samples, n);
  });
  dds_delete(participant);
  std::this_thread::sleep_for(std::chrono::seconds(1));  // the reader's loss is discovered
  const double after = CpuPerSecondOver(pid, seconds, nullptr);

  kill(pid, SIGTERM);
  waitpid(pid, nullptr, 0);
  std::cout << "monocled CPU (cores busy, 1.0 = one core), " << seconds << " s per phase:\n"
            << "  nobody subscribes to image_raw:   " << idle << "\n"
            << "  a sensor-data reader takes them:  " << watched << "  (" << images / seconds
            << " images/s of 1280x1024 mono8, limit image_max_rate_hz 5)\n"
            << "  the reader gone again:            " << after << "\n";
  return 0;
}
