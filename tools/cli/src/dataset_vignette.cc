#include <omnidso/cli/dataset_vignette.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace omnidso::cli {

VignetteEstimate estimateDatasetVignette(const DatasetIndex& index, size_t num_frames,
                                         const Camera& source, const Mask& content,
                                         const PhotometricCalibration& response, int max_pairs,
                                         const VignetteEstimationOptions& options) {
  Eigen::Vector2d centre(0.5 * (source.width() - 1), 0.5 * (source.height() - 1));
  Eigen::Vector2d axis;
  if (source.project(Eigen::Vector3d::UnitZ(), axis)) centre = axis;
  const PhotometricCalibration response_only(response.inverseResponseTable(), ImageF());
  VignetteEstimator estimator(source.width(), source.height(), content, centre,
                              response_only.inverseResponse(255.0), options);
  num_frames = std::min(num_frames, index.frames.size());
  if (num_frames >= 2 && max_pairs > 0) {
    const size_t pairs = std::min<size_t>(static_cast<size_t>(max_pairs), num_frames - 1);
    for (size_t j = 0; j < pairs; ++j) {
      // First frames of the pairs, evenly from 0 to num_frames − 2.
      const size_t i = pairs == 1 ? 0 : j * (num_frames - 2) / (pairs - 1);
      const ImageF first = response_only.correct(readDatasetRawFrame(index.frames[i]));
      const ImageF second = response_only.correct(readDatasetRawFrame(index.frames[i + 1]));
      if (first.width() != source.width() || first.height() != source.height() ||
          second.width() != source.width() || second.height() != source.height())
        continue;  // the run itself reports the wrong size, naming the frame
      estimator.addPair(first, second);
    }
  }
  return estimator.solve();
}

nlohmann::json vignetteEstimateJson(const VignetteEstimate& e) {
  nlohmann::json j = {{"valid", e.valid},
                      {"pairs", e.num_pairs},
                      {"observations", e.num_observations}};
  if (!e.valid) {
    j["reason"] = e.reason;
    return j;
  }
  j["centre_px"] = {e.centre.x(), e.centre.y()};
  j["radius_px"] = e.radius;
  std::vector<double> v;
  for (Eigen::Index k = 0; k < e.knots.size(); ++k)
    v.push_back(e.at(static_cast<double>(k) / static_cast<double>(e.knots.size() - 1)));
  j["v_at_knots"] = v;  // V at ρ = k / (knots − 1), ρ = distance from the centre / radius
  j["residual_mad_log"] = e.residual_mad;
  return j;
}

std::string vignetteEstimateNote(const VignetteEstimate& e) {
  std::ostringstream note;
  if (!e.valid) {
    note << "no vignette.png, and none could be estimated (" << e.reason
         << "): the images are taken as unvignetted";
    return note.str();
  }
  note << std::fixed << std::setprecision(2) << "no vignette.png: estimated from " << e.num_observations
       << " points tracked over " << e.num_pairs << " frame pairs, V = " << e.at(0.5) << " / "
       << e.at(0.75) << " / " << e.at(1.0)
       << " at 1/2, 3/4 and all of the way from the principal point to the farthest image "
          "pixel (OUT/vignette_estimated.png; --no-vignette-estimation to assume none)";
  return note.str();
}

}  // namespace omnidso::cli
