#include "omnidso/cameras/calibration/board_detection.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>

#include "omnidso/core/error.hpp"

namespace omnidso {
namespace fs = std::filesystem;

// Smaller images are searched at full resolution only (their squares are small already).
constexpr int kMinSideForHalfDetection = 480;

Eigen::Vector3d BoardSpec::corner(int k) const {
  return Eigen::Vector3d((k % cols) * square, (k / cols) * square, 0.0);
}

BoardSpec parseBoardSpec(const std::string& text, double square) {
  static const std::regex pattern(R"(^\s*(\d{1,4})\s*(?:x|X|×)\s*(\d{1,4})\s*$)");
  std::smatch m;
  if (!std::regex_match(text, m, pattern)) {
    throw Error("--board '" + text + "': expected COLSxROWS inner corners, e.g. 8x6");
  }
  BoardSpec board{std::stoi(m[1]), std::stoi(m[2]), square};
  if (board.cols < 2 || board.rows < 2) {
    throw Error("--board '" + text + "': a board needs at least 2x2 inner corners");
  }
  if (!(square > 0.0) || !std::isfinite(square)) {
    throw Error("--square " + std::to_string(square) + ": the square side must be positive");
  }
  return board;
}

std::vector<std::string> listImageFiles(const std::string& folder) {
  if (!fs::exists(folder)) throw fileError(folder, "no such folder");
  if (!fs::is_directory(folder)) throw fileError(folder, "not a folder");
  static const std::vector<std::string> extensions = {".png", ".jpg", ".jpeg", ".bmp",
                                                      ".tif", ".tiff", ".pgm", ".ppm"};
  std::vector<std::string> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (std::find(extensions.begin(), extensions.end(), ext) != extensions.end())
      files.push_back(entry.path().string());
  }
  if (files.empty()) {
    throw fileError(folder, "no image files (.png .jpg .jpeg .bmp .tif .tiff .pgm .ppm)");
  }
  std::sort(files.begin(), files.end());
  return files;
}

namespace {

// Half the side of cornerSubPix's search window: a third of the closest corner spacing
// (the window must not reach the neighbouring corners), 2 to 5 px: larger windows take in
// the curved edges of fisheye boards and bias the corner (on the real fisheye photos a
// 21 × 21 window quadrupled the calibration RMS).
int subPixHalfWindow(const std::vector<cv::Point2f>& corners, const BoardSpec& board) {
  double spacing = std::numeric_limits<double>::infinity();
  for (int k = 0; k < board.numCorners(); ++k) {
    if (k % board.cols + 1 < board.cols)
      spacing = std::min(spacing, static_cast<double>(cv::norm(corners[k + 1] - corners[k])));
    if (k + board.cols < board.numCorners())
      spacing = std::min(spacing, static_cast<double>(cv::norm(corners[k + board.cols] - corners[k])));
  }
  return std::clamp(static_cast<int>(spacing / 3.0), 2, 5);
}

void refineCorners(const cv::Mat& grey, const BoardSpec& board,
                   std::vector<cv::Point2f>& corners) {
  const int half = subPixHalfWindow(corners, board);
  cv::cornerSubPix(grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
}

// The sector-based detector on the image halved (INTER_AREA), its corners mapped back
// (full = 2·half + 0.5 in the pixel-centre convention). A quarter of the pixels makes it
// ~4× cheaper; cornerSubPix at full resolution then restores the accuracy (on the real
// fisheye photos the calibration RMS equals that of CALIB_CB_ACCURACY at full resolution
// to 0.001 px, for 1/10 of the time — docs/performance.md).
bool detectOnHalfImage(const cv::Mat& grey, const cv::Size& pattern,
                       std::vector<cv::Point2f>& corners) {
  cv::Mat half;
  cv::resize(grey, half, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  if (!cv::findChessboardCornersSB(half, pattern, corners, cv::CALIB_CB_NORMALIZE_IMAGE))
    return false;
  for (cv::Point2f& p : corners) p = 2.0f * p + cv::Point2f(0.5f, 0.5f);
  return true;
}

}  // namespace

std::vector<Eigen::Vector2d> detectBoardCorners(const cv::Mat& grey, const BoardSpec& board) {
  const cv::Size pattern(board.cols, board.rows);
  std::vector<cv::Point2f> found;
  bool ok = std::min(grey.cols, grey.rows) >= kMinSideForHalfDetection &&
            detectOnHalfImage(grey, pattern, found);
  if (!ok) {
    found.clear();
    ok = cv::findChessboardCornersSB(grey, pattern, found, cv::CALIB_CB_NORMALIZE_IMAGE);
  }
  if (!ok) {
    found.clear();
    ok = cv::findChessboardCorners(
        grey, pattern, found, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
  }
  std::vector<Eigen::Vector2d> corners;
  if (!ok || static_cast<int>(found.size()) != board.numCorners()) return corners;
  refineCorners(grey, board, found);
  for (const cv::Point2f& p : found) corners.emplace_back(p.x, p.y);
  return corners;
}

BoardDetections detectBoardsInFolder(const std::string& folder, const BoardSpec& board) {
  const std::vector<std::string> files = listImageFiles(folder);
  BoardDetections out;
  for (const std::string& file : files) {
    const cv::Mat grey = cv::imread(file, cv::IMREAD_GRAYSCALE);
    if (grey.empty()) throw fileError(file, "cannot read the image (corrupt or unsupported)");
    if (out.width == 0) {
      out.width = grey.cols;
      out.height = grey.rows;
    } else if (grey.cols != out.width || grey.rows != out.height) {
      throw fileError(file, "image size " + std::to_string(grey.cols) + "x" +
                                std::to_string(grey.rows) + " differs from " +
                                std::to_string(out.width) + "x" + std::to_string(out.height) +
                                " of " + files.front() + " (one camera per calibration)");
    }
    std::vector<Eigen::Vector2d> corners = detectBoardCorners(grey, board);
    if (corners.empty()) {
      out.without_board.push_back(file);
    } else {
      out.views.push_back({file, std::move(corners)});
    }
  }
  if (out.views.empty()) {
    throw fileError(folder, "no " + std::to_string(board.cols) + "x" +
                                std::to_string(board.rows) + " chessboard found in any of the " +
                                std::to_string(files.size()) +
                                " images; check --board (inner corners, COLSxROWS)");
  }
  return out;
}

}  // namespace omnidso
