// Explicit instantiation of the photometric and tracking residuals for UnifiedCamera, pattern
// sizes 1, 5 and 8. One TU per camera model keeps the AutoDiffCostFunction (Jet) code out
// of every other TU and lets the models compile in parallel.
#include "omnidso/cameras/unified.hpp"
#include "omnidso/residuals/photometric_cost_impl.hpp"
#include "omnidso/residuals/tracking_residual_impl.hpp"

namespace omnidso {

template class PhotometricResidualAnalytic<UnifiedCamera, 1>;
template ceres::CostFunction* makePhotometricCost<UnifiedCamera, 1>(
    DifferentiationMode, const PhotometricObservation<1>&);
template PhotometricStatus photometricStatus<UnifiedCamera, 1>(const PhotometricObservation<1>&,
                                                               double const* const*);
template class TrackingResidualAnalytic<UnifiedCamera, 1>;
template PhotometricStatus evaluateTrackingResidual<UnifiedCamera, 1>(
    const UnifiedCamera<double>&, const TrackingObservation<1>&, const ImageSampler&,
    const Eigen::Matrix3d&, const Eigen::Vector3d&, const double*, double*,
    TrackingPoseJacobian<1>*, TrackingAffineJacobian<1>*);
template ceres::CostFunction* makeTrackingCost<UnifiedCamera, 1>(DifferentiationMode,
                                                                 const UnifiedCamera<double>&,
                                                                 const TrackingObservation<1>&);
template std::optional<TrackingObservation<1>> makeTrackingObservation<UnifiedCamera, 1>(
    const UnifiedCamera<double>&, const HostPatch<1>&, double);

template class PhotometricResidualAnalytic<UnifiedCamera, 5>;
template ceres::CostFunction* makePhotometricCost<UnifiedCamera, 5>(
    DifferentiationMode, const PhotometricObservation<5>&);
template PhotometricStatus photometricStatus<UnifiedCamera, 5>(const PhotometricObservation<5>&,
                                                               double const* const*);
template class TrackingResidualAnalytic<UnifiedCamera, 5>;
template ceres::CostFunction* makeTrackingCost<UnifiedCamera, 5>(DifferentiationMode,
                                                                 const UnifiedCamera<double>&,
                                                                 const TrackingObservation<5>&);
template std::optional<TrackingObservation<5>> makeTrackingObservation<UnifiedCamera, 5>(
    const UnifiedCamera<double>&, const HostPatch<5>&, double);

template class PhotometricResidualAnalytic<UnifiedCamera, 8>;
template ceres::CostFunction* makePhotometricCost<UnifiedCamera, 8>(
    DifferentiationMode, const PhotometricObservation<8>&);
template PhotometricStatus photometricStatus<UnifiedCamera, 8>(const PhotometricObservation<8>&,
                                                               double const* const*);
template class TrackingResidualAnalytic<UnifiedCamera, 8>;
template ceres::CostFunction* makeTrackingCost<UnifiedCamera, 8>(DifferentiationMode,
                                                                 const UnifiedCamera<double>&,
                                                                 const TrackingObservation<8>&);
template std::optional<TrackingObservation<8>> makeTrackingObservation<UnifiedCamera, 8>(
    const UnifiedCamera<double>&, const HostPatch<8>&, double);

}  // namespace omnidso
