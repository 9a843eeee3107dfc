// Explicit instantiation of the photometric and tracking residuals for PinholeCamera, pattern
// sizes 1, 5 and 8. One TU per camera model keeps the AutoDiffCostFunction (Jet) code out
// of every other TU and lets the models compile in parallel.
#include "omnidso/cameras/pinhole.hpp"
#include "omnidso/residuals/photometric_cost_impl.hpp"
#include "omnidso/residuals/tracking_residual_impl.hpp"

namespace omnidso {

template class PhotometricResidualAnalytic<PinholeCamera, 1>;
template ceres::CostFunction* makePhotometricCost<PinholeCamera, 1>(
    DifferentiationMode, const PhotometricObservation<1>&);
template PhotometricStatus photometricStatus<PinholeCamera, 1>(const PhotometricObservation<1>&,
                                                               double const* const*);
template class TrackingResidualAnalytic<PinholeCamera, 1>;
template PhotometricStatus evaluateTrackingResidual<PinholeCamera, 1>(
    const PinholeCamera<double>&, const TrackingObservation<1>&, const ImageSampler&,
    const Eigen::Matrix3d&, const Eigen::Vector3d&, const double*, double*,
    TrackingPoseJacobian<1>*, TrackingAffineJacobian<1>*);
template ceres::CostFunction* makeTrackingCost<PinholeCamera, 1>(DifferentiationMode,
                                                                 const PinholeCamera<double>&,
                                                                 const TrackingObservation<1>&);
template std::optional<TrackingObservation<1>> makeTrackingObservation<PinholeCamera, 1>(
    const PinholeCamera<double>&, const HostPatch<1>&, double);

template class PhotometricResidualAnalytic<PinholeCamera, 5>;
template ceres::CostFunction* makePhotometricCost<PinholeCamera, 5>(
    DifferentiationMode, const PhotometricObservation<5>&);
template PhotometricStatus photometricStatus<PinholeCamera, 5>(const PhotometricObservation<5>&,
                                                               double const* const*);
template class TrackingResidualAnalytic<PinholeCamera, 5>;
template ceres::CostFunction* makeTrackingCost<PinholeCamera, 5>(DifferentiationMode,
                                                                 const PinholeCamera<double>&,
                                                                 const TrackingObservation<5>&);
template std::optional<TrackingObservation<5>> makeTrackingObservation<PinholeCamera, 5>(
    const PinholeCamera<double>&, const HostPatch<5>&, double);

template class PhotometricResidualAnalytic<PinholeCamera, 8>;
template ceres::CostFunction* makePhotometricCost<PinholeCamera, 8>(
    DifferentiationMode, const PhotometricObservation<8>&);
template PhotometricStatus photometricStatus<PinholeCamera, 8>(const PhotometricObservation<8>&,
                                                               double const* const*);
template class TrackingResidualAnalytic<PinholeCamera, 8>;
template ceres::CostFunction* makeTrackingCost<PinholeCamera, 8>(DifferentiationMode,
                                                                 const PinholeCamera<double>&,
                                                                 const TrackingObservation<8>&);
template std::optional<TrackingObservation<8>> makeTrackingObservation<PinholeCamera, 8>(
    const PinholeCamera<double>&, const HostPatch<8>&, double);

}  // namespace omnidso
