// The service over DDS, end to end, each side in its own process on this machine:
//   1. point-query round trip, one point per request (p50, p99), in rounds interleaved with
//      rounds of ddsperf ping-pong (Cyclone DDS's own tool) on the same machine, so both see
//      the same load (monocled keeps processing its corner camera meanwhile);
//   2. batched point-query throughput (points per second, requests of 100 000 points);
//   3. frame complete -> pose received by a subscriber in another process;
//   4. the point-query round trip again with DDS Security on (a keystore made here with
//      `monocle security init`, a reader client; authenticated, encrypted), beside 1.
// Goals (issue 13): round trip p50 <= 1.0x ddsperf's and p99 <= 2x ddsperf's p99; >= 2 M
// points/s; frame -> pose p50 <= processing time + 0.5 ms.
//
//   build/bench/service_bench [--queries 3000] [--rounds 5] [--seconds 10] [--domain 35]
//                             [--batch 100000]
//
// monocled runs with both simulated cameras (sim-corner processing at 30 fps meanwhile, as in
// use). ddsperf prints half the round trip; we double it. DDS goes over loopback only
// (docker/cyclonedds-loopback.xml) unless CYCLONEDDS_URI is set.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_process.h"
#include "monocle/client.h"

namespace {

using Clock = std::chrono::steady_clock;

using monocle::bench::Percentile;
using monocle::bench::Spawn;
using monocle::bench::Stop;

// ddsperf ping prints once a second "... 50% 55.6us 90% ... 99% 110.2us ..." (half round
// trips); the median over the seconds of the run.
struct DdsperfFigures {
  double half_rtt_p50_us = 0, half_rtt_p99_us = 0;
};

// One round of `seconds` + 1 (the first second, with discovery, is dropped).
DdsperfFigures RunDdsperf(int domain, const std::string& dir, int seconds) {
  const pid_t pong = Spawn({"ddsperf", "-i", std::to_string(domain), "-D",
                            std::to_string(seconds + 3), "pong", "waitset"},
                           dir + "/pong.log");
  const pid_t ping = Spawn({"ddsperf", "-i", std::to_string(domain), "-D",
                            std::to_string(seconds + 1), "ping", "waitset"},
                           dir + "/ping.log");
  waitpid(ping, nullptr, 0);
  Stop(pong);
  std::ifstream in(dir + "/ping.log");
  std::vector<double> p50, p99;
  const std::regex re(R"(50% ([0-9.]+)us .* 99% ([0-9.]+)us)");
  bool first = true;
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, re)) continue;
    if (first) {  // the first second includes discovery
      first = false;
      continue;
    }
    p50.push_back(std::stod(m[1]));
    p99.push_back(std::stod(m[2]));
  }
  return {Percentile(p50, 0.5), Percentile(p99, 0.5)};
}

}  // namespace

