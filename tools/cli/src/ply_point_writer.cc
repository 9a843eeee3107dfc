#include <fmt/core.h>

#include <cstdio>
#include <omnidso/cli/ply_point_writer.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso::cli {

PlyPointWriter::PlyPointWriter(std::string path)
    : path_(std::move(path)), body_path_(path_ + ".body"), body_(body_path_) {
  if (!body_) throw Error(body_path_ + ": cannot write");
}

PlyPointWriter::~PlyPointWriter() {
  if (!finished_) {
    body_.close();
    std::remove(body_path_.c_str());
  }
}

void PlyPointWriter::add(const OdometryPoint& p) {
  body_ << fmt::format("{:.6f} {:.6f} {:.6f} {:.2f} {}\n", p.position_world.x(),
                       p.position_world.y(), p.position_world.z(), p.intensity, p.segment);
  ++count_;
}

void PlyPointWriter::finish(const Odometry& odometry) {
  odometry.forEachPoint([this](const OdometryPoint& p) { add(p); });
  body_.close();
  if (!body_) throw Error(body_path_ + ": write failed (disk full?)");
  {
    std::ofstream ply(path_, std::ios::binary);
    if (!ply) throw Error(path_ + ": cannot write");
    ply << "ply\nformat ascii 1.0\nelement vertex " << count_
        << "\nproperty float x\nproperty float y\nproperty float z\n"
           "property float intensity\nproperty int segment\nend_header\n";
    std::ifstream body(body_path_, std::ios::binary);
    if (!body) throw Error(body_path_ + ": cannot read back");
    if (count_ > 0) ply << body.rdbuf();
    if (!ply) throw Error(path_ + ": write failed (disk full?)");
  }
  std::remove(body_path_.c_str());
  finished_ = true;
}

}  // namespace omnidso::cli
