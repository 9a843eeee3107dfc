// Explicit instantiation of the photometric and tracking residuals for FovCamera, pattern
// sizes 1, 5 and 8. One TU per camera model keeps the AutoDiffCostFunction (Jet) code out
// of every other TU and lets the models compile in parallel.
#include "omnidso/cameras/fov.hpp"
#include "omnidso/residuals/photometric_cost_impl.hpp"
#include "omnidso/residuals/tracking_residual_impl.hpp"

namespace omnidso {

template class PhotometricResidualAnalytic<FovCamera, 1>;
template ceres::CostFunction* makePhotometricCost<FovCamera, 1>(
    DifferentiationMode, const PhotometricObservation<1>&);
template PhotometricStatus photometricStatus<FovCamera, 1>(
    const PhotometricObservation<1>&, double const* const*);
template class TrackingResidualAnalytic<FovCamera, 1>;
template PhotometricStatus evaluateTrackingResidual<FovCamera, 1>(
    const FovCamera<double>&, const TrackingObservation<1>&, const ImageSampler&,
    const Eigen::Matrix3d&, const Eigen::Vector3d&, const double*, double*,
    TrackingPoseJacobian<1>*, TrackingAffineJacobian<1>*);
template ceres::CostFunction* makeTrackingCost<FovCamera, 1>(
    DifferentiationMode, const FovCamera<double>&, const TrackingObservation<1>&);
template std::optional<TrackingObservation<1>> makeTrackingObservation<FovCamera, 1>(
    const FovCamera<double>&, const HostPatch<1>&, double);

template class PhotometricResidualAnalytic<FovCamera, 5>;
template ceres::CostFunction* makePhotometricCost<FovCamera, 5>(
    DifferentiationMode, const PhotometricObservation<5>&);
template PhotometricStatus photometricStatus<FovCamera, 5>(
    const PhotometricObservation<5>&, double const* const*);
template class TrackingResidualAnalytic<FovCamera, 5>;
template ceres::CostFunction* makeTrackingCost<FovCamera, 5>(
    DifferentiationMode, const FovCamera<double>&, const TrackingObservation<5>&);
template std::optional<TrackingObservation<5>> makeTrackingObservation<FovCamera, 5>(
    const FovCamera<double>&, const HostPatch<5>&, double);

template class PhotometricResidualAnalytic<FovCamera, 8>;
template ceres::CostFunction* makePhotometricCost<FovCamera, 8>(
    DifferentiationMode, const PhotometricObservation<8>&);
template PhotometricStatus photometricStatus<FovCamera, 8>(
    const PhotometricObservation<8>&, double const* const*);
template class TrackingResidualAnalytic<FovCamera, 8>;
template ceres::CostFunction* makeTrackingCost<FovCamera, 8>(
    DifferentiationMode, const FovCamera<double>&, const TrackingObservation<8>&);
template std::optional<TrackingObservation<8>> makeTrackingObservation<FovCamera, 8>(
    const FovCamera<double>&, const HostPatch<8>&, double);

}  // namespace omnidso
