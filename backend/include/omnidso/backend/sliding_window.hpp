#pragma once
// The sliding window of photometric bundle adjustment (paper Sec. V-A, V-D; DSO Sec. 2.3):
// N_f keyframes (pose T_world_cam, affine [a, b], exposure t), active points hosted by
// keyframes (host pixel + inverse distance 1/‖x‖), and one photometric residual
// (eq. 5–7, DSO's 8-pixel pattern) per (point, target keyframe) pair that projects validly.
// Everything lives in ONE persistent ceres::Problem, jointly over poses, inverse distances,
// affine parameters and — when enabled — the intrinsics shared by all keyframes; the
// marginalisation priors stay in it.
//
// Deferred residual blocks: where the native solver solves level 0 (WindowOptions::
// native_solver, analytic residuals, no Jacobi scaling), a photometric residual is recorded
// by its point and target only (WindowPoint::residuals holds nullptr), and its residual block
// enters the problem when a Ceres path needs it: for the points being marginalised (the
// marginaliser linearises through Ceres), before a Ceres solve, and for mutableProblem(). The
// native solver reads the same residuals from the points. Adding and removing ≈ 12 000 blocks
// per keyframe step — Ceres's hash sets per parameter block — was a quarter of a keyframe's
// mapping time on one thread (docs/performance.md, "Deferred residual blocks").
//
// Solving: points form the first elimination group, so Ceres's Schur complement removes them
// (DENSE_SCHUR while the reduced camera system is small, SPARSE_SCHUR beyond);
// Levenberg–Marquardt with an iteration limit (DSO: at most 6 Gauss–Newton iterations per
// keyframe; we default to 2, see WindowOptions::max_iterations) and a time limit.
//
// Gauge (7 DoF of monocular odometry, plus the brightness offset of the affine model):
//  - pose: the first keyframe's pose is held constant while it is in the window;
//  - brightness: its affine block is held constant too (e^{a_j − a_i} sees only differences);
//  - scale: one inverse distance — the anchor keyframe's point with the most residuals when
//    the window is first optimised — is held constant; when that point leaves the window
//    (marginalised or dropped), the next solve holds another one (WindowOptions::
//    keep_scale_anchor).
// Marginalisation treats constant blocks as known, so the priors built while the anchors are
// constant carry the gauge: once the anchor keyframe has left, the prior fixes the pose and
// brightness gauge. It does not hold the scale well enough: the prior's Jacobian stays at its
// linearisation point while the photometric residuals are relinearised at every iteration,
// so along the similarity direction — where the photometric energy is flat — the prior's
// linear residual has a gradient of its own, and every iteration moves the scale a little
// (DSO projects its steps off the gauge null spaces from its third iteration on). Measured
// on the independent renders (docs/performance.md, "The scale gauge"): with the scale left
// to the prior, D3's full image (seed 0) read 1.7 % of the path at 2 iterations per keyframe
// and 5.3 % at 6; with the anchor re-chosen, 0.64 % and 0.49 %.
//
// Out of bounds: every residual is wrapped in OutOfBoundsPenalty, so that a step moving some
// pattern out of the image costs the outlier energy instead of making Ceres reject the step;
// such residuals are dropped before and after each solve (DSO's OOB state).
//
// Outliers: after a solve, a residual whose energy (without the robust loss) exceeds
// outlier_energy_per_pixel × pattern size is removed (DSO's 12² per pixel), or with
// outlier_threshold.adaptive the larger of its host's and target's bounds measured from the
// window's residuals (outlier_threshold.hpp); a point left with fewer than
// min_residuals_per_point residuals is dropped.
//
// Marginalisation (marginalizeKeyframe): points hosted by the keyframe, and points no longer
// observed by the two newest keyframes, are marginalised (points with no residual are
// dropped: they carry no information); residuals of the remaining points in the keyframe
// are dropped (DSO, to keep the Hessian sparse); then the keyframe's pose and affine blocks
// are marginalised into the prior (marginalizer.hpp). Where the residual blocks are deferred
// the points' Schur complement is formed from the native terms instead of Ceres's
// evaluation (window_point_marginalization.hpp), the same prior without their blocks.

#include <ceres/problem.h>

#include <Eigen/Core>
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <omnidso/backend/keyframe_marginalization_policy.hpp>
#include <omnidso/backend/marginalizer.hpp>
#include <omnidso/backend/new_point_refinement.hpp>
#include <omnidso/backend/outlier_threshold.hpp>
#include <omnidso/backend/parameter_slots.hpp>
#include <omnidso/backend/photometric_factory.hpp>
#include <omnidso/backend/window_problem.hpp>
#include <omnidso/core/task_pool.hpp>
#include <omnidso/core/pyramid.hpp>
#include <omnidso/core/se3.hpp>
#include <omnidso/residuals/evaluation_reuse.hpp>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>
#include <string>
#include <vector>

