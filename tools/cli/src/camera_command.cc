// `omnidso camera info CALIB [--json]` and
// `omnidso camera convert CALIB --to MODEL --out FILE [--format kalibr|dso] [--force] [--json]`.
// Thin: loading, field of view and model fitting live in omnidso::cameras.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <omnidso/cameras/calibration_io.hpp>
#include <omnidso/cameras/field_of_view.hpp>
#include <omnidso/cameras/model_fitting.hpp>
#include <omnidso/cli/commands.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso::cli {
namespace {

using Json = nlohmann::ordered_json;

struct InfoArgs {
  std::string calib;
  bool json = false;
};

struct ConvertArgs {
  std::string calib;
  std::string to;
  std::string out;
  std::string format;  // kalibr | dso; empty: from the extension of `out`
  bool force = false;
  bool json = false;
};

Json parametersJson(const Camera& camera) {
  Json params = Json::object();
  const Eigen::VectorXd values = camera.params();
  const std::vector<std::string> names = camera.paramNames();
  for (size_t i = 0; i < names.size(); ++i) params[names[i]] = values[static_cast<int>(i)];
  return params;
}

Json cameraJson(const Camera& camera) {
  return Json{{"model", camera.modelName()},
              {"width", camera.width()},
              {"height", camera.height()},
              {"parameters", parametersJson(camera)}};
}

void printParameters(const Camera& camera) {
  const Eigen::VectorXd values = camera.params();
  const std::vector<std::string> names = camera.paramNames();
  for (size_t i = 0; i < names.size(); ++i) {
    std::cout << "  " << std::left << std::setw(4) << names[i] << " = " << std::setprecision(10)
              << values[static_cast<int>(i)] << "\n";
  }
}

void runInfo(const InfoArgs& args) {
  const Camera camera = loadCalibration(args.calib);
  const FieldOfView fov = fieldOfView(camera);
  if (args.json) {
    Json out = cameraJson(camera);
    out["file"] = args.calib;
    out["fov_deg"] = {{"horizontal", fov.horizontal_deg},
                      {"vertical", fov.vertical_deg},
                      {"diagonal", fov.diagonal_deg},
                      {"maximum", fov.maximum_deg}};
    out["valid_pixel_fraction"] = fov.valid_pixel_fraction;
    std::cout << out.dump(2) << "\n";
    return;
  }
  std::cout << args.calib << "\n"
            << "model:      " << camera.modelName() << "\n"
            << "resolution: " << camera.width() << " x " << camera.height() << "\n"
            << "parameters:\n";
  printParameters(camera);
  std::cout << std::fixed << std::setprecision(2) << "field of view (deg): horizontal "
            << fov.horizontal_deg << ", vertical " << fov.vertical_deg << ", diagonal "
            << fov.diagonal_deg << ", maximum " << fov.maximum_deg << "\n"
            << "valid pixels: " << 100.0 * fov.valid_pixel_fraction << " %\n";
}

void runConvert(const ConvertArgs& args) {
  std::string format = args.format;
  if (format.empty()) {
    format = std::filesystem::path(args.out).extension() == ".txt" ? "dso" : "kalibr";
  }
  if (std::filesystem::exists(args.out) && !args.force) {
    throw Error(args.out + ": exists; pass --force to overwrite it");
  }
  const Camera source = loadCalibration(args.calib);
  const FitResult fit = fitCameraModel(source, args.to);
  if (format == "dso") {
    saveDsoCameraTxt(args.out, fit.camera);
  } else {
    saveKalibr(args.out, fit.camera);
  }
  if (args.json) {
    Json out{{"source", cameraJson(source)},
             {"target", cameraJson(fit.camera)},
             {"out", args.out},
             {"format", format},
             {"rms_error_px", fit.rms_error_px},
             {"max_error_px", fit.max_error_px},
             {"num_samples", fit.num_samples},
             {"num_validation", fit.num_validation},
             {"validation_outside_domain", fit.validation_outside_domain}};
    std::cout << out.dump(2) << "\n";
    return;
  }
  std::cout << source.modelName() << " -> " << fit.camera.modelName() << " (" << args.out << ", "
            << format << ")\nparameters:\n";
  printParameters(fit.camera);
  std::cout << std::scientific << std::setprecision(3) << "reprojection error over "
            << fit.num_validation << " validation bearings: rms " << fit.rms_error_px << " px, max "
            << fit.max_error_px << " px\n";
  if (fit.validation_outside_domain > 0) {
    std::cout << "warning: " << fit.validation_outside_domain << " of " << fit.num_validation
              << " validation bearings lie outside the " << fit.camera.modelName()
              << " model's domain (not counted in the errors)\n";
  }
}

}  // namespace

void registerCameraCommand(CLI::App& app) {
  CLI::App* camera =
      app.add_subcommand("camera", "Inspect camera calibrations and convert between models");
  camera->require_subcommand(1);

  auto info_args = std::make_shared<InfoArgs>();
  CLI::App* info = camera->add_subcommand(
      "info", "Model, parameters, resolution, field of view and valid-pixel fraction");
  info->add_option("CALIB", info_args->calib,
                   "Calibration file (Kalibr YAML, DSO camera.txt or EuRoC sensor.yaml)")
      ->required();
  info->add_flag("--json", info_args->json, "Print JSON");
  info->callback([info_args] { runInfo(*info_args); });

  auto convert_args = std::make_shared<ConvertArgs>();
  CLI::App* convert =
      camera->add_subcommand("convert", "Fit another camera model to a calibration and write it");
  convert->add_option("CALIB", convert_args->calib, "Calibration file to convert")->required();
  std::string known;
  for (const std::string& name : knownCameraModelNames())
    known += (known.empty() ? "" : ", ") + name;
  convert->add_option("--to", convert_args->to, "Target model: " + known)->required();
  convert->add_option("--out", convert_args->out, "Output calibration file")->required();
  convert
      ->add_option("--format", convert_args->format,
                   "kalibr or dso (default: dso for a .txt output, else kalibr)")
      ->check(CLI::IsMember({"kalibr", "dso"}));
  convert->add_flag("--force", convert_args->force, "Overwrite an existing output file");
  convert->add_flag("--json", convert_args->json, "Print JSON");
  convert->callback([convert_args] { runConvert(*convert_args); });
}

}  // namespace omnidso::cli
