#pragma once
// points.ply of `omnidso run`, written while the odometry runs. Every point that leaves the
// window goes to disk at once (Odometry::setRetiredPointSink), so that a long run's memory is
// bounded by the window and does not grow with its map. PLY states the vertex count in its
// header, before the vertices: they go to a body file beside the target first, and finish()
// writes the header with the count and then copies the body after it.
//
// ASCII PLY, one vertex per line: x y z (world, metres) intensity segment.

#include <cstddef>
#include <fstream>
#include <omnidso/frontend/odometry.hpp>
#include <string>

namespace omnidso::cli {

class PlyPointWriter {
 public:
  // Creates PATH.body now (an unwritable directory fails before the run).
  explicit PlyPointWriter(std::string path);
  ~PlyPointWriter();  // removes PATH.body if finish() was never reached
  PlyPointWriter(const PlyPointWriter&) = delete;
  PlyPointWriter& operator=(const PlyPointWriter&) = delete;

  void add(const OdometryPoint& point);
  // Adds the points still held by `odometry` (active ones, and any it kept itself), writes
  // PATH and removes PATH.body. Throws omnidso::Error when a write fails (a full disk).
  void finish(const Odometry& odometry);
  size_t count() const { return count_; }

 private:
  std::string path_, body_path_;
  std::ofstream body_;
  size_t count_ = 0;
  bool finished_ = false;
};

}  // namespace omnidso::cli
