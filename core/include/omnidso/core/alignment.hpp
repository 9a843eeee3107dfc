#pragma once
// Closed-form least-squares alignment of corresponding 3D points (Umeyama 1991, "Least-
// squares estimation of transformation parameters between two point patterns"). Column i
// of `est` corresponds to column i of `gt`; every function returns the transform S that
// minimises Σᵢ |gtᵢ − S·estᵢ|², i.e. gt ≈ S·est.
//
// With μ_e, μ_g the means, σ_e² = (1/N)Σ|estᵢ − μ_e|² and the cross-covariance
// Σ = (1/N)Σ (gtᵢ − μ_g)(estᵢ − μ_e)ᵀ = U D Vᵀ (SVD):
//   R = U diag(1, 1, det(U)det(V)) Vᵀ   (the last sign forbids reflections, Umeyama eq. 39)
//   s = tr(D diag(1, 1, det(U)det(V))) / σ_e²   (eq. 42; s = 1 for SE(3))
//   t = μ_g − s R μ_e                            (eq. 41)
// This is the alignment of evo (`--align`, `--correct_scale`) and of
// rpg_trajectory_evaluation (`sim3`, `se3`).
//
// Degenerate input throws omnidso::Error: fewer than 3 points, or points (of either set)
// that are collinear or coincide, for which the rotation is not determined.

#include <Eigen/Core>
#include <omnidso/core/se3.hpp>
#include <omnidso/core/sim3.hpp>

namespace omnidso {

// Similarity (scale, rotation, translation): monocular odometry.
Sim3d alignSim3(const Eigen::Matrix3Xd& est, const Eigen::Matrix3Xd& gt);

// Rigid transform: odometry with metric scale (stereo, visual-inertial, KITTI).
SE3d alignSE3(const Eigen::Matrix3Xd& est, const Eigen::Matrix3Xd& gt);

// Rotation about the z (gravity) axis and translation — the 4 unobservable degrees of
// freedom of visual-inertial odometry (rpg_trajectory_evaluation's `posyaw`). The yaw
// maximising Σ (gtᵢ − μ_g)·R_z(ψ)(estᵢ − μ_e) is
//   ψ = atan2(Σ (e_x g_y − e_y g_x), Σ (e_x g_x + e_y g_y))   (centred coordinates),
// and t = μ_g − R_z(ψ) μ_e. Needs at least 2 points not coinciding in x-y.
SE3d alignPositionYaw(const Eigen::Matrix3Xd& est, const Eigen::Matrix3Xd& gt);

}  // namespace omnidso