namespace omnidso {

struct WindowOptions {
  int max_keyframes = 7;  // N_f
  bool optimize_intrinsics = true;
  // intrinsics_prior.hpp: energy per squared pixel of image displacement pulling the
  // intrinsics towards the calibration they started from; 0 leaves them free. The default is
  // DSO's prior (a Hessian of 5·10⁹ on f/50, i.e. 2·10⁶ per px²): on a 90° crop the free
  // intrinsics wandered by 2–3 px and took the scale with them (D2: 5.9 % of the path and
  // −100 % scale drift free, 1.5 % held; docs/performance.md, "The calibration prior").
  double intrinsics_prior_weight = 2e6;
  DifferentiationMode differentiation = DifferentiationMode::kAnalytic;
  // Per keyframe. The tracker's estimates arrive nearly right: on four rendered sequences 2
  // iterations were as accurate as 3, 4 or 6 (docs/performance.md) at a third of the cost
  // of 6. (Ceres evaluates residuals and Jacobian once more after the last step, so 2
  // iterations cost 3 Jacobian and 2 residual evaluations; reuse_evaluations skips the third
  // Jacobian evaluation.)
  int max_iterations = 2;
  // Ceres's function_tolerance: stop once an iteration lowers the cost by less than this
  // fraction (DSO likewise stops early once its updates become small).
  double function_tolerance = 1e-6;
  double max_solver_time_s = 1e6;
  // Ceres's jacobi_scaling (columns of J scaled to unit norm). Off: Levenberg–Marquardt
  // already damps with diag(JᵀJ), and on the four sequences the ATE was the same to three
  // digits without it while the window was ≈ 2 % faster (docs/performance.md).
  bool jacobi_scaling = false;
  // Skip the evaluation Ceres makes after the last allowed step and never uses (its
  // residuals are copied from the last candidate, its Jacobians zero; evaluation_reuse.hpp):
  // the same solution bit for bit, one Jacobian evaluation fewer per solve.
  bool reuse_evaluations = true;
  // Hold the scale with a constant inverse distance in every solve: when the anchor point
  // leaves, the next solve picks another (see the header comment, "Gauge"). false leaves the
  // scale to the prior once an anchor has been marginalised (the behaviour before; an
  // ablation; an anchor dropped as an outlier is replaced either way).
  bool keep_scale_anchor = true;
  // The native solver takes every photometric residual's Jacobian with respect to a frame at
  // that frame's first estimate once a prior holds it (and the intrinsics' likewise), as DSO
  // does, so that the residuals and the priors share one linearisation point and one null
  // space; the residuals' values, their robust weights and the image gradients stay at the
  // current estimate (window_photometric_terms.hpp). With Jacobians at the current
  // estimate, the priors' null space (at x̄) and the residuals' (at x) part once the
  // translations move, and the priors push along the scale: D3's full image drifted by +6 %
  // in three seeds of five (docs/performance.md, "First-estimate Jacobians in the window").
  // Setting `window.first_estimate_jacobians`; the Ceres path (native_solver = false)
  // linearises at x either way. false: the native solve linearises at x and the points'
  // marginalisation takes the whole Jacobian at x̄, as the Ceres path does.
  bool first_estimate_jacobians = true;
  // The native window solver (window_solver.hpp) instead of ceres::Solve: the same problem,
  // the same Levenberg–Marquardt semantics, faster (docs/performance.md, "The native window
  // solver"). Level 0 with hand-derived residuals and without jacobi_scaling only; other
  // solves (the coarser levels of optimizeCoarseToFine, autodiff, Jacobi scaling, a prior on
  // a point) stay on Ceres. Single-threaded (num_threads is Ceres's). On by default: the
  // development set's accuracy is unchanged within its seed spread and the window solve takes
  // ≈ 1/4 of Ceres's time; false is ceres::Solve, for ablations and as the oracle.
  bool native_solver = true;
  int num_threads = 1;
  // Reduced camera systems up to this size use DENSE_SCHUR, larger ones SPARSE_SCHUR.
  int dense_schur_max_size = 400;
  // The outlier bound: measured per keyframe (outlier_threshold.hpp) when
  // outlier_threshold.adaptive, else outlier_energy_per_pixel for every residual. The fixed
  // bound also stays the one for residuals between keyframes that have no measured bound.
  double outlier_energy_per_pixel = kDsoOutlierEnergyPerPixel;
  OutlierThresholdOptions outlier_threshold;
  int min_residuals_per_point = 1;
  // A point leaving the window with fewer residuals than this is dropped, not marginalised
  // (DSO's setting_minGoodActiveResForMarg, 3): its inverse distance rests on one or two
  // patches, where a wrong match along the epipolar curve cannot yet be told from a right
  // one, and a prior keeps whatever it linearises for as long as the window runs. A dropped
  // point is not kept for the map (points.ply) either. On the native pinhole H12p the first
  // marginalisation took 1 329 points, 685 of them with one or two residuals
  // (docs/performance.md, "DSO's rule for the points a prior takes").
  int min_residuals_to_marginalize = 3;
  double huber_threshold = kDsoHuberThreshold;
  // affine_prior.hpp: every keyframe's [a, b] tied to 0 (calibrated photometry, as DSO);
  // 0 frees a parameter (DSO's uncalibrated mode, which `omnidso run` chooses for data without
  // exposure times: cli::applyPhotometricMode).
  double affine_prior_weight_a = 1e8;
  double affine_prior_weight_b = 1e6;
  double gradient_weight_c = kDsoGradientWeightC;
  int pattern_spread = 1;  // OdometryOptions::pattern_spread
  // The image gradient in the solve's Jacobians: false, the bilinear interpolant's derivative;
  // true, central differences blended bilinearly (DSO's; core/interpolation.hpp,
  // sampleBilinearWithCentralGradient). The activation's refinement has its own setting
  // (NewPointRefinementOptions). Measured in docs/performance.md, "The image gradient in the
  // Jacobians".
  bool central_difference_gradients = false;
  // Capacity of the inverse-distance storage (parameter_slots.hpp): the most points the
  // window can hold at once; addPoint throws beyond it.
  int max_points = 1 << 16;
};

struct WindowKeyframe {
  int id = 0;
  double timestamp = 0.0;
  double exposure = 1.0;  // t, any unit consistent across frames
  std::array<double, 7> pose{};  // T_world_cam as [qx qy qz qw tx ty tz]
  std::array<double, 2> affine{};  // [a, b]
  std::shared_ptr<const ImagePyramid> pyramid;
  // θ (outlier_threshold.hpp), measured while this keyframe was the newest; 0: none.
  double outlier_energy = 0.0;

