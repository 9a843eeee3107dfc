#pragma once
// One pyramid level's photometric patches of the initialiser (initializer.cc) as its native
// solve sees them (initializer_solver.hpp, InitializerPatches) — the kernel of the Ceres cost
// function (residuals/photometric_kernel.hpp, evaluatePhotometricPatch) with the host fixed
// at the identity with affine [0, 0] (the first frame), the host bearings b_o unprojected
// once per level (the intrinsics are constant), one sampler of the frame's level image for
// all points, and the Jacobians in the frame's tangent space directly
// (photometric_analytic.hpp's target rows, T ⊞ δ = T exp(δ)):
//   ∂r_o/∂δ = [−d g_o, g_o [x̃_o]×],  ∂r_o/∂[a b] = [−√w_o s h_o, −√w_o],  ∂r_o/∂d = g_o t.
// Why: the Ceres path's cost function unprojects the host pattern, forms the relative pose
// and builds a sampler on every evaluation and returns ambient Jacobians for all six blocks.

#include <omnidso/backend/photometric_factory.hpp>
#include <omnidso/core/se3.hpp>
#include <omnidso/frontend/initializer_solver.hpp>
#include <omnidso/residuals/image_sampler.hpp>
#include <omnidso/residuals/photometric_kernel.hpp>
#include <optional>
#include <vector>

namespace omnidso {

// The patches of one level, kept by the initialiser for the first frame's lifetime and
// refilled for every problem (frame, level, start), so that their ≈ 1 kB per point of
// storage is allocated once and not for every problem of every frame.
class InitializerLevelPatchesBase : public InitializerPatches {
 public:
  // Empties the patches and sets the frame's level image, its content and its exposure.
  virtual void setFrame(const ImageF& image, const Mask* content, double frame_exposure) = 0;
  // Adds the patch if it is valid at inverse distance d and the current point (setPoint):
  // the Ceres path's test (PhotometricResidualFactory::status, the same kernel).
  virtual bool addIfValid(const HostPatch<kPatchSize>& host, double d) = 0;
};

template <template <typename> class M>
class InitializerLevelPatches final : public InitializerLevelPatchesBase {
  static constexpr int K = M<double>::kNumParams;

 public:
  // `level_camera`: the model with the level's intrinsics; the host pose and affine blocks
  // (identity, zero) as the Ceres path passes them; room for `capacity` patches.
  InitializerLevelPatches(const M<double>& level_camera, double host_exposure,
                          const double* host_pose, const double* host_affine, size_t capacity,
                          ImageGradient gradient = ImageGradient::kInterpolant)
      : camera_(level_camera),
        host_exposure_(host_exposure),
        host_pose_(host_pose),
        host_affine_(host_affine),
        gradient_(gradient) {
    hosts_.reserve(capacity);
    bearings_.reserve(capacity);
  }

  void setFrame(const ImageF& image, const Mask* content, double frame_exposure) override {
    sampler_.emplace(image, ImageInterpolation::kBilinear, content, gradient_);
    image_ = &image;
    content_ = content;
    frame_exposure_ = frame_exposure;
    size_ = 0;  // the storage is kept and overwritten (no allocation, no zeroing)
  }

  bool addIfValid(const HostPatch<kPatchSize>& host, double d) override {
    if (hosts_.size() == size_) {
      hosts_.emplace_back();
      bearings_.emplace_back();
    }
    hosts_[size_] = host;
    unprojectHostPattern(camera_, host, false, &bearings_[size_]);
    Residuals r;
    if (!evaluate(static_cast<int>(size_), d, &r, nullptr, nullptr)) return false;
    ++size_;
    return true;
  }

  std::unique_ptr<InitializerPatches> clone() const override {
    auto copy = std::make_unique<InitializerLevelPatches>(camera_, host_exposure_, host_pose_,
                                                          host_affine_, 0, gradient_);
    if (image_) copy->setFrame(*image_, content_, frame_exposure_);  // a sampler of its own
    copy->hosts_.assign(hosts_.begin(), hosts_.begin() + size_);
    copy->bearings_.assign(bearings_.begin(), bearings_.begin() + size_);
    copy->size_ = size_;
    copy->pair_ = pair_;
    return copy;
  }
  int size() const override { return static_cast<int>(size_); }
  void setPoint(const double* pose, const double* affine) override {
    pair_ = makePhotometricPair(host_pose_, pose, host_affine_, affine, host_exposure_,
                                frame_exposure_);
  }
  bool evaluate(int i, double d, Residuals* r, FrameJacobian* J_f, Residuals* J_d) const override {
    const size_t k = static_cast<size_t>(i);
    PatchDerivatives<kPatchSize, K> patch;
    const bool jacobians = J_f != nullptr;
    if (evaluatePhotometricPatch(camera_, *sampler_, hosts_[k], bearings_[k], pair_, d, r->data(),
                                 jacobians ? &patch : nullptr, false) != PhotometricStatus::kValid)
      return false;
    if (!jacobians) return true;
    for (int o = 0; o < kPatchSize; ++o) {
      const double sw = hosts_[k].sqrt_weight[o];
      const Eigen::RowVector3d g = patch.d_r_d_x.row(o);
      const Eigen::Vector3d x = patch.point.row(o).transpose();
      J_f->template block<1, 3>(o, 0) = -d * g;
      J_f->template block<1, 3>(o, 3) = g * skew(x);
      (*J_f)(o, 6) = -sw * pair_.s * patch.host_term[o];
      (*J_f)(o, 7) = -sw;
      (*J_d)[o] = g.dot(pair_.t);
    }
    return true;
  }

 private:
  M<double> camera_;
  std::optional<ImageSampler> sampler_;  // of *image_ and *content_ (setFrame)
  const ImageF* image_ = nullptr;
  const Mask* content_ = nullptr;
  double host_exposure_, frame_exposure_ = 1.0;
  const double* host_pose_;
  const double* host_affine_;
  ImageGradient gradient_;
  std::vector<HostPatch<kPatchSize>> hosts_;
  std::vector<HostBearings<kPatchSize, K>> bearings_;
  size_t size_ = 0;  // patches in use: the first size_ of hosts_ and bearings_
  PhotometricPair pair_;
};

}  // namespace omnidso
