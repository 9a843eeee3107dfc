#pragma once
// The native window solver's view of SlidingWindow's ceres::Problem (window_solver.hpp):
// the same parameter blocks (by pointer, so a solve writes its result where Ceres would),
// the same constant blocks (the gauge, read from the problem), the photometric residuals as
// (point, target keyframe) pairs in a fixed order — points by id, targets by keyframe id —
// and every other residual block of the problem (affine, intrinsics and marginalisation
// priors) as a `WindowPrior`, evaluated through its own ceres::CostFunction.
//
// Tangent coordinates (the solver's variables), with F keyframes and K intrinsics:
//   frame space: keyframe k at 8k: [ρ φ] of its pose (SE3Manifold, x ⊞ δ = x·exp(δ)) and
//   its affine [a b]; the intrinsics at 8F; points: one inverse distance each.
// Constant blocks keep their coordinates (so that offsets do not depend on the gauge) and
// are left out of the linear system.

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>

#include <cstdint>
#include <memory>
#include <omnidso/backend/photometric_factory.hpp>
#include <omnidso/core/task_pool.hpp>
#include <vector>

namespace omnidso {

class WindowPhotometricTerms;

inline constexpr int kFrameTangentSize = 8;  // pose 6 + affine 2

struct WindowFrame {
  double* pose = nullptr;    // [qx qy qz qw tx ty tz], T_world_cam
  double* affine = nullptr;  // [a b]
  bool pose_constant = false;
  bool affine_constant = false;
  double exposure = 1.0;
  const ImageF* image = nullptr;  // level 0
  const Mask* content = nullptr;  // level 0, or nullptr for the whole image
};

struct WindowPointBlock {
  double* inverse_distance = nullptr;
  bool constant = false;  // the scale anchor
  int host = 0;           // frame index
  const HostPatch<kWindowPatternSize>* patch = nullptr;  // level 0
  int first_residual = 0;  // its residuals: [first_residual, first_residual + num_residuals)
  int num_residuals = 0;
};

struct WindowResidual {
  int point = 0;
  int target = 0;  // frame index
};

// Where a parameter block of a prior lives in frame space.
struct WindowPriorBlock {
  double* values = nullptr;
  int ambient_size = 0;
  int tangent_offset = 0;  // in frame space
  int tangent_size = 0;
  const ceres::Manifold* manifold = nullptr;  // nullptr: Euclidean
  bool constant = false;
};

struct WindowPrior {
  const ceres::CostFunction* cost = nullptr;
  const ceres::LossFunction* loss = nullptr;  // nullptr: squared norm
  std::vector<WindowPriorBlock> blocks;
  bool fixed() const;  // every block constant: Ceres's fixed cost
};

struct WindowProblem {
  std::vector<WindowFrame> frames;       // oldest first
  std::vector<WindowPointBlock> points;  // by point id
  std::vector<WindowResidual> residuals;  // by point, then target keyframe id
  std::vector<WindowPrior> priors;        // in the problem's order
  double* intrinsics = nullptr;          // level 0 [fx fy cx cy …]
  int num_intrinsics = 0;
  bool intrinsics_constant = false;
  const ceres::Manifold* pose_manifold = nullptr;
  const ceres::LossFunction* photometric_loss = nullptr;
  ImageInterpolation interpolation = ImageInterpolation::kBilinear;  // of the target images
  ImageGradient gradient = ImageGradient::kInterpolant;  // in the Jacobians (image_sampler.hpp)
  double out_of_bounds_energy = 0.0;  // ‖r‖² of an invalid residual (out_of_bounds_penalty.hpp)
  // The model's residual kernel. A window keeps one for its lifetime (its buffers stay
  // allocated from solve to solve); what it caches per problem is keyed on `id`.
  std::shared_ptr<WindowPhotometricTerms> photometric;
  std::uint64_t id = 0;  // different for every problem a window assembles
  // Threads for the evaluation and the reduced system (null: the caller alone). Each sum is
  // formed by one task in a fixed order, so the solve does not depend on them.
  TaskPool* pool = nullptr;

  int frameSpaceSize() const {
    return kFrameTangentSize * static_cast<int>(frames.size()) + num_intrinsics;
  }
  int intrinsicsOffset() const { return kFrameTangentSize * static_cast<int>(frames.size()); }
};

}  // namespace omnidso