  SE3d T_world_cam() const { return SE3d::fromParameters(pose.data()); }
};

struct WindowPoint {
  // inverse_distance_slot: the point's parameter block, owned by the window's ParameterSlots.
  explicit WindowPoint(double& inverse_distance_slot) : inverse_distance(inverse_distance_slot) {}

  double& inverse_distance;
  int id = 0;
  int host_id = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // level 0
  HostPatch<kWindowPatternSize> patch;
  // By target keyframe id; nullptr while the block is deferred (not yet in the problem).
  std::map<int, ceres::ResidualBlockId> residuals;

  // The host intensity at the point's own pixel: offset (0, 0) is index 4 of DSO's pattern.
  float hostIntensity() const { return static_cast<float>(patch.intensity[4]); }
};

// A point as it left the window by marginalisation: its last estimate, in the world.
struct MarginalizedPoint {
  Eigen::Vector3d position_world;
  float intensity = 0.f;  // host intensity at the point's pixel
};

struct WindowSolveSummary {
  int iterations = 0;
  // Iterations whose step Ceres accepted (the others only shrank the trust region), as
  // Ceres counts them: iteration 0 included.
  int successful_iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double solve_ms = 0.0;
  double evaluation_ms = 0.0;     // residuals and Jacobians (Ceres's own accounting)
  double linear_solver_ms = 0.0;  // Schur complement and the reduced camera system
  int num_residuals = 0;
  int num_points = 0;
  int num_keyframes = 0;
  bool usable = false;
  std::string linear_solver;
  std::string message;  // Ceres's termination message (the native solver writes the same)
};

struct WindowSolverWorkspace;  // window_solver.hpp

class SlidingWindow {
 public:
  // intrinsics: the level-0 parameters of `model_name` ([fx fy cx cy …]).
  SlidingWindow(const std::string& model_name, const Eigen::VectorXd& intrinsics,
                WindowOptions options = {});
  ~SlidingWindow();
  SlidingWindow(const SlidingWindow&) = delete;
  SlidingWindow& operator=(const SlidingWindow&) = delete;

