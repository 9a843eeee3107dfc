#pragma once
// Internal to the odometry: the state behind the Odometry facade (odometry.hpp has the
// pipeline of one frame) and the steps that act on it, one job per file:
//   odometry.cc                 the facade, set-up of the options, the read accessors;
//   odometry_initialization.cc  a segment's start (Initializer → the first two keyframes)
//                               and its end when tracking is lost;
//   odometry_tracking.cc        the tracking side (steps 2, 4) and its hand-off to mapping:
//                               the real-time queue and the published tracking reference;
//   odometry_mapping.cc         the mapping side: epipolar search (step 3), then for a
//                               keyframe the window, outliers, marginalisation (step 5);
//   odometry_activation.cc      converged candidates → window points (occupancy grid,
//                               refinement against the window's keyframes);
//   odometry_race.cc            the first segment's start raced against a rival's.
// Tracking and mapping are two threads in the real-time mode: they share only the
// published tracking reference (under reference_mutex) and the frame records (a deque,
// so records stay put); everything else belongs to one side.

#include <Eigen/Core>
#include <array>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <omnidso/core/content_mask.hpp>
#include <omnidso/core/task_pool.hpp>
#include <omnidso/frontend/frame_placement.hpp>
#include <omnidso/frontend/mapping_worker.hpp>
#include <omnidso/frontend/odometry.hpp>
#include <string>
#include <vector>

namespace omnidso {

// The initialisation race applies (InitializationRaceOptions): a rival snap angle below the
// configured one, not in the real-time mode.
bool raceApplies(const OdometryOptions& options);

struct Odometry::Impl {
  Camera camera;
  Mask mask;  // where pixels are selected: the content, eroded by content_margin_px
  OdometryOptions options;
  // The content of every pyramid level (not eroded), attached to every frame's pyramid so
  // that target samples leaving it are invalid; null when every pixel is content or
  // reject_targets_outside_content is off.
  std::shared_ptr<const std::vector<Mask>> content_levels;
  // The content's bounding box (content_mask.hpp, contentExtent): the image size the
  // keyframe decision's flow is relative to.
  ContentExtent content_extent;
  // The (eroded) mask's pixels with content: the area activation's grid spreads num_points
  // over (activation_grid.hpp). The mask is fixed once built, so it is counted once.
  double content_area = 0.0;

  std::unique_ptr<SlidingWindow> window;
  // The compute threads (OdometryOptions::compute_threads): data-parallel steps whose results
  // do not depend on the thread count. Null with one thread.
  std::unique_ptr<TaskPool> pool;
  // What tracking aligns to: set by the mapping side (setTrackingReference), picked up by
  // the tracking side at its next frame (adoptPublishedReference). In the real-time mode the
  // two sides are two threads, hence the mutex.
  struct TrackingReference {
    std::shared_ptr<const CoarseTracker> tracker;
    int id = -1;
    SE3d T_world_ref;
    double exposure = 1.0;
    Eigen::Vector2d affine = Eigen::Vector2d::Zero();
  };
  std::mutex reference_mutex;
  TrackingReference published;  // guarded by reference_mutex
  TrackingReference reference;  // the tracking side's copy
  std::unique_ptr<Initializer> initializer;
  std::map<int, std::vector<ImmaturePoint>> immature;  // by host keyframe
  ActivationDensity activation_density;  // the grid's cell scale; reset at every segment

  std::deque<FrameRecord> frames;  // a deque: records stay put while the mapper writes timings
  std::map<int, KeyframeRecord> keyframes;  // every keyframe ever; poses kept current
  std::deque<OdometryPoint> points;         // marginalised points (a deque: no 2× regrowth)
  std::function<void(const OdometryPoint&)> retired_point_sink;  // replaces `points` if set
  std::vector<std::string> log;

