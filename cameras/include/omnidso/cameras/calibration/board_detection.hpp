#pragma once
// Chessboard corners in a folder of images, for calibration (omnidso calibrate).
//
// A board of COLS × ROWS *inner* corners (OpenCV's pattern size) with square side `square`
// metres. Its corners lie in the board plane z = 0 at (c·square, r·square), c = 0..COLS−1,
// r = 0..ROWS−1, in OpenCV's row-major order (which findChessboardCorners reports).
//
// Detection: cv::findChessboardCornersSB (sector-based) on the image halved, then at full
// resolution, then cv::findChessboardCorners; the corners found are refined by
// cv::cornerSubPix at full resolution (window a third of the corner spacing). Corners are
// returned in this project's pixel convention (centre of the top-left pixel at (0, 0)), which
// is OpenCV's.

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace omnidso {

struct BoardSpec {
  int cols = 0;         // inner corners along a row
  int rows = 0;         // inner corners along a column
  double square = 1.0;  // metres (any unit: it only scales the board poses)

  int numCorners() const { return cols * rows; }
  // Corner k in the board frame (z = 0), k = r·cols + c.
  Eigen::Vector3d corner(int k) const;
};

// "COLSxROWS" (e.g. "8x6"; 'X' or '×' accepted), both ≥ 2, and square > 0; throws
// omnidso::Error saying what is wrong otherwise.
BoardSpec parseBoardSpec(const std::string& text, double square);

struct BoardView {
  std::string image;                     // path
  std::vector<Eigen::Vector2d> corners;  // numCorners() pixels, row-major
};

struct BoardDetections {
  int width = 0;
  int height = 0;
  std::vector<BoardView> views;             // images with a complete board, in file order
  std::vector<std::string> without_board;   // images where no board was found
};

// Image files of a folder (extensions .png .jpg .jpeg .bmp .tif .tiff .pgm .ppm, any case),
// sorted by name. Throws omnidso::Error for a missing path, a non-folder or no image files.
std::vector<std::string> listImageFiles(const std::string& folder);

// The board's corners in one 8-bit grey image; empty when not found.
std::vector<Eigen::Vector2d> detectBoardCorners(const cv::Mat& grey, const BoardSpec& board);

// Every image of the folder read and searched. Throws omnidso::Error naming the file for an
// unreadable image or an image whose size differs from the first one's, and when no image
// shows the board (the message suggests checking --board).
BoardDetections detectBoardsInFolder(const std::string& folder, const BoardSpec& board);

}  // namespace omnidso
