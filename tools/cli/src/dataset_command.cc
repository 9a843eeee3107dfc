// `omnidso dataset info DIR [--json]`: the health check a researcher runs before a long
// run. It opens the dataset (core/dataset.hpp), reads every image header, loads the
// calibration, the photometric calibration and the ground truth, and reports; any broken
// part throws omnidso::Error naming the file and line.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include <omnidso/cameras/field_of_view.hpp>
#include <omnidso/cli/commands.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/photometric_calibration.hpp>
#include <omnidso/synth/dataset_loading.hpp>

namespace omnidso::cli {
namespace {

struct DatasetInfoArguments {
  std::string path;
  std::string calib;
  bool json = false;
  bool decode = false;
};

nlohmann::json optionalPath(const std::optional<std::string>& path) {
  return path ? nlohmann::json(*path) : nlohmann::json(nullptr);
}

// Whose poses the ground truth holds, for the report.
std::string groundTruthFrame(GroundTruthKind kind, const std::string& extrinsics_source) {
  switch (kind) {
    case GroundTruthKind::kBodyAsl:
      return "body, composed with the extrinsics in " + extrinsics_source;
    case GroundTruthKind::kCameraKitti:
      return "camera, one KITTI pose per frame";
    case GroundTruthKind::kCameraTum:
    case GroundTruthKind::kNone:
      break;
  }
  return "camera";
}

nlohmann::json datasetInfo(const DatasetInfoArguments& args) {
  const DatasetIndex index = openDataset(args.path);
  for (const std::string& warning : index.warnings) std::cerr << "warning: " << warning << "\n";
  verifyDatasetImages(index, args.decode);
  const Camera camera = synth::datasetCamera(index, args.calib);
  const FieldOfView fov = fieldOfView(camera);
  // Loading checks the files (value count, monotone G⁻¹, vignette size).
  const PhotometricCalibration photometric = PhotometricCalibration::fromFiles(
      index.pcalib_path.value_or(""), index.vignette_path.value_or(""));
  photometric.checkImageSize(index.width, index.height);
  std::optional<Trajectory> ground_truth;
  std::string extrinsics_source;  // body poses only
  if (index.groundtruth_path) ground_truth = synth::cameraGroundTruth(index, &extrinsics_source);

  const auto exposure = std::minmax_element(
      index.frames.begin(), index.frames.end(),
      [](const DatasetFrame& a, const DatasetFrame& b) { return a.exposure_ms < b.exposure_ms; });
  const bool exposure_known = exposure.first->exposure_ms > 0;
  nlohmann::json params = nlohmann::json::array();
  const Eigen::VectorXd p = camera.params();
  for (Eigen::Index i = 0; i < p.size(); ++i) params.push_back(p[i]);

  nlohmann::json info = {
      {"path", index.root},
      {"layout", datasetLayoutName(index.layout)},
      {"frames", index.frames.size()},
      {"width", index.width},
      {"height", index.height},
      {"first_timestamp_s", index.frames.front().timestamp_s},
      {"time_span_s", datasetDuration(index)},
      {"rate_hz", datasetFrameRate(index)},
      {"exposure",
       {{"known", exposure_known},
        {"min_ms", exposure.first->exposure_ms},
        {"max_ms", exposure.second->exposure_ms}}},
      {"camera",
       {{"model", camera.modelName()},
        {"params", params},
        {"param_names", camera.paramNames()},
        {"calibration_file", args.calib.empty() ? index.calibration_paths.front() : args.calib},
        {"fov_deg",
         {{"horizontal", fov.horizontal_deg},
          {"vertical", fov.vertical_deg},
          {"diagonal", fov.diagonal_deg},
          {"maximum", fov.maximum_deg}}}}},
      {"photometric_calibration",
       {{"present", index.pcalib_path.has_value() || index.vignette_path.has_value()},
        {"pcalib", optionalPath(index.pcalib_path)},
        {"vignette", optionalPath(index.vignette_path)}}},
      {"ground_truth",
       {{"present", ground_truth.has_value()},
        {"path", optionalPath(index.groundtruth_path)},
        {"frame", groundTruthFrame(index.groundtruth_kind, extrinsics_source)},
        {"poses", ground_truth ? ground_truth->size() : 0}}},
  };
  return info;
}

void printInfo(const nlohmann::json& info) {
  const auto& camera = info["camera"];
  const auto& fov = camera["fov_deg"];
  const auto& exposure = info["exposure"];
  const auto& photometric = info["photometric_calibration"];
  const auto& gt = info["ground_truth"];
  std::cout << fmt::format("dataset        {}\n", info["path"].get<std::string>())
            << fmt::format("layout         {}\n", info["layout"].get<std::string>())
            << fmt::format("frames         {}\n", info["frames"].get<size_t>())
            << fmt::format("resolution     {}x{}\n", info["width"].get<int>(),
                           info["height"].get<int>())
            << fmt::format("time span      {:.3f} s at {:.2f} Hz\n",
                           info["time_span_s"].get<double>(), info["rate_hz"].get<double>())
            << (exposure["known"].get<bool>()
                    ? fmt::format("exposure       {:.3f} .. {:.3f} ms\n",
                                  exposure["min_ms"].get<double>(),
                                  exposure["max_ms"].get<double>())
                    : std::string("exposure       unknown\n"))
            << fmt::format("camera         {} ({})\n", camera["model"].get<std::string>(),
                           camera["calibration_file"].get<std::string>())
            << fmt::format("field of view  {:.1f} deg horizontal, {:.1f} diagonal, {:.1f} maximum\n",
                           fov["horizontal"].get<double>(), fov["diagonal"].get<double>(),
                           fov["maximum"].get<double>())
            << fmt::format("photometric    pcalib {}, vignette {}\n",
                           photometric["pcalib"].is_null() ? "absent" : "present",
                           photometric["vignette"].is_null() ? "absent" : "present")
            << (gt["present"].get<bool>()
                    ? fmt::format("ground truth   {} poses ({})\n", gt["poses"].get<size_t>(),
                                  gt["frame"].get<std::string>())
                    : std::string("ground truth   absent\n"));
}

}  // namespace

void registerDatasetCommand(CLI::App& app) {
  CLI::App* cmd =
      app.add_subcommand("dataset", "inspect a dataset (TUM, ASL or KITTI odometry layout)");
  cmd->require_subcommand(1);
  auto args = std::make_shared<DatasetInfoArguments>();
  CLI::App* info = cmd->add_subcommand(
      "info", "layout, frames, resolution, rate, camera and field of view, photometric "
              "calibration and ground truth; checks every image header");
  info->add_option("dir", args->path, "dataset directory")->required();
  info->add_option("--calib", args->calib, "calibration file overriding the dataset's");
  info->add_flag("--json", args->json, "print a JSON object");
  info->add_flag("--decode", args->decode,
                 "decode every image, not only its header (slower; finds corrupt pixel data)");
  info->callback([args] {
    const nlohmann::json result = datasetInfo(*args);
    if (args->json) {
      std::cout << result.dump(2) << "\n";
    } else {
      printInfo(result);
    }
  });
}

}  // namespace omnidso::cli
