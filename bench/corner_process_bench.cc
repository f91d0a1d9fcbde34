// Corner detection as a user runs it, whole processes: `monocle corner locate` on 300 PGM
// files (72 distinct views: clean, cluttered, realistic, from bench/corner_bench_frames.h)
// against `canny_hough_baseline` (OpenCV Canny + HoughLines) on the same files, each pinned
// to one core with taskset, alternately, 3 rounds. Start-up, image decoding and output are
// inside the time. Failed frames are counted from monocle's JSON, not dropped. Then the
// realistic frames alone, also against the baseline with thresholds low enough to see their
// white-on-white edges.
// Then beside OpenCV contrib's FastLineDetector and EdgeDrawing (line_baseline --method).
// Goals (issues 11 and 62): monocle <= 0.4x Canny + HoughLines, <= 0.45x FastLineDetector.
// Run: build/bench/corner_process_bench [--frames 300] [--rounds 3]
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>

#include "bench/corner_bench_frames.h"
#include "service/io/calibration_file.h"

namespace {

double RunSeconds(const std::string& command) {
  const auto t0 = std::chrono::steady_clock::now();
  const int status = std::system(command.c_str());
  const auto t1 = std::chrono::steady_clock::now();
  if (status == -1) {
    std::cerr << "cannot run: " << command << "\n";
    std::exit(1);
  }
  return std::chrono::duration<double>(t1 - t0).count();
}

// "N failed of M" from monocle's JSON lines: failures are counted, not dropped.
std::string FailedFrames(const std::filesystem::path& jsonl) {
  int failed = 0, lines = 0;
  std::ifstream results(jsonl);
  for (std::string line; std::getline(results, line); ++lines)
    failed += line.find("\"error\"") != std::string::npos;
  return std::to_string(failed) + " failed of " + std::to_string(lines);
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 300, rounds = 3;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--frames")
      frames = std::atoi(argv[i + 1]);
    else if (flag == "--rounds")
      rounds = std::atoi(argv[i + 1]);
    else {
      std::cerr << "usage: corner_process_bench [--frames N] [--rounds R]\n";
      return 2;
    }
  }
  const std::filesystem::path bin = std::filesystem::path(argv[0]).parent_path();
  const std::string monocle = (bin / "../client/monocle").string();
  const std::string baseline = (bin / "line_baseline").string();
  const auto dir = std::filesystem::temp_directory_path() / "monocle_corner_process_bench";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);

  std::cerr << "rendering 72 distinct frames...\n";
  const auto views = monocle::bench::RenderBenchFrames();
  std::string files;
  for (int i = 0; i < frames; ++i) {
    std::ostringstream name;
    name << "frame" << std::setw(3) << std::setfill('0') << i << ".pgm";
    cv::imwrite((dir / name.str()).string(), views[i % views.size()].image);
    files += " " + (dir / name.str()).string();
  }
  monocle::CameraCalibration cal;
  cal.intrinsics = monocle::testing::PaperCamera();
  cal.ceiling_distance_m = 1.6;  // one distance for all: it scales the pose, not the work
  if (!monocle::SaveCalibrationFileAtomically((dir / "cam.pbtxt").string(), cal).ok()) return 1;

  const std::string calibration = " --calibration " + (dir / "cam.pbtxt").string();
  const auto run_monocle = [&](const std::string& file_list, const std::string& out) {
    return RunSeconds("taskset -c 0 " + monocle + " corner locate" + file_list + calibration +
                      " --json > " + (dir / out).string() + " 2>&1");
  };
  const auto run_baseline = [&](const std::string& file_list, const std::string& settings) {
    return RunSeconds("taskset -c 0 " + baseline + settings + file_list + " > " +
                      (dir / "baseline.txt").string() + " 2>&1");
  };
  double ours_s = 0, theirs_s = 0;
  for (int round = 0; round < rounds; ++round) {
    const double a = run_monocle(files, "monocle.jsonl"), b = run_baseline(files, "");
    std::cout << "round " << round + 1 << ": monocle " << 1e3 * a / frames << " ms/frame, baseline "
              << 1e3 * b / frames << " ms/frame, ratio " << a / b << "\n";
    ours_s += a;
    theirs_s += b;
  }
  std::cout << "monocle corner locate: " << 1e3 * ours_s / (rounds * frames) << " ms/frame over "
            << frames << " frames (" << FailedFrames(dir / "monocle.jsonl") << "), baseline "
            << 1e3 * theirs_s / (rounds * frames) << " ms/frame, ratio " << ours_s / theirs_s
            << " (goal <= 0.4)\n";

  // Beside OpenCV contrib's segment finders, the same files, alternately (they find segments,
  // not a corner: the edges' cost alone). Goal (issue 62): <= 0.45x FastLineDetector.
  for (const std::string method : {"fld", "edge-drawing"}) {
    double ours_m = 0, theirs_m = 0;
    for (int round = 0; round < rounds; ++round) {
      const bool ours_first = round % 2 == 0;
      const double first = ours_first ? run_monocle(files, "monocle.jsonl")
                                      : run_baseline(files, " --method " + method);
      const double second = ours_first ? run_baseline(files, " --method " + method)
                                       : run_monocle(files, "monocle.jsonl");
      ours_m += ours_first ? first : second;
      theirs_m += ours_first ? second : first;
    }
    std::cout << "beside " << method << ": monocle " << 1e3 * ours_m / (rounds * frames)
              << " ms/frame, " << method << " " << 1e3 * theirs_m / (rounds * frames)
              << " ms/frame, ratio " << ours_m / theirs_m
              << (method == "fld" ? " (goal <= 0.45)" : "") << "\n";
  }

  // The realistic frames alone, against the baseline as above (which finds none of their Ys:
  // bench/corner_bench's baseline_sees_y) and with its thresholds lowered until it sees
  // most of them, Canny(20,60) + 60 votes.
  std::string realistic_files;
  int realistic = 0;
  for (int i = 0; i < frames; ++i) {
    if (views[i % views.size()].kind != "realistic") continue;
    std::ostringstream name;
    name << "frame" << std::setw(3) << std::setfill('0') << i << ".pgm";
    realistic_files += " " + (dir / name.str()).string();
    ++realistic;
  }
  if (realistic > 0) {
    double ours_r = 0, default_r = 0, seeing_r = 0;
    for (int round = 0; round < rounds; ++round) {
      ours_r += run_monocle(realistic_files, "monocle_realistic.jsonl");
      default_r += run_baseline(realistic_files, "");
      seeing_r += run_baseline(realistic_files, " --canny 20,60 --votes 60");
    }
    const double per = 1e3 / (rounds * realistic);
    std::cout << "realistic frames only (" << realistic << " files, "
              << FailedFrames(dir / "monocle_realistic.jsonl") << "): monocle " << ours_r * per
              << " ms/frame; baseline Canny(50,150) + 150 votes " << default_r * per
              << " ms/frame, ratio " << ours_r / default_r << "; baseline Canny(20,60) + 60 votes "
              << seeing_r * per << " ms/frame, ratio " << ours_r / seeing_r << "\n";
  }
  std::filesystem::remove_all(dir);
  return 0;
}