int main(int argc, char** argv) {
  int queries = 3000, domain = 35, batch_size = 100000, rounds = 5;
  double seconds = 10;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--queries")
      queries = std::atoi(argv[i + 1]);
    else if (a == "--seconds")
      seconds = std::atof(argv[i + 1]);
    else if (a == "--rounds")
      rounds = std::max(1, std::atoi(argv[i + 1]));
    else if (a == "--domain")
      domain = std::atoi(argv[i + 1]);
    else if (a == "--batch")
      batch_size = std::clamp(std::atoi(argv[i + 1]), 1, 100000);
    else {
      std::cerr << "usage: service_bench [--queries N] [--rounds R] [--seconds S] [--domain D] "
                   "[--batch N]\n";
      return 2;
    }
  }
  const std::filesystem::path self = std::filesystem::canonical("/proc/self/exe");
  const std::string build = self.parent_path().parent_path().string();
  const std::string source = MONOCLE_SOURCE_DIR;
  if (std::getenv("CYCLONEDDS_URI") == nullptr)
    setenv("CYCLONEDDS_URI", ("file://" + source + "/docker/cyclonedds-loopback.xml").c_str(), 1);
  const std::string dir = (std::filesystem::temp_directory_path() /
                           ("monocle_service_bench_" + std::to_string(getpid())))
                              .string();
  std::filesystem::create_directories(dir);

  const pid_t monocled = Spawn({build + "/service/monocled", "--domain", std::to_string(domain),
                                "--state-dir", dir + "/state"},
                               dir + "/monocled.log");
  auto client = monocle::Client::open({domain, std::chrono::seconds(30)});
  if (!client) {
    std::cerr << client.error() << "\n";
    Stop(monocled);
    return 1;
  }

  // monocled renders its simulated cameras' frames when it starts (seconds of CPU on both
  // cores); measuring before that ends would measure the renderer. Ready: the corner camera
  // has produced a pose (its frames exist) and the floor camera answers.
  std::cout << "waiting for monocled's simulated cameras to stream" << std::endl;
  for (int tries = 0;; ++tries) {
    const auto pose = client->pose("sim-corner", monocle::PoseWhich::kNextFrame);
    if (pose && client->measure("sim-floor", {{640, 900, std::nullopt}})) break;
    if (tries == 60) {
      std::cerr << "monocled's cameras did not stream within a minute: "
                << (pose ? std::string("sim-floor does not answer") : pose.error().message) << "\n";
      Stop(monocled);
      return 1;
    }
    std::this_thread::sleep_for(std::chrono::seconds(1));
  }

  // Round trip, one point per request, in rounds between rounds of ddsperf.
  std::vector<double> rtt_us, dds_p50_us, dds_p99_us;
  const std::vector<monocle::PixelQuery> one{{640, 900, std::nullopt}};
  auto query_round = [&](int n, bool keep) {
    for (int i = 0; i < n; ++i) {
      const auto start = Clock::now();
      const auto r = client->measure("sim-floor", one);
      const double us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
      if (!r) {
        std::cerr << "point query failed: " << r.error() << "\n";
        return false;
      }
      if (keep) rtt_us.push_back(us);
    }
    return true;
  };
  if (!query_round(200, false)) {  // the first ones include discovery
    Stop(monocled);
    return 1;
  }
  for (int round = 0; round < rounds; ++round) {
    std::cout << "round " << round + 1 << "/" << rounds << ": ddsperf ping-pong (domain "
              << domain + 1 << "), then " << queries / rounds << " point queries" << std::endl;
    const DdsperfFigures d = RunDdsperf(domain + 1, dir, 2);
    dds_p50_us.push_back(2 * d.half_rtt_p50_us);
    dds_p99_us.push_back(2 * d.half_rtt_p99_us);
    // As ddsperf's first second is dropped, so is the start of each query round: for about
    // 150 ms after ddsperf's processes end, every round trip on this 2-core machine took
    // ~3 ms (measured: the slow queries all fell in that window), which says nothing about
    // monocle. A pause and 50 unrecorded queries put both on the same footing.
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    if (!query_round(50, false) || !query_round(queries / rounds, true)) {
      Stop(monocled);
      return 1;
    }
  }

  // Batched throughput: requests of 100 000 points (the service's limit per request).
  std::vector<monocle::PixelQuery> batch;
  for (int i = 0; i < batch_size; ++i)
    batch.push_back({100.0 + (i % 1000), 600.0 + (i / 1000) * 4, std::nullopt});
  const int batches = std::max(20, 2000000 / batch_size);
  const auto t0 = Clock::now();
  for (int i = 0; i < batches; ++i) {
    const auto r = client->measure("sim-floor", batch);
    if (!r || r->size() != batch.size()) {
      std::cerr << "batch failed\n";
      Stop(monocled);
      return 1;
    }
  }
  const double points_per_s = batches * static_cast<double>(batch.size()) /
                              std::chrono::duration<double>(Clock::now() - t0).count();

  // Frame complete (the host's real-time stamp of the frame) -> pose received here.
  std::mutex mutex;
  std::vector<double> latency_ms, processing_ms, overhead_ms;
  auto sub = client->subscribe_poses(
      [&](const monocle::Pose& p) {
        const auto now_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                std::chrono::system_clock::now().time_since_epoch())
                                .count();
        const double latency = static_cast<double>(now_ns - p.capture_time_ns) / 1e6;
        const double processing = static_cast<double>(p.processing_ns) / 1e6;
        std::lock_guard<std::mutex> lock(mutex);
        latency_ms.push_back(latency);
        processing_ms.push_back(processing);
        overhead_ms.push_back(latency - processing);
      },
      "sim-corner");
  if (!sub) {
    std::cerr << sub.error() << "\n";
    Stop(monocled);
    return 1;
  }
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  sub->stop();
  Stop(monocled);

  // 4. Secured: the same round trip against a monocled with DDS Security, by a reader client.
  std::vector<double> secured_us;
  {
    const std::string keys = dir + "/keys";
    const std::string init = build + "/client/monocle security init " + keys +
                             " --client bench:reader >" + dir + "/security.log 2>&1";
    if (std::system(init.c_str()) != 0) {
      std::cerr << "monocle security init failed: see " << dir << "/security.log\n";
      return 1;
    }
    const pid_t secured =
        Spawn({build + "/service/monocled", "--domain", std::to_string(domain + 2), "--state-dir",
               dir + "/state", "--security", keys + "/monocled"},
              dir + "/monocled-secured.log");
    monocle::Client::Options options;
    options.domain = domain + 2;
    options.timeout = std::chrono::seconds(30);
    options.security_dir = keys + "/bench";
    auto secured_client = monocle::Client::open(options);
    bool ok = secured_client.ok();
    // Ready as above: the corner camera streams (its rendering is over) and points answer.
    const auto ready = [&] {
      return secured_client->pose("sim-corner", monocle::PoseWhich::kNextFrame).ok() &&
             secured_client->measure("sim-floor", one).ok();
    };
    for (int tries = 0; ok && !ready(); ++tries) {
      if (tries == 60) ok = false;
      std::this_thread::sleep_for(std::chrono::seconds(1));
    }
    for (int i = 0; ok && i < 250 + queries; ++i) {
      const auto start = Clock::now();
      const auto r = secured_client->measure("sim-floor", one);
      const double us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
      ok = r.ok();
      if (i >= 250) secured_us.push_back(us);  // after discovery and the handshake settle
    }
    Stop(secured);
    if (!ok) {
      std::cerr << "secured point queries failed: see " << dir << "/monocled-secured.log\n";
      return 1;
    }
  }
  if (!std::getenv("TIMING")) std::filesystem::remove_all(dir);

  const double dds_rtt_p50 = Percentile(dds_p50_us, 0.5), dds_rtt_p99 = Percentile(dds_p99_us, 0.5);
  const double p50 = Percentile(rtt_us, 0.5), p99 = Percentile(rtt_us, 0.99);
  std::cout << std::fixed << std::setprecision(1) << "\n"
            << "ddsperf ping-pong round trip     p50 " << dds_rtt_p50 << " us  p99 " << dds_rtt_p99
            << " us  (median of " << rounds << " rounds; ddsperf prints half)\n"
            << "point query round trip (1 point) p50 " << p50 << " us  p99 " << p99 << " us  over "
            << rtt_us.size() << " requests:\n"
            << std::setprecision(2) << "  p50 = " << p50 / dds_rtt_p50
            << "x ddsperf's (goal <= 1.0x), p99 = " << p99 / dds_rtt_p99
            << "x ddsperf's p99 (goal <= 2x)\n"
            << "  with DDS Security (reader)     p50 " << std::setprecision(1)
            << Percentile(secured_us, 0.5) << " us  p99 " << Percentile(secured_us, 0.99)
            << " us  over " << secured_us.size() << " requests (authenticated, encrypted)\n"
            << std::setprecision(2) << "batched point queries            " << points_per_s / 1e6
            << " M points/s  (" << batches << " requests of " << batch.size()
            << " points; goal >= 2 M/s)\n";
  std::lock_guard<std::mutex> lock(mutex);
  std::cout << std::setprecision(2) << "frame complete -> pose received  p50 "
            << Percentile(latency_ms, 0.5) << " ms  p99 " << Percentile(latency_ms, 0.99)
            << " ms  over " << latency_ms.size() << " poses\n"
            << "  of which processing            p50 " << Percentile(processing_ms, 0.5)
            << " ms;  latency - processing p50 " << Percentile(overhead_ms, 0.5) << " ms  p99 "
            << Percentile(overhead_ms, 0.99) << " ms (goal p50 <= 0.5 ms)\n";
  return 0;
}
