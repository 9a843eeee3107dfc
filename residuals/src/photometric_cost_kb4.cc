// Explicit instantiation of the photometric and tracking residuals for KannalaBrandtCamera, pattern
// sizes 1, 5 and 8. One TU per camera model keeps the AutoDiffCostFunction (Jet) code out
// of every other TU and lets the models compile in parallel.
#include "omnidso/cameras/kannala_brandt.hpp"
#include "omnidso/residuals/photometric_cost_impl.hpp"
#include "omnidso/residuals/tracking_residual_impl.hpp"

namespace omnidso {

template class PhotometricResidualAnalytic<KannalaBrandtCamera, 1>;
template ceres::CostFunction* makePhotometricCost<KannalaBrandtCamera, 1>(
    DifferentiationMode, const PhotometricObservation<1>&);
template PhotometricStatus photometricStatus<KannalaBrandtCamera, 1>(
    const PhotometricObservation<1>&, double const* const*);
template class TrackingResidualAnalytic<KannalaBrandtCamera, 1>;
template PhotometricStatus evaluateTrackingResidual<KannalaBrandtCamera, 1>(
    const KannalaBrandtCamera<double>&, const TrackingObservation<1>&, const ImageSampler&,
    const Eigen::Matrix3d&, const Eigen::Vector3d&, const double*, double*,
    TrackingPoseJacobian<1>*, TrackingAffineJacobian<1>*);
template ceres::CostFunction* makeTrackingCost<KannalaBrandtCamera, 1>(
    DifferentiationMode, const KannalaBrandtCamera<double>&, const TrackingObservation<1>&);
template std::optional<TrackingObservation<1>> makeTrackingObservation<KannalaBrandtCamera, 1>(
    const KannalaBrandtCamera<double>&, const HostPatch<1>&, double);

template class PhotometricResidualAnalytic<KannalaBrandtCamera, 5>;
template ceres::CostFunction* makePhotometricCost<KannalaBrandtCamera, 5>(
    DifferentiationMode, const PhotometricObservation<5>&);
template PhotometricStatus photometricStatus<KannalaBrandtCamera, 5>(
    const PhotometricObservation<5>&, double const* const*);
template class TrackingResidualAnalytic<KannalaBrandtCamera, 5>;
template ceres::CostFunction* makeTrackingCost<KannalaBrandtCamera, 5>(
    DifferentiationMode, const KannalaBrandtCamera<double>&, const TrackingObservation<5>&);
template std::optional<TrackingObservation<5>> makeTrackingObservation<KannalaBrandtCamera, 5>(
    const KannalaBrandtCamera<double>&, const HostPatch<5>&, double);

template class PhotometricResidualAnalytic<KannalaBrandtCamera, 8>;
template ceres::CostFunction* makePhotometricCost<KannalaBrandtCamera, 8>(
    DifferentiationMode, const PhotometricObservation<8>&);
template PhotometricStatus photometricStatus<KannalaBrandtCamera, 8>(
    const PhotometricObservation<8>&, double const* const*);
template class TrackingResidualAnalytic<KannalaBrandtCamera, 8>;
template ceres::CostFunction* makeTrackingCost<KannalaBrandtCamera, 8>(
    DifferentiationMode, const KannalaBrandtCamera<double>&, const TrackingObservation<8>&);
template std::optional<TrackingObservation<8>> makeTrackingObservation<KannalaBrandtCamera, 8>(
    const KannalaBrandtCamera<double>&, const HostPatch<8>&, double);

}  // namespace omnidso