  bool initialized = false;
  int segment = 0;
  int first_frame_index = -1;
  std::shared_ptr<const ImagePyramid> first_pyramid;
  double first_exposure = 1.0;
  double last_rmse = std::numeric_limits<double>::infinity();
  double first_rmse = std::numeric_limits<double>::infinity();  // since the newest keyframe
  SE3d T_world_last, T_world_prev;
  Eigen::Vector2d last_affine = Eigen::Vector2d::Zero();
  double last_exposure = 1.0;  // of the last tracked frame
  // Real-time mode, tracking side only: the affine the tracker gave each keyframe it sent to
  // mapping, until that keyframe becomes the reference (adoptPublishedReference).
  std::map<int, Eigen::Vector2d> tracked_keyframe_affine;
  int frames_since_keyframe = 0;
  Eigen::VectorXd last_intrinsics;  // of the last finished segment
  // The initialisation race (odometry.hpp): the window's cost RMS once segment 0's window
  // first held race.keyframes keyframes (NaN before), and segment 0's initial pair's first
  // frame, the frame it snapped at (−1 before) and the pair's pose: two starts that agree on
  // all three computed the same, their acceptance included.
  double race_cost = std::numeric_limits<double>::quiet_NaN();
  int race_first_frame = -1, race_snap_frame = -1;
  std::array<double, 7> race_initial_pose{};
  void noteRaceCost(const WindowSolveSummary& summary);

  // odometry.cc ------------------------------------------------------------------------
  Impl(const Camera& c, OdometryOptions o, const Mask& image_mask);
  // A frame's way in: initialisation or tracking (the facade checks the input and builds the
  // pyramid, which a race's two sides share).
  FrameRecord& addFrame(std::shared_ptr<const ImagePyramid> pyramid, double timestamp,
                        double exposure);
  void newInitializer();
  SE3d keyframePose(int id) const;
  void say(const std::string& message) { log.push_back(message); }
  void refreshKeyframeRecords();
  // The window's active points (those not at infinity), in the world.
  void visitActivePoints(const std::function<void(const OdometryPoint&)>& visit) const;
  void retirePoint(const OdometryPoint& point);  // to the sink, or kept in `points`

  // odometry_initialization.cc ---------------------------------------------------------
  void initialize(FrameRecord& record, std::shared_ptr<const ImagePyramid> pyramid,
                  double exposure);
  void loseTracking(const FrameRecord& record, std::shared_ptr<const ImagePyramid> pyramid,
                    double exposure);

  // odometry_tracking.cc ---------------------------------------------------------------
  void trackFrame(FrameRecord& record, std::shared_ptr<const ImagePyramid> pyramid,
                  double exposure);
  // Mapping side: a new tracking reference from the window's keyframe `id` and its points.
  void setTrackingReference(int id);
  // Tracking side: a newer reference from the mapping side replaces the current one.
  void adoptPublishedReference();
  // In the real-time mode: waits for the mapping thread (before re-initialising, and before
  // results are read).
  void drainMapping();

  // odometry_mapping.cc ----------------------------------------------------------------
  // What a tracked frame hands to mapping. `record` stays valid: frames is a deque.
  struct MappingJob {
    FrameRecord* record = nullptr;
    std::shared_ptr<const ImagePyramid> pyramid;
    double exposure = 1.0;
    SE3d T_world_frame;  // the reference's pose when tracked · T_frame_ref⁻¹
    Eigen::Vector2d affine = Eigen::Vector2d::Zero();
    bool make_keyframe = false;
    int reference_id = -1;  // the keyframe tracking aligned the frame to
    SE3d T_frame_reference;  // what tracking measured
  };
  // The frame's world pose placed by its reference keyframe's current estimate
  // (frame_placement.hpp): in the real-time mode a solve may have moved the reference since
  // the frame was tracked. A reference that has left the window keeps the job's pose.
  SE3d placeInWindow(const MappingJob& job) const;
  // Epipolar-curve search of every window keyframe's immature points in the frame (step 3),
  // then, for a keyframe, the window (step 5).
  void map(const MappingJob& job);
  void makeKeyframe(FrameRecord& record, std::shared_ptr<const ImagePyramid> pyramid,
                    double exposure, const SE3d& T_world_frame, const Eigen::Vector2d& affine);
  void selectImmaturePoints(int id, const ImagePyramid& pyramid);
  // Keyframe `id`'s candidates (reads only the image, the mask, the camera and the options).
  std::vector<ImmaturePoint> selectCandidates(int id, const ImagePyramid& pyramid) const;
  void collectMarginalizedPoints();

  // odometry_activation.cc -------------------------------------------------------------
  void activatePoints(int newest_id, const std::vector<int>& leaving);

  // Declared last: destroyed first, so queued jobs finish while everything they use exists.
  std::unique_ptr<MappingWorker> worker;
};

}  // namespace omnidso
