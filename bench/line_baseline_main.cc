// The baselines a user would write to find straight edges, as whole processes: read each
// image, find its lines with one method (bench/line_baselines.h), print how many. One thread.
// For bench/corner_process_bench.
// Usage: line_baseline [--method canny-hough|fld|edge-drawing] [--canny LOW,HIGH] [--votes N]
//        IMAGE...  (built twice: as canny_hough_baseline its default method is canny-hough)
#include <cstdio>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "bench/line_baselines.h"

int main(int argc, char** argv) {
  cv::setNumThreads(1);
  using monocle::bench::LineMethod;
  LineMethod method = LineMethod::kCannyHough;
  monocle::bench::CannyHoughSettings canny_hough;
  std::vector<std::string> images;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--method" && i + 1 < argc) {
      const auto parsed = monocle::bench::ParseLineMethod(argv[++i]);
      if (!parsed) {
        std::cerr << "--method takes canny-hough, fld or edge-drawing\n";
        return 2;
      }
      method = *parsed;
    } else if (arg == "--canny" && i + 1 < argc) {
      if (std::sscanf(argv[++i], "%lf,%lf", &canny_hough.low, &canny_hough.high) != 2) {
        std::cerr << "--canny takes LOW,HIGH, e.g. --canny 20,60\n";
        return 2;
      }
    } else if (arg == "--votes" && i + 1 < argc) {
      canny_hough.votes = std::stoi(argv[++i]);
    } else {
      images.push_back(arg);
    }
  }
  monocle::bench::LineFinder finder(method, canny_hough);
  int failed = 0;
  for (const auto& path : images) {
    const cv::Mat image = cv::imread(path, cv::IMREAD_GRAYSCALE);
    if (image.empty()) {
      std::cout << path << " unreadable\n";
      ++failed;
      continue;
    }
    std::cout << path << " " << finder.Find(image) << " lines\n";
  }
  return failed == 0 ? 0 : 1;
}
