// The baseline a user would write to find straight edges: read each image, OpenCV Canny +
// HoughLines, print how many lines. One thread. For bench/corner_process_bench.
// Usage: canny_hough_baseline [--canny LOW,HIGH] [--votes N] IMAGE...
// (defaults Canny(50,150), 150 votes; bench/corner_bench.cc says why other rows lower them)
#include <cstdio>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

int main(int argc, char** argv) {
  cv::setNumThreads(1);
  double canny_low = 50, canny_high = 150;
  int votes = 150, failed = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--canny" && i + 1 < argc) {
      if (std::sscanf(argv[++i], "%lf,%lf", &canny_low, &canny_high) != 2) {
        std::cerr << "--canny takes LOW,HIGH, e.g. --canny 20,60\n";
        return 2;
      }
      continue;
    }
    if (arg == "--votes" && i + 1 < argc) {
      votes = std::stoi(argv[++i]);
      continue;
    }
    const cv::Mat image = cv::imread(arg, cv::IMREAD_GRAYSCALE);
    if (image.empty()) {
      std::cout << arg << " unreadable\n";
      ++failed;
      continue;
    }
    cv::Mat edges;
    std::vector<cv::Vec2f> lines;
    cv::Canny(image, edges, canny_low, canny_high);
    cv::HoughLines(edges, lines, 1, CV_PI / 360, votes);
    std::cout << arg << " " << lines.size() << " lines\n";
  }
  return failed == 0 ? 0 : 1;
}
