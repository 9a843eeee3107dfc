// DSO's camera.txt (format in calibration_io.hpp).
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <vector>

#include "calibration_text.hpp"
#include "omnidso/cameras/calibration_io.hpp"
#include "omnidso/core/error.hpp"

namespace omnidso {
namespace {

struct DsoModel {
  std::string name;  // our kName
  int num_values;    // numbers after the keyword
};

// camera.txt keywords and the model each names. Pinhole has a fifth number, always 0.
const std::map<std::string, DsoModel>& dsoKeywords() {
  static const std::map<std::string, DsoModel> kKeywords = {
      {"Pinhole", {"pinhole", 5}},   {"RadTan", {"pinhole-radtan", 8}},
      {"KannalaBrandt", {"kb4", 8}}, {"EquiDistant", {"kb4", 8}},
      {"FOV", {"fov", 5}},           {"UCM", {"ucm", 5}},
      {"Unified", {"ucm", 5}},       {"UnifiedModel", {"ucm", 5}},
      {"Omni", {"ucm", 5}}};
  return kKeywords;
}

std::pair<int, int> imageSize(const std::string& path, int line_no, const std::string& line,
                              const std::string& what) {
  std::vector<double> v;
  try {
    v = detail::finiteNumbers(path, line_no, detail::textTokens(line), 0);
  } catch (const Error&) {
    v.clear();  // reported below, with what the line should hold
  }
  if (v.size() != 2 || v[0] < 1 || v[1] < 1 || v[0] != std::floor(v[0]) ||
      v[1] != std::floor(v[1]) || v[0] > kMaxImageSide || v[1] > kMaxImageSide) {
    throw fileError(path, line_no,
                    "expected '" + what + "' (two integers in [1, " +
                        std::to_string(kMaxImageSide) + "])");
  }
  return {static_cast<int>(v[0]), static_cast<int>(v[1])};
}

}  // namespace

Camera loadDsoCameraTxt(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open calibration file");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  while (!lines.empty() && detail::textTokens(lines.back()).empty()) lines.pop_back();
  if (lines.size() < 2) {
    throw fileError(path,
                    "expected at least 2 lines: 'MODEL fx fy cx cy ...' and "
                    "'in_width in_height'");
  }

  const std::vector<std::string> toks = detail::textTokens(lines[0]);
  if (toks.empty()) throw fileError(path, 1, "expected 'MODEL fx fy cx cy ...'");
  const bool has_keyword = !std::isdigit(static_cast<unsigned char>(toks[0][0])) &&
                           toks[0][0] != '-' && toks[0][0] != '.' && toks[0][0] != '+';
  DsoModel model{"pinhole-radtan", 8};
  if (has_keyword) {
    const auto it = dsoKeywords().find(toks[0]);
    if (it == dsoKeywords().end()) {
      throw fileError(path, 1,
                      "unknown camera model '" + toks[0] +
                          "' (known: Pinhole, RadTan, KannalaBrandt, EquiDistant, FOV, "
                          "UCM/Unified/UnifiedModel/Omni)");
    }
    model = it->second;
  }
  std::vector<double> values = detail::finiteNumbers(path, 1, toks, has_keyword ? 1 : 0);
  // Without a keyword DSO tells the model by the count: 8 numbers RadTan, 5 FOV (ATAN,
  // DSO's original format and TUM monoVO's).
  if (!has_keyword) {
    if (values.size() == 5) model = {"fov", 5};
    if (values.size() != 5 && values.size() != 8) {
      throw fileError(path, 1,
                      "a line without a model keyword takes 5 numbers (FOV: fx fy cx cy w) or 8 "
                      "(RadTan: fx fy cx cy k1 k2 p1 p2), got " +
                          std::to_string(values.size()));
    }
  }
  if (static_cast<int>(values.size()) != model.num_values) {
    throw fileError(path, 1,
                    "camera model '" + model.name + "' takes " + std::to_string(model.num_values) +
                        " numbers, got " + std::to_string(values.size()));
  }
  if (model.name == "pinhole") {
    if (values[4] != 0.0) throw fileError(path, 1, "Pinhole: the fifth number must be 0");
    values.pop_back();
  }
  const auto [width, height] = imageSize(path, 2, lines[1], "in_width in_height");

  // DSO's relative form (cx, cy < 1): fractions of the image size with the pixel-corner
  // origin; −0.5 moves it to our pixel-centre origin.
  if (values[2] < 1.0 && values[3] < 1.0) {
    values[0] *= width;
    values[1] *= height;
    values[2] = values[2] * width - 0.5;
    values[3] = values[3] * height - 0.5;
  }

  if (lines.size() >= 3) {
    const std::vector<std::string> crop = detail::textTokens(lines[2]);
    const bool keyword =
        crop.size() == 1 && (crop[0] == "crop" || crop[0] == "full" || crop[0] == "none");
    if (!keyword && !(crop.size() == 5 && detail::finiteNumbers(path, 3, crop, 0).size() == 5)) {
      throw fileError(path, 3, "expected 'crop', 'full', 'none' or 'fx fy cx cy 0'");
    }
    if (lines.size() < 4) throw fileError(path, 4, "missing 'out_width out_height'");
    imageSize(path, 4, lines[3], "out_width out_height");
  }

  try {
    return Camera::create(
        model.name, Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<int>(values.size())),
        width, height);
  } catch (const Error& e) {
    throw fileError(path, 1, e.what());
  }
}

std::string dsoCameraTxtKeyword(const std::string& name) {
  if (name == "pinhole") return "Pinhole";
  if (name == "pinhole-radtan") return "RadTan";
  if (name == "kb4") return "KannalaBrandt";
  if (name == "fov") return "FOV";
  if (name == "ucm") return "UCM";
  return "";
}

void saveDsoCameraTxt(const std::string& path, const Camera& camera) {
  const std::string name = camera.modelName();
  const std::string keyword = dsoCameraTxtKeyword(name);
  if (keyword.empty()) {
    throw Error(path + ": DSO's camera.txt has no form for camera model '" + name +
                "' (it has pinhole, pinhole-radtan, kb4, fov and, as this project's extension, ucm)");
  }
  std::ofstream file(path);
  if (!file) throw fileError(path, "cannot open for writing");
  file << std::setprecision(17) << keyword;
  const Eigen::VectorXd p = camera.params();
  for (int i = 0; i < p.size(); ++i) file << " " << p[i];
  if (name == "pinhole") file << " 0";
  file << "\n"
       << camera.width() << " " << camera.height() << "\nnone\n"
       << camera.width() << " " << camera.height() << "\n";
  if (!file) throw fileError(path, "write failed");
}

}  // namespace omnidso
