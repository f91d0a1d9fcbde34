// The baseline a user would write to find straight edges: read each image, OpenCV Canny +
// HoughLines, print how many lines. One thread. For bench/corner_process_bench.
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

int main(int argc, char** argv) {
  cv::setNumThreads(1);
  int failed = 0;
  for (int i = 1; i < argc; ++i) {
    const cv::Mat image = cv::imread(argv[i], cv::IMREAD_GRAYSCALE);
    if (image.empty()) {
      std::cout << argv[i] << " unreadable\n";
      ++failed;
      continue;
    }
    cv::Mat edges;
    std::vector<cv::Vec2f> lines;
    cv::Canny(image, edges, 50, 150);
    cv::HoughLines(edges, lines, 1, CV_PI / 360, 150);
    std::cout << argv[i] << " " << lines.size() << " lines\n";
  }
  return failed == 0 ? 0 : 1;
}
