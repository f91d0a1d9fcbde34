// What recording costs monocled, as a user runs it: monocled serving one simulated
// 1280x1024 camera at 30 fps (corner processing on every frame) in its own process, its CPU
// time read from /proc over --seconds, side by side in one run:
//   1. monocled alone (the baseline);
//   2. monocled --record FILE --record-frames every (poses, status and every frame);
//   3. the same with --record-zstd.
// Goal (issue 15): 2 costs at most 10 % of one core beyond 1.
//   build/bench/record_bench [--seconds 10] [--domain 39] [--dir /tmp]
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_process.h"

namespace {

struct Phase {
  double cores = 0;         // CPU seconds per second (1.0 = one core busy)
  double file_mb = 0;       // recording size
  double frames_per_s = 0;  // frames received by monocled (its status log)
};

Phase Run(const std::string& monocled, const std::filesystem::path& dir, int domain, int seconds,
          const std::vector<std::string>& extra) {
  std::ofstream(dir / "bench.pbtxt") << "domain: " << domain << R"(
camera { id: "corner" device: "sim-corner" role: CORNER calibration: ")"
                                     << (dir / "sim-corner.pbtxt").string() << R"("
         ceiling_distance_m: 1.6 frame_rate_hz: 30 }
)";
  std::vector<std::string> args{monocled, "--config", (dir / "bench.pbtxt").string(), "--state-dir",
                                dir.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  const pid_t pid = monocle::bench::Spawn(args, (dir / "monocled.log").string());
  std::this_thread::sleep_for(std::chrono::seconds(4));  // camera open, streaming
  const double before = monocle::bench::CpuSeconds(pid);
  const auto t0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::seconds(seconds));
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Phase p;
  p.cores = (monocle::bench::CpuSeconds(pid) - before) / wall;
  monocle::bench::Stop(pid);
  if (std::filesystem::exists(dir / "bench.mcap")) {
    p.file_mb = static_cast<double>(std::filesystem::file_size(dir / "bench.mcap")) / 1e6;
    std::filesystem::remove(dir / "bench.mcap");
  }
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  int seconds = 10, domain = 39;
  std::filesystem::path base = std::filesystem::temp_directory_path();
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--seconds") {
      seconds = std::atoi(argv[i + 1]);
    } else if (flag == "--domain") {
      domain = std::atoi(argv[i + 1]);
    } else if (flag == "--dir") {
      base = argv[i + 1];
    } else {
      std::cerr << "usage: record_bench [--seconds N] [--domain D] [--dir DIR]\n";
      return 2;
    }
  }
  const std::string source = MONOCLE_SOURCE_DIR;
  if (std::getenv("CYCLONEDDS_URI") == nullptr)
    setenv("CYCLONEDDS_URI", ("file://" + source + "/docker/cyclonedds-loopback.xml").c_str(), 1);
  const std::string monocled =
      (std::filesystem::path(argv[0]).parent_path() / "../service/monocled").string();
  const auto dir = base / "monocle_record_bench";
  std::filesystem::create_directories(dir);
  // The simulated camera's calibration, as the embedded default makes it.
  {
    const pid_t pid = monocle::bench::Spawn(
        {monocled, "--state-dir", dir.string(), "--domain", std::to_string(domain)},
        (dir / "default.log").string());
    std::this_thread::sleep_for(std::chrono::seconds(2));
    monocle::bench::Stop(pid);
  }
  const std::string out = (dir / "bench.mcap").string();
  const Phase alone = Run(monocled, dir, domain, seconds, {});
  const Phase recording =
      Run(monocled, dir, domain, seconds, {"--record", out, "--record-frames", "every"});
  const Phase zstd = Run(monocled, dir, domain, seconds,
                         {"--record", out, "--record-frames", "every", "--record-zstd"});
  std::cout << std::fixed << std::setprecision(3)
            << "monocled, one simulated 1280x1024 camera at 30 fps, " << seconds
            << " s per phase (CPU: 1.0 = one core busy)\n"
            << "  service alone:                       " << alone.cores << "\n"
            << "  --record-frames every:               " << recording.cores << "  (+"
            << std::setprecision(1) << 100 * (recording.cores - alone.cores)
            << " % of a core, file " << recording.file_mb / seconds << " MB/s)\n"
            << std::setprecision(3) << "  --record-frames every --record-zstd: " << zstd.cores
            << "  (+" << std::setprecision(1) << 100 * (zstd.cores - alone.cores)
            << " % of a core, file " << zstd.file_mb / seconds << " MB/s)\n";
  return 0;
}
