#pragma once
// The PNG plots of `omnidso ablate`, per dataset, from the median-RMSE run of every cell:
//   OUT/plots/DATASET_trajectories.png  top view of the ground truth (black) and of every
//       method's keyframe trajectory after Sim(3) alignment to it (one colour per method),
//       in the plane of the two axes along which the ground truth extends most
//   OUT/plots/DATASET_ate.png           the ATE of every keyframe over time, per method
// Methods whose runs all failed appear in the legend as a grey note.

#include <omnidso/core/trajectory.hpp>
#include <optional>
#include <string>
#include <vector>

namespace omnidso::cli {

struct PlottedMethod {
  std::string label;                    // "native Kf7 (run 2, RMSE 0.0170 m)"
  std::optional<Trajectory> keyframes;  // nullopt: nothing to draw, label is a note
};

struct DatasetPlots {
  std::string name;         // file name prefix
  Trajectory ground_truth;  // T_world_cam over the frames the runs used
  double max_dt = 0.02;     // association of keyframes to the ground truth
  std::vector<PlottedMethod> methods;
};

// Writes both PNGs into plots_dir (created if needed); returns their paths. A method whose
// trajectory cannot be aligned becomes a note saying why.
std::vector<std::string> writeDatasetPlots(const std::string& plots_dir, const DatasetPlots& input);

// The indices (0, 1, 2) of the two axes along which the positions extend most, in
// increasing order: the plane of the top view.
std::pair<int, int> topViewAxes(const Trajectory& trajectory);

}  // namespace omnidso::cli
