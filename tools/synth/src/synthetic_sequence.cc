// Synthetic sequences: presets, cameras and in-order rendering with auto-exposure.
#include <omnidso/synth/synthetic_sequence.hpp>

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include <omnidso/cameras/rectification.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/trajectory_io.hpp>
#include <omnidso/synth/random.hpp>

namespace omnidso::synth {

std::vector<std::string> presetNames() { return {"room185", "room185_long", "room_pinhole90"}; }

SyntheticSequenceConfig presetConfig(const std::string& name) {
  SyntheticSequenceConfig config;
  if (name == "room185") return config;
  if (name == "room185_long") {
    config.frames = 6000;
    config.handheld.duration_s = 6000 / config.fps;
    return config;
  }
  if (name == "room_pinhole90") {
    config.camera_model = "pinhole";
    config.fov_deg = 90.0;
    return config;
  }
  std::string known;
  for (const std::string& preset : presetNames()) known += (known.empty() ? "" : ", ") + preset;
  throw Error(fmt::format("unknown synth preset '{}' (known: {})", name, known));
}

Camera syntheticCamera(const std::string& model_name, double fov_deg, int width, int height) {
  const std::string model = canonicalCameraModelName(model_name);
  if (model == "pinhole") return pinholeForFov(fov_deg, width, height);
  static const std::map<std::string, std::vector<double>> kExtraParams = {
      {"ucm", {0.97}},
      {"eucm", {0.55, 1.1}},
      {"ds", {0.2, 0.55}},
      {"kb4", {-0.01, 0.002, 0.0, 0.0}},
      {"fov", {0.93}},
      {"pinhole-radtan", {0.0, 0.0, 0.0, 0.0}},
      {"ucm-radtan", {0.97, 0.0, 0.0, 0.0, 0.0}},
  };
  const std::vector<double>& extra = kExtraParams.at(model);
  Eigen::VectorXd params(4 + static_cast<Eigen::Index>(extra.size()));
  params.head<4>() << 1.0, 1.0, 0.0, 0.0;
  for (size_t i = 0; i < extra.size(); ++i) params[4 + static_cast<Eigen::Index>(i)] = extra[i];
  // r₁: image radius of the unit-focal model at the half field of view.
  const Camera unit = Camera::create(model, params, width, height);
  const double half_fov = 0.5 * fov_deg * M_PI / 180.0;
  const Eigen::Vector3d ray(std::sin(half_fov), 0.0, std::cos(half_fov));
  Eigen::Vector2d uv;
  const bool ok = std::visit([&](const auto& m) { return m.project(ray, uv); }, unit.model());
  if (!ok || !(uv.x() > 0)) {
    throw Error(fmt::format("camera model '{}' cannot see {}° (half angle beyond its domain)",
                            model, fov_deg));
  }
  const double focal = 0.5 * std::min(width, height) / uv.x();
  params.head<4>() << focal, focal, 0.5 * (width - 1), 0.5 * (height - 1);
  return Camera::create(model, params, width, height);
}

double roundExposure(double exposure_ms) { return std::round(exposure_ms * 1e4) / 1e4; }

namespace {

BearingTable bearingsOf(const Camera& camera, int samples_per_axis) {
  const Eigen::VectorXd params = camera.params();
  return makeBearingTable(camera, camera.width(), camera.height(), samples_per_axis, params[2],
                          params[3]);
}

}  // namespace

SyntheticSequence::SyntheticSequence(const SyntheticSequenceConfig& config)
    : config_(config),
      camera_(syntheticCamera(config.camera_model, config.fov_deg, config.width, config.height)),
      scene_(std::make_unique<Scene>(makeRoomScene(config.room, config.seed))),
      exposure_ms_(roundExposure(config.initial_exposure_ms)) {
  if (config.frames < 1) throw Error("a synthetic sequence needs at least one frame");
  if (!(config.fps > 0)) throw Error("the frame rate must be positive");
  renderer_ = std::make_unique<Renderer>(*scene_, bearingsOf(camera_, config.samples_per_axis),
                                         config.photometric, config.threads,
                                         counterHash(config.seed, 0x401535));
  if (config.trajectory_file.empty()) {
    HandheldMotionConfig handheld = config.handheld;
    handheld.duration_s = std::max(handheld.duration_s, config.frames / config.fps + 1.0);
    handheld_ = std::make_unique<HandheldMotion>(scene_->freeSpace(), handheld,
                                                 counterHash(config.seed, 0x3071));
    for (int k = 0; k < config.frames; ++k) {
      ground_truth_.push_back({k / config.fps, handheld_->poseAt(k / config.fps)});
    }
  } else {
    ground_truth_ = recordedCameraTrajectory(readTrajectoryTum(config.trajectory_file),
                                             config.trajectory_file, scene_->freeSpace(),
                                             config.fps, config.frames);
    // Time from 0 like the hand-held sequences; t₀ + k/fps → k/fps.
    for (size_t k = 0; k < ground_truth_.size(); ++k) {
      ground_truth_[k].timestamp = static_cast<double>(k) / config.fps;
    }
  }
}

SE3d SyntheticSequence::poseAt(double t) const {
  if (handheld_) return handheld_->poseAt(t);
  const double position = std::clamp(t * config_.fps, 0.0, numFrames() - 1.0);
  const size_t k = std::min(static_cast<size_t>(position), ground_truth_.size() - 1);
  if (k + 1 >= ground_truth_.size()) return ground_truth_.back().pose;
  return interpolate(ground_truth_[k].pose, ground_truth_[k + 1].pose,
                     position - static_cast<double>(k));
}

SyntheticSequence::Frame SyntheticSequence::renderNext() {
  if (!hasNext()) throw Error("synthetic sequence: no frame left to render");
  Frame frame;
  frame.index = next_;
  frame.timestamp_s = ground_truth_[static_cast<size_t>(next_)].timestamp;
  frame.pose = ground_truth_[static_cast<size_t>(next_)].pose;
  frame.exposure_ms = exposure_ms_;
  // The exposure is centred on the timestamp: blur poses at t + ((j + ½)/P − ½)·t_exp.
  std::vector<SE3d> poses;
  const int blur = std::max(1, config_.motion_blur_samples);
  if (blur == 1) {
    poses.push_back(frame.pose);
  } else {
    for (int j = 0; j < blur; ++j) {
      const double offset_s = ((j + 0.5) / blur - 0.5) * frame.exposure_ms * 1e-3;
      poses.push_back(poseAt(frame.timestamp_s + offset_s));
    }
  }
  frame.image = renderer_->render(poses, frame.exposure_ms, static_cast<std::uint64_t>(next_));
  exposure_ms_ = roundExposure(
      config_.auto_exposure.next(exposure_ms_, renderer_->meanValidPixelValue(frame.image)));
  ++next_;
  return frame;
}

}  // namespace omnidso::synth
