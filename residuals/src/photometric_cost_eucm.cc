// Explicit instantiation of the photometric and tracking residuals for ExtendedUnifiedCamera,
// pattern sizes 1, 5 and 8. One TU per camera model keeps the AutoDiffCostFunction (Jet) code out
// of every other TU and lets the models compile in parallel.
#include "omnidso/cameras/extended_unified.hpp"
#include "omnidso/residuals/photometric_cost_impl.hpp"
#include "omnidso/residuals/tracking_residual_impl.hpp"

namespace omnidso {

template class PhotometricResidualAnalytic<ExtendedUnifiedCamera, 1>;
template ceres::CostFunction* makePhotometricCost<ExtendedUnifiedCamera, 1>(
    DifferentiationMode, const PhotometricObservation<1>&);
template PhotometricStatus photometricStatus<ExtendedUnifiedCamera, 1>(
    const PhotometricObservation<1>&, double const* const*);
template class TrackingResidualAnalytic<ExtendedUnifiedCamera, 1>;
template PhotometricStatus evaluateTrackingResidual<ExtendedUnifiedCamera, 1>(
    const ExtendedUnifiedCamera<double>&, const TrackingObservation<1>&, const ImageSampler&,
    const Eigen::Matrix3d&, const Eigen::Vector3d&, const double*, double*,
    TrackingPoseJacobian<1>*, TrackingAffineJacobian<1>*);
template ceres::CostFunction* makeTrackingCost<ExtendedUnifiedCamera, 1>(
    DifferentiationMode, const ExtendedUnifiedCamera<double>&, const TrackingObservation<1>&);
template std::optional<TrackingObservation<1>> makeTrackingObservation<ExtendedUnifiedCamera, 1>(
    const ExtendedUnifiedCamera<double>&, const HostPatch<1>&, double);

template class PhotometricResidualAnalytic<ExtendedUnifiedCamera, 5>;
template ceres::CostFunction* makePhotometricCost<ExtendedUnifiedCamera, 5>(
    DifferentiationMode, const PhotometricObservation<5>&);
template PhotometricStatus photometricStatus<ExtendedUnifiedCamera, 5>(
    const PhotometricObservation<5>&, double const* const*);
template class TrackingResidualAnalytic<ExtendedUnifiedCamera, 5>;
template ceres::CostFunction* makeTrackingCost<ExtendedUnifiedCamera, 5>(
    DifferentiationMode, const ExtendedUnifiedCamera<double>&, const TrackingObservation<5>&);
template std::optional<TrackingObservation<5>> makeTrackingObservation<ExtendedUnifiedCamera, 5>(
    const ExtendedUnifiedCamera<double>&, const HostPatch<5>&, double);

template class PhotometricResidualAnalytic<ExtendedUnifiedCamera, 8>;
template ceres::CostFunction* makePhotometricCost<ExtendedUnifiedCamera, 8>(
    DifferentiationMode, const PhotometricObservation<8>&);
template PhotometricStatus photometricStatus<ExtendedUnifiedCamera, 8>(
    const PhotometricObservation<8>&, double const* const*);
template class TrackingResidualAnalytic<ExtendedUnifiedCamera, 8>;
template ceres::CostFunction* makeTrackingCost<ExtendedUnifiedCamera, 8>(
    DifferentiationMode, const ExtendedUnifiedCamera<double>&, const TrackingObservation<8>&);
template std::optional<TrackingObservation<8>> makeTrackingObservation<ExtendedUnifiedCamera, 8>(
    const ExtendedUnifiedCamera<double>&, const HostPatch<8>&, double);

}  // namespace omnidso
