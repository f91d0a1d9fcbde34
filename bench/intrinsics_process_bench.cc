// Intrinsic calibration as a user runs it, whole processes: `monocle intrinsics calibrate`
// on 30 rendered 1280x1024 PNG views (board detection, three distortion models compared,
// blunder screening, full covariance, the calibration file written) against
// `opencv_calibration_baseline` (OpenCV's tutorial pipeline: findChessboardCorners,
// cornerSubPix, calibrateCamera with its defaults) on the same files; each pinned to one core
// with taskset, alternately, 3 rounds. Start-up and PNG decoding are inside the time.
// Goal (issue 12): monocle <= 2 s.
// Run: build/bench/intrinsics_process_bench [--views 30] [--rounds 3]
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

namespace {

double RunSeconds(const std::string& command) {
  const auto t0 = std::chrono::steady_clock::now();
  const int status = std::system(command.c_str());
  const auto t1 = std::chrono::steady_clock::now();
  if (status != 0) {
    std::cerr << "failed (" << status << "): " << command << "\n";
    std::exit(1);
  }
  return std::chrono::duration<double>(t1 - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  int views = 30, rounds = 3;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--views")
      views = std::atoi(argv[i + 1]);
    else if (flag == "--rounds")
      rounds = std::atoi(argv[i + 1]);
    else {
      std::cerr << "usage: intrinsics_process_bench [--views N] [--rounds R]\n";
      return 2;
    }
  }
  const std::filesystem::path bin = std::filesystem::path(argv[0]).parent_path();
  const std::string monocle = (bin / "../client/monocle").string();
  const std::string baseline = (bin / "opencv_calibration_baseline").string();
  const auto dir = std::filesystem::temp_directory_path() / "monocle_intrinsics_process_bench";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string d = dir.string();

  // The lens of Xu et al.'s camera, rendered with monocle's own board renderer (uneven
  // light, blur, noise, JPEG-like loss), boards spread over the image.
  RunSeconds(
      "printf 'intrinsics { width: 1280 height: 1024 fx: 1624.34 fy: 1623.04 cx: 634.77 "
      "cy: 499.02 distortion: [-0.07021, 0.07348, -0.00112, 0.00267] }\\n' > " +
      d + "/lens.pbtxt");
  std::cerr << "rendering " << views << " views...\n";
  RunSeconds(monocle + " render boards --calibration " + d + "/lens.pbtxt --board 9x6 " +
             "--square 0.04 --views " + std::to_string(views) + " --seed 3 --out-dir " + d +
             "/views > /dev/null");
  const std::string files = d + "/views/view-*.png";
  const std::string ours = "taskset -c 0 " + monocle + " intrinsics calibrate " + files +
                           " --board 9x6 --square 0.04 --out " + d + "/cam.pbtxt > " + d +
                           "/monocle.txt 2>&1";
  const std::string theirs =
      "taskset -c 0 " + baseline + " 9 6 0.04 " + files + " > " + d + "/baseline.txt 2>&1";
  double ours_s = 0, theirs_s = 0;
  for (int round = 0; round < rounds; ++round) {
    const double a = RunSeconds(ours), b = RunSeconds(theirs);
    std::cout << "round " << round + 1 << ": monocle " << a << " s, baseline " << b << " s, ratio "
              << a / b << "\n";
    ours_s += a;
    theirs_s += b;
  }
  std::cout << "monocle intrinsics calibrate, " << views
            << " views of 1280x1024, one core: " << ours_s / rounds
            << " s (goal <= 2 s); OpenCV tutorial pipeline " << theirs_s / rounds << " s; ratio "
            << ours_s / theirs_s << "\n";
  RunSeconds("grep -E '^ *(fx|cx|rms)' " + d + "/monocle.txt; cat " + d + "/baseline.txt");
  std::filesystem::remove_all(dir);
  return 0;
}
