// Explicit instantiation of the photometric and tracking residuals for DoubleSphereCamera, pattern
// sizes 1, 5 and 8. One TU per camera model keeps the AutoDiffCostFunction (Jet) code out
// of every other TU and lets the models compile in parallel.
#include "omnidso/cameras/double_sphere.hpp"
#include "omnidso/residuals/photometric_cost_impl.hpp"
#include "omnidso/residuals/tracking_residual_impl.hpp"

namespace omnidso {

template class PhotometricResidualAnalytic<DoubleSphereCamera, 1>;
template ceres::CostFunction* makePhotometricCost<DoubleSphereCamera, 1>(
    DifferentiationMode, const PhotometricObservation<1>&);
template PhotometricStatus photometricStatus<DoubleSphereCamera, 1>(
    const PhotometricObservation<1>&, double const* const*);
template class TrackingResidualAnalytic<DoubleSphereCamera, 1>;
template PhotometricStatus evaluateTrackingResidual<DoubleSphereCamera, 1>(
    const DoubleSphereCamera<double>&, const TrackingObservation<1>&, const ImageSampler&,
    const Eigen::Matrix3d&, const Eigen::Vector3d&, const double*, double*,
    TrackingPoseJacobian<1>*, TrackingAffineJacobian<1>*);
template ceres::CostFunction* makeTrackingCost<DoubleSphereCamera, 1>(
    DifferentiationMode, const DoubleSphereCamera<double>&, const TrackingObservation<1>&);
template std::optional<TrackingObservation<1>> makeTrackingObservation<DoubleSphereCamera, 1>(
    const DoubleSphereCamera<double>&, const HostPatch<1>&, double);

template class PhotometricResidualAnalytic<DoubleSphereCamera, 5>;
template ceres::CostFunction* makePhotometricCost<DoubleSphereCamera, 5>(
    DifferentiationMode, const PhotometricObservation<5>&);
template PhotometricStatus photometricStatus<DoubleSphereCamera, 5>(
    const PhotometricObservation<5>&, double const* const*);
template class TrackingResidualAnalytic<DoubleSphereCamera, 5>;
template ceres::CostFunction* makeTrackingCost<DoubleSphereCamera, 5>(
    DifferentiationMode, const DoubleSphereCamera<double>&, const TrackingObservation<5>&);
template std::optional<TrackingObservation<5>> makeTrackingObservation<DoubleSphereCamera, 5>(
    const DoubleSphereCamera<double>&, const HostPatch<5>&, double);

template class PhotometricResidualAnalytic<DoubleSphereCamera, 8>;
template ceres::CostFunction* makePhotometricCost<DoubleSphereCamera, 8>(
    DifferentiationMode, const PhotometricObservation<8>&);
template PhotometricStatus photometricStatus<DoubleSphereCamera, 8>(
    const PhotometricObservation<8>&, double const* const*);
template class TrackingResidualAnalytic<DoubleSphereCamera, 8>;
template ceres::CostFunction* makeTrackingCost<DoubleSphereCamera, 8>(
    DifferentiationMode, const DoubleSphereCamera<double>&, const TrackingObservation<8>&);
template std::optional<TrackingObservation<8>> makeTrackingObservation<DoubleSphereCamera, 8>(
    const DoubleSphereCamera<double>&, const HostPatch<8>&, double);

}  // namespace omnidso