  // Adds a keyframe, and residuals of every active point that projects validly into it.
  void addKeyframe(int id, double timestamp, double exposure, const SE3d& T_world_cam,
                   const Eigen::Vector2d& affine, std::shared_ptr<const ImagePyramid> pyramid);

  // Activates a point hosted by keyframe host_id at a level-0 pixel. Returns its id, or -1
  // when the pattern leaves the host image or no other keyframe observes it validly.
  int addPoint(int host_id, const Eigen::Vector2d& pixel, double inverse_distance);
  // A candidate's inverse distance optimised against every window keyframe with everything
  // else held at the window's estimate, and the verdict whether to activate it
  // (new_point_refinement.hpp). Changes nothing in the window.
  NewPointRefinement refineNewPoint(int host_id, const Eigen::Vector2d& pixel,
                                    double inverse_distance,
                                    const NewPointRefinementOptions& options) const;

  // Compute threads for the native solve's evaluation and reduced system (task_pool.hpp; the
  // results do not depend on them). Not owned; null: the calling thread alone.
  void setTaskPool(TaskPool* pool) { pool_ = pool; }

  WindowSolveSummary optimize();
  // Coarse to fine: the same problem with every photometric residual evaluated on pyramid
  // levels num_levels−1 … 0 in turn (host patch and target image of that level, intrinsics
  // scaled), widening the convergence basin for large initial errors.
  WindowSolveSummary optimizeCoarseToFine(int num_levels);
  // Removes outlier residuals, then points left with too few residuals. Returns the number
  // of residuals removed.
  int removeOutliers();

  // The policy's view of the window (oldest first) and the keyframes it would remove.
  std::vector<KeyframeSummary> keyframeSummaries() const;
  std::vector<int> keyframesToMarginalize(const KeyframeMarginalizationOptions& policy) const;
  void marginalizeKeyframe(int id);

  // Read access.
  int numKeyframes() const { return static_cast<int>(keyframes_.size()); }
  int numPoints() const { return static_cast<int>(points_.size()); }
  int numResiduals() const;
  std::vector<int> keyframeIds() const;  // oldest first
  const WindowKeyframe& keyframe(int id) const;
  const std::map<int, std::unique_ptr<WindowPoint>>& points() const { return points_; }
  const Eigen::VectorXd& intrinsics() const { return intrinsics_; }
  // World position of an active point (host pose · bearing / inverse distance).
  Eigen::Vector3d pointInWorld(const WindowPoint& point) const;
  bool hasPrior() const { return has_prior_; }
  // The point whose inverse distance holds the scale gauge in the solves, or -1 when none
  // does (before the first solve; once it was marginalised with keep_scale_anchor off).
  int scaleAnchorPointId() const { return scale_anchor_point_id_; }
  // Points marginalised since the last call (for the map the odometry writes out).
  std::vector<MarginalizedPoint> takeMarginalizedPoints();

  // Test access: set the state directly (e.g. to perturb it).
  WindowKeyframe& mutableKeyframe(int id);
  WindowPoint& mutablePoint(int id);
  Eigen::VectorXd& mutableIntrinsics();
  // Test access: the ceres::Problem, every deferred residual block added to it first, and
  // the native solver's view of the window (window_problem.hpp; nullopt where the problem
  // holds a residual block the native solver does not handle).
  ceres::Problem& mutableProblem();
  std::optional<WindowProblem> nativeProblem();

