#pragma once
// A synthetic sequence: the room scene, a camera of any model, a camera path (procedural
// hand-held or a recorded trajectory), the photometric model with auto-exposure, and the
// renderer. Frames are rendered in order because auto-exposure reacts to the previous
// frame, as a camera's does.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <omnidso/cameras/camera.hpp>
#include <omnidso/core/image.hpp>
#include <omnidso/core/trajectory.hpp>
#include <omnidso/synth/motion.hpp>
#include <omnidso/synth/photometric_model.hpp>
#include <omnidso/synth/renderer.hpp>
#include <omnidso/synth/scene.hpp>

namespace omnidso::synth {

struct SyntheticSequenceConfig {
  std::string camera_model = "ucm";  // any name Camera::create accepts
  double fov_deg = 185.0;            // across the image's inscribed circle (syntheticCamera)
  int width = 480;
  int height = 480;
  int frames = 500;  // a recorded trajectory may give fewer (its duration × fps + 1)
  double fps = 20.0;
  std::string trajectory_file;  // TUM-format body poses; empty → procedural hand-held
  std::uint64_t seed = 1;
  int samples_per_axis = 2;     // n × n samples per pixel
  int threads = 2;
  int motion_blur_samples = 1;  // poses spread over the exposure (1 = no blur)
  double initial_exposure_ms = 10.0;
  AutoExposure auto_exposure;
  PhotometricModel photometric;
  RoomSceneConfig room;
  HandheldMotionConfig handheld;
};

// "room185": UCM 480×480, 185°, hand-held, 500 frames at 20 Hz (the paper's indoor case).
// "room185_long": the same, 6000 frames (5 minutes) for soak tests.
// "room_pinhole90": the same scene and motion through a 90° pinhole (the ablation).
// Throws omnidso::Error listing the presets for an unknown name.
SyntheticSequenceConfig presetConfig(const std::string& name);
std::vector<std::string> presetNames();

// A camera of the given model whose inscribed image circle (radius min(w, h)/2 around the
// image centre) spans fov_deg: the focal length f = R / r₁(fov/2), with r₁ the radius of the
// unit-focal model at that angle. Model-specific parameters are fixed typical values
// (ucm ξ = 0.97; eucm α = 0.55, β = 1.1; ds ξ = 0.2, α = 0.55; kb4 k = [−0.01, 0.002, 0, 0];
// fov ω = 0.93, near TUM monoVO's).
// A pinhole camera takes fov_deg horizontally (pinholeForFov) and needs fov_deg < 180.
Camera syntheticCamera(const std::string& model_name, double fov_deg, int width, int height);

class SyntheticSequence {
 public:
  explicit SyntheticSequence(const SyntheticSequenceConfig& config);

  struct Frame {
    int index = 0;
    double timestamp_s = 0;
    double exposure_ms = 0;
    SE3d pose;  // T_world_cam at the timestamp (the centre of the exposure)
    ImageU8 image;
  };
  bool hasNext() const { return next_ < numFrames(); }
  Frame renderNext();

  int numFrames() const { return static_cast<int>(ground_truth_.size()); }
  const SyntheticSequenceConfig& config() const { return config_; }
  const Camera& camera() const { return camera_; }
  const Scene& scene() const { return *scene_; }
  const Renderer& renderer() const { return *renderer_; }
  // T_world_cam of every frame, at the frame timestamps k / fps.
  const Trajectory& groundTruth() const { return ground_truth_; }
  // Pose at any time (hand-held: the continuous path; recorded: interpolated between frames).
  SE3d poseAt(double t) const;

 private:
  SyntheticSequenceConfig config_;
  Camera camera_;
  std::unique_ptr<Scene> scene_;  // stable address for the renderer
  std::unique_ptr<Renderer> renderer_;
  std::unique_ptr<HandheldMotion> handheld_;
  Trajectory ground_truth_;
  int next_ = 0;
  double exposure_ms_;
};

// Exposure times are rounded to 1e-4 ms before rendering so that times.txt (written with a
// round-trip representation) holds exactly the value used.
double roundExposure(double exposure_ms);

}  // namespace omnidso::synth
