// The baseline a user would otherwise run for intrinsics: OpenCV's tutorial pipeline
// (findChessboardCorners, cornerSubPix 11x11, calibrateCamera with its defaults) over image
// files. Prints fx fy cx cy and the RMS. Usage: opencv_calibration_baseline COLS ROWS SQUARE_M
// IMAGE...
#include <cstdlib>
#include <iostream>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 5) {
    std::cerr << "usage: opencv_calibration_baseline COLS ROWS SQUARE_M IMAGE...\n";
    return 2;
  }
  const cv::Size pattern(std::atoi(argv[1]), std::atoi(argv[2]));
  const float square = static_cast<float>(std::atof(argv[3]));
  std::vector<cv::Point3f> board;
  for (int j = 0; j < pattern.height; ++j)
    for (int i = 0; i < pattern.width; ++i) board.emplace_back(i * square, j * square, 0.f);
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  cv::Size size;
  for (int a = 4; a < argc; ++a) {
    const cv::Mat grey = cv::imread(argv[a], cv::IMREAD_GRAYSCALE);
    if (grey.empty()) continue;
    size = grey.size();
    std::vector<cv::Point2f> corners;
    if (!cv::findChessboardCorners(grey, pattern, corners,
                                   cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
      continue;
    cv::cornerSubPix(grey, corners, {11, 11}, {-1, -1},
                     {cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.001});
    object.push_back(board);
    image.push_back(corners);
  }
  if (object.size() < 3) {
    std::cerr << "too few boards found (" << object.size() << ")\n";
    return 1;
  }
  cv::Mat camera_matrix, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  const double rms = cv::calibrateCamera(object, image, size, camera_matrix, dist, rvecs, tvecs);
  std::cout << "views " << object.size() << " fx " << camera_matrix.at<double>(0, 0) << " fy "
            << camera_matrix.at<double>(1, 1) << " cx " << camera_matrix.at<double>(0, 2) << " cy "
            << camera_matrix.at<double>(1, 2) << " rms " << rms << "\n";
  return 0;
}