 private:
  WindowKeyframe& keyframeRef(int id);
  WindowPoint& pointRef(int id);
  // Records a residual of `point` in `target` when its projection is valid: its block is
  // added to the problem, or deferred (defersResidualBlocks).
  bool addResidual(WindowPoint& point, WindowKeyframe& target, int level = 0);
  // The residual's parameter blocks: host pose, target pose, inverse distance, host affine,
  // target affine, intrinsics.
  std::array<double*, 6> residualParameters(WindowPoint& point, WindowKeyframe& target);
  OutOfBoundsPenalty* makeResidualCost(const WindowObservation& obs);
  // Adds the block of the residual over `blocks` (residualParameters) to the problem.
  ceres::ResidualBlockId addResidualBlock(std::array<double*, 6>& blocks,
                                          const WindowObservation& obs);
  // Whether the native solver solves level 0 of this window (solve()).
  bool nativeSolverApplies() const;
  bool defersResidualBlocks(int level) const;
  // Adds the deferred blocks of one point, or of every point, to the problem.
  void materializeResidualBlocks(WindowPoint& point);
  void materializeResidualBlocks();
  void removeResidualBlock(ceres::ResidualBlockId id);  // nothing for a deferred one
  // The raw energy (out_of_bounds_penalty.hpp) of the residual of `point` in `target_id`.
  double residualEnergy(WindowPoint& point, int target_id, ceres::ResidualBlockId id);
  std::optional<WindowObservation> observation(const WindowPoint& point,
                                               const WindowKeyframe& target, int level) const;
  void rebuildResiduals(int level, const std::map<int, std::vector<int>>& targets_by_point);
  // The raw energy (out_of_bounds_penalty.hpp) of every photometric residual, in
  // nativeProblem's order (points by id, then targets); invalid ones are infinite.
  std::vector<double> residualEnergies();
  // Removes residuals whose energy (residualEnergies) exceeds max_energy(host id, target id)
  // (all invalid ones: theirs is infinite), then the points left with fewer than
  // min_residuals_per_point. Returns the number of residuals removed.
  template <typename MaxEnergy>
  int removeResiduals(const std::vector<double>& energies, const MaxEnergy& max_energy,
                      int min_residuals_per_point);
  // Ceres, or the native solver where options_.native_solver allows it (level 0).
  WindowSolveSummary solve(int level);
  WindowSolveSummary solveNative(const WindowProblem& problem, WindowSolveSummary out);
  // The native view (window_problem.hpp) of the keyframes and of `points` — their residuals,
  // no priors.
  WindowProblem nativePhotometricProblem(const std::vector<const WindowPoint*>& points);
  // The native problem with the variable frames' and intrinsics' blocks that a prior holds at
  // their first estimates (its points those of `problem`); nullopt when no prior holds any
  // (x̄ = x). For the window's solve and the points' marginalisation.
  std::optional<WindowProblem> firstEstimateProblem(const WindowProblem& problem);
  // Marginalises the points into a prior natively (window_point_marginalization.hpp) where
  // that path applies — every residual of theirs deferred, no other block on them — and
  // removes their blocks from the problem. False where it does not apply (nothing changed).
  bool marginalizePointsNatively(const std::vector<int>& ids);
  // Drops a point and its residuals without marginalising it (points that carry information
  // are marginalised with their keyframe in marginalizeKeyframe).
  void dropPoint(int id);
  // Forgets a point whose block has left the problem, and frees its slot.
  void erasePoint(int id);
  int dropInvalidResiduals();
  void holdScaleAnchor();
  void recordMarginalized(const WindowPoint& point);

  WindowOptions options_;
  std::unique_ptr<PhotometricResidualFactory> factory_;
  Eigen::VectorXd intrinsics_;
  std::unique_ptr<ceres::Manifold> pose_manifold_;
  std::unique_ptr<ceres::LossFunction> loss_;
  ParameterSlots inverse_distance_slots_;  // before problem_: it outlives the problem
  EvaluationReuse evaluation_reuse_;  // likewise
  std::unique_ptr<ceres::Problem> problem_;
  Marginalizer marginalizer_;
  std::vector<std::unique_ptr<WindowKeyframe>> keyframes_;  // oldest first
  std::map<int, std::unique_ptr<WindowPoint>> points_;
  int next_point_id_ = 0;
  int anchor_keyframe_id_ = -1;
  int scale_anchor_point_id_ = -1;
  bool has_prior_ = false;
  bool scale_fixed_by_prior_ = false;
  // Every photometric residual evaluates validly at the current state: true after a removal
  // pass, false once a solve or a mutable accessor may have moved the state.
  bool all_residuals_valid_ = false;
  // The photometric residuals' raw energies left by the last native solve, in nativeProblem's
  // order, and the state they belong to (energyFingerprint): the outlier pass uses them
  // instead of evaluating every residual again while the window is as that solve left it.
  std::vector<double> solved_energies_, solved_fingerprint_;
  // What those energies depend on that can change: keyframe ids, poses and affine
  // parameters, point ids, hosts, inverse distances and targets, the intrinsics.
  std::vector<double> energyFingerprint() const;
  std::vector<MarginalizedPoint> marginalized_points_;
  TaskPool* pool_ = nullptr;
  // The native solver's residual kernel, kept from solve to solve: its buffers (a few MB)
  // were allocated and first touched anew for every keyframe otherwise (nativeProblem).
  std::shared_ptr<WindowPhotometricTerms> window_terms_;
  std::uint64_t num_native_problems_ = 0;
  std::unique_ptr<WindowSolverWorkspace> solver_workspace_;  // likewise (window_solver.hpp)
  std::vector<Eigen::VectorXd> first_estimate_values_;  // x̄ of firstEstimateProblem's blocks
};

}  // namespace omnidso
