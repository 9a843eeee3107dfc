#pragma once
// Trajectory evaluation: association by time, alignment, absolute trajectory error (ATE)
// and relative pose error (RPE), defined as the field's standard tools define them (evo's
// evo_ape / evo_rpe; the TUM RGB-D benchmark's associate.py), so that the numbers agree.
//
// Definitions (G_k ground-truth pose, E_k estimated pose of the k-th associated pair,
// S the alignment with G_k ≈ S·E_k, applied to the estimate as S·E = (R R_E, s R t_E + t)):
// - ATE error of pair k: e_k = |trans(G_k⁻¹ · S·E_k)| = |t(S·E_k) − t(G_k)| (metres).
// - RPE of the pose pair (i, j): E_ij = (G_i⁻¹ G_j)⁻¹ (Ê_i⁻¹ Ê_j), Ê = S·E (the scale
//   matters, the rigid part cancels). Translation error |trans(E_ij)| (m), rotation error
//   the angle of rot(E_ij) in degrees.
// - RPE pairs, consecutive and non-overlapping (evo without --all_pairs):
//   frames: indices 0, Δ, 2Δ, ... of the associated list, pairs of neighbours;
//   metres: walking the aligned estimate (evo's default; the ground truth with
//   pairs_from_reference), an index is kept whenever the path length accumulated since the
//   last kept index reaches Δ (accumulation starts at index 0, which itself is not kept, as
//   in evo); pairs of neighbouring kept indices.
// - Statistics of errors e_1..e_N: rmse = √(Σe²/N), mean, median (mean of the two middle
//   values for even N), std = √(Σ(e − mean)²/N) (population, as numpy.std), min, max.
// - Ground-truth length: Σ_k |t(G_{k+1}) − t(G_k)| over the associated ground-truth poses.

#include <cstddef>
#include <omnidso/core/sim3.hpp>
#include <omnidso/core/trajectory.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace omnidso {

// (ground-truth index, estimate index) pairs, in increasing ground-truth order.
using Association = std::vector<std::pair<size_t, size_t>>;

// Greedy nearest-timestamp matching (TUM associate.py): all pairs with |t_gt − t_est| ≤
// max_dt taken in order of increasing |t_gt − t_est| (ties: earlier ground truth first),
// each accepted when neither pose is matched yet. So each pose is used at most once, and
// different rates and gaps are handled. Runs in O((N + M) log M) for sane max_dt.
Association associate(const Trajectory& gt, const Trajectory& est, double max_dt);
// Pose k with pose k for k < min(sizes): files without timestamps (KITTI).
Association associateByIndex(const Trajectory& gt, const Trajectory& est);

enum class AlignmentType { kSim3, kSE3, kPositionYaw, kNone };
// "sim3", "se3", "posyaw", "none"; anything else throws Error.
AlignmentType parseAlignmentType(const std::string& name);

// S with G_k ≈ S·E_k over the associated positions (alignment.hpp); identity for kNone,
// unit scale for kSE3 and kPositionYaw.
Sim3d alignTrajectories(const Trajectory& gt, const Trajectory& est,
                        const Association& association, AlignmentType type);

struct ErrorStatistics {
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;
  double min = 0.0;
  double max = 0.0;
  size_t count = 0;
};
// Throws Error for an empty list.
ErrorStatistics computeStatistics(const std::vector<double>& errors);

// e_k of the ATE for every associated pair.
std::vector<double> absolutePositionErrors(const Trajectory& gt, const Trajectory& est,
                                           const Association& association,
                                           const Sim3d& alignment);

double groundTruthLength(const Trajectory& gt, const Association& association);

// Length of the polyline through every pose of `trajectory` whose timestamp lies in [t0, t1]
// (all its poses, not only those matched to an estimate).
double pathLength(const Trajectory& trajectory, double t0, double t1);

enum class DeltaUnit { kFrames, kMeters };
// "f", "m"; anything else throws Error.
DeltaUnit parseDeltaUnit(const std::string& name);

struct RpeOptions {
  double delta = 1.0;  // a positive integer for kFrames
  DeltaUnit unit = DeltaUnit::kFrames;
  bool pairs_from_reference = false;  // metres: walk the ground truth instead of the estimate
};

struct RelativeErrors {
  std::vector<std::pair<size_t, size_t>> pairs;  // indices into the association
  std::vector<double> translation_m;
  std::vector<double> rotation_deg;
};
RelativeErrors relativePoseErrors(const Trajectory& gt, const Trajectory& est,
                                  const Association& association, const Sim3d& alignment,
                                  const RpeOptions& options);

struct EvaluationOptions {
  AlignmentType alignment = AlignmentType::kSim3;
  double max_dt = 0.02;            // seconds, for timestamp association
  bool associate_by_index = false;  // KITTI files
  RpeOptions rpe;
};

struct EvaluationResult {
  Association association;
  Sim3d alignment;
  std::vector<double> position_errors;  // per associated pair, for plots over time
  ErrorStatistics ate;
  double gt_length_m = 0.0;
  // Absent when the trajectory is too short for a single pair at the requested delta.
  std::optional<ErrorStatistics> rpe_translation_m;
  std::optional<ErrorStatistics> rpe_rotation_deg;
};

// Associates, aligns and computes ATE and RPE. Throws Error when no pose is associated or
// too few for the alignment.
EvaluationResult evaluate(const Trajectory& gt, const Trajectory& est,
                          const EvaluationOptions& options);

}  // namespace omnidso
