// Kalibr camchain / camera YAML and EuRoC sensor.yaml (calibration_io.hpp for the formats).
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "calibration_yaml.hpp"
#include "omnidso/cameras/calibration_io.hpp"
#include "omnidso/core/error.hpp"

namespace omnidso {
namespace detail {

YAML::Node readYamlFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open calibration file");
  std::stringstream text;
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    // OpenCV writes "%YAML:1.0", which is not a valid YAML directive: keep the line count.
    if (first && line.rfind("%YAML:", 0) == 0) line = "";
    first = false;
    text << line << "\n";
  }
  try {
    return YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    throw fileError(path, e.mark.line + 1, "malformed YAML: " + e.msg);
  }
}

}  // namespace detail

namespace {

// One YAML mapping with the file name and the path prefix ("cam0.") for error messages.
class FieldReader {
 public:
  FieldReader(std::string file, YAML::Node node, std::string prefix)
      : file_(std::move(file)), node_(std::move(node)), prefix_(std::move(prefix)) {}

  bool has(const std::string& key) const { return static_cast<bool>(node_[key]); }
  std::string name(const std::string& key) const { return prefix_ + key; }
  Error error(const std::string& key, const std::string& message) const {
    return fieldError(file_, name(key), message);
  }

  const YAML::Node node(const std::string& key) const {
    const YAML::Node n = node_[key];
    if (!n) throw error(key, "missing");
    return n;
  }
  // A nested mapping (T_BS): anything else would make its fields unreadable.
  const YAML::Node map(const std::string& key) const {
    const YAML::Node n = node(key);
    if (!n.IsMap()) throw error(key, "expected a mapping");
    return n;
  }

  std::string text(const std::string& key) const {
    const YAML::Node n = node(key);
    if (!n.IsScalar()) throw error(key, "expected a name");
    return n.Scalar();
  }

  // A sequence of finite numbers (NaN and ±inf are rejected).
  std::vector<double> numbers(const std::string& key) const { return numbersOf(node(key), key); }
  std::vector<double> numbersOf(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence()) throw error(key, "expected a list of numbers");
    std::vector<double> out;
    for (size_t i = 0; i < n.size(); ++i) {
      double x = 0.0;
      try {
        x = n[i].as<double>();
      } catch (const YAML::Exception&) {
        throw error(key, "element " + std::to_string(i) + " is not a number");
      }
      if (!std::isfinite(x)) {
        throw error(key, "element " + std::to_string(i) + " is not a finite number");
      }
      out.push_back(x);
    }
    return out;
  }

  void requireCount(const std::string& key, const std::vector<double>& values, size_t n,
                    const std::string& what) const {
    if (values.size() != n) {
      throw error(key, "expected " + std::to_string(n) + " values " + what + ", got " +
                           std::to_string(values.size()));
    }
  }

  // resolution: [w, h], positive integers.
  std::pair<int, int> resolution() const {
    const std::vector<double> r = numbers("resolution");
    requireCount("resolution", r, 2, "[width, height]");
    if (r[0] < 1 || r[1] < 1 || r[0] != std::floor(r[0]) || r[1] != std::floor(r[1]) ||
        r[0] > kMaxImageSide || r[1] > kMaxImageSide) {
      throw error("resolution", "width and height must be integers in [1, " +
                                    std::to_string(kMaxImageSide) + "]");
    }
    return {static_cast<int>(r[0]), static_cast<int>(r[1])};
  }

 private:
  std::string file_;
  YAML::Node node_;
  std::string prefix_;
};

// Kalibr's (camera_model, intrinsics, distortion) → our model name and parameter order.
Camera cameraFromKalibrFields(const FieldReader& f, const std::string& coeffs_key) {
  const std::string camera_model = f.text("camera_model");
  const std::vector<double> in = f.numbers("intrinsics");
  std::string name;
  Eigen::VectorXd params;
  const auto take = [&](size_t n, const std::string& order, const std::vector<int>& to_internal) {
    f.requireCount("intrinsics", in, n, order + " for camera_model '" + camera_model + "'");
    params.resize(static_cast<int>(n));
    for (size_t i = 0; i < n; ++i) params[to_internal[i]] = in[i];
  };
  // Internal order is always [fx, fy, cx, cy, extra...].
  if (camera_model == "pinhole") {
    take(4, "[fu, fv, pu, pv]", {0, 1, 2, 3});
    name = "pinhole";
  } else if (camera_model == "omni") {
    take(5, "[xi, fu, fv, pu, pv]", {4, 0, 1, 2, 3});
    name = "ucm";
  } else if (camera_model == "eucm") {
    take(6, "[alpha, beta, fu, fv, pu, pv]", {4, 5, 0, 1, 2, 3});
    name = "eucm";
  } else if (camera_model == "ds") {
    take(6, "[xi, alpha, fu, fv, pu, pv]", {4, 5, 0, 1, 2, 3});
    name = "ds";
  } else {
    throw f.error("camera_model",
                  "unknown camera model '" + camera_model + "' (known: pinhole, omni, eucm, ds)");
  }
  if (!(params[0] > 0.0) || !(params[1] > 0.0)) {
    throw f.error("intrinsics", "focal lengths fu, fv must be positive, got " +
                                    std::to_string(params[0]) + ", " + std::to_string(params[1]));
  }

  const std::string distortion =
      f.has("distortion_model") ? f.text("distortion_model") : std::string("none");
  const std::vector<double> coeffs =
      f.has(coeffs_key) ? f.numbers(coeffs_key) : std::vector<double>();
  const auto append_coeffs = [&](const std::string& order) {
    f.requireCount(coeffs_key, coeffs, 4, order);
    params.conservativeResize(params.size() + 4);
    for (int i = 0; i < 4; ++i) params[params.size() - 4 + i] = coeffs[i];
  };
  if (distortion == "none") {
    for (double c : coeffs) {
      if (c != 0.0) throw f.error(coeffs_key, "non-zero coefficients with distortion_model none");
    }
  } else if ((distortion == "radtan" || distortion == "radial-tangential") &&
             (name == "pinhole" || name == "ucm")) {
    append_coeffs("[k1, k2, p1, p2]");
    name += "-radtan";
  } else if ((distortion == "equidistant" || distortion == "equi") && name == "pinhole") {
    append_coeffs("[k1, k2, k3, k4]");
    name = "kb4";
  } else if (distortion == "fov" && name == "pinhole") {
    // Kalibr's FovDistortion: one coefficient, the ω of Devernay & Faugeras. Its range is
    // Camera::create's, checked here so that the message names this field.
    f.requireCount(coeffs_key, coeffs, 1, "[w]");
    if (!(coeffs[0] > 0.0 && coeffs[0] < M_PI)) {
      throw f.error(coeffs_key, "w must be in (0, pi), got " + std::to_string(coeffs[0]));
    }
    params.conservativeResize(5);
    params[4] = coeffs[0];
    name = "fov";
  } else {
    throw f.error("distortion_model", "distortion model '" + distortion +
                                          "' is not supported with camera_model '" + camera_model +
                                          "' (pinhole: none, radtan, "
                                          "equidistant, fov; omni: none, radtan; eucm, ds: none)");
  }

  const auto [width, height] = f.resolution();
  try {
    return Camera::create(name, params, width, height);
  } catch (const Error& e) {
    throw f.error("intrinsics", e.what());
  }
}

// A row-major 4×4 matrix that must be a rigid transformation (EuRoC's T_BS, Kalibr's
// T_cam_imu). Published extrinsics carry ~1e-9 rounding; 1e-6 rejects anything that is not a
// rotation.
SE3d rigidTransform(const FieldReader& f, const std::string& key,
                    const std::vector<double>& row_major) {
  const Eigen::Matrix4d T =
      Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(row_major.data());
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0.0 ||
      (T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9) {
    throw f.error(key, "not a rigid transformation");
  }
  return SE3d(R, T.topRightCorner<3, 1>());
}

void requireMap(const YAML::Node& root, const std::string& path) {
  if (!root.IsMap()) throw fileError(path, "expected a YAML mapping of calibration fields");
}

// cam0's fields of a Kalibr file: under `cam0:` (a camchain) or at the top (one camera).
FieldReader kalibrCam0Fields(const std::string& path) {
  const YAML::Node root = detail::readYamlFile(path);
  requireMap(root, path);
  if (!root["cam0"]) return FieldReader(path, root, "");
  if (!root["cam0"].IsMap()) throw fieldError(path, "cam0", "expected a mapping");
  return FieldReader(path, root["cam0"], "cam0.");
}

}  // namespace

Camera loadKalibr(const std::string& path) {
  return cameraFromKalibrFields(kalibrCam0Fields(path), "distortion_coeffs");
}

SensorCalibration loadEurocSensor(const std::string& path) {
  const YAML::Node root = detail::readYamlFile(path);
  requireMap(root, path);
  const FieldReader f(path, root, "");
  Camera camera = cameraFromKalibrFields(f, "distortion_coefficients");

  const FieldReader t(path, f.map("T_BS"), "T_BS.");
  const std::vector<double> data = t.numbers("data");
  t.requireCount("data", data, 16, "(a row-major 4x4 matrix)");
  return {std::move(camera), rigidTransform(t, "data", data)};
}

std::optional<SE3d> loadKalibrCamImu(const std::string& path) {
  const FieldReader f = kalibrCam0Fields(path);
  if (!f.has("T_cam_imu")) return std::nullopt;
  const YAML::Node rows = f.node("T_cam_imu");
  if (!rows.IsSequence() || rows.size() != 4) {
    throw f.error("T_cam_imu", "expected four rows of four numbers");
  }
  std::vector<double> data;
  for (size_t i = 0; i < 4; ++i) {
    const std::vector<double> row = f.numbersOf(rows[i], "T_cam_imu");
    f.requireCount("T_cam_imu", row, 4, "in row " + std::to_string(i));
    data.insert(data.end(), row.begin(), row.end());
  }
  return rigidTransform(f, "T_cam_imu", data);
}

void saveKalibr(const std::string& path, const Camera& camera) {
  const std::string name = camera.modelName();
  const Eigen::VectorXd p = camera.params();
  std::string camera_model = "pinhole";
  std::string distortion = "none";
  std::vector<double> intrinsics{p[0], p[1], p[2], p[3]};
  std::vector<double> coeffs;
  const auto tail = [&](int from) {
    return std::vector<double>(p.data() + from, p.data() + p.size());
  };
  static const std::map<std::string, std::string> kPinholeDistortions = {
      {"pinhole-radtan", "radtan"}, {"kb4", "equidistant"}, {"fov", "fov"}};
  if (const auto d = kPinholeDistortions.find(name); d != kPinholeDistortions.end()) {
    distortion = d->second;
    coeffs = tail(4);
  } else if (name == "ucm" || name == "ucm-radtan") {
    camera_model = "omni";
    intrinsics.insert(intrinsics.begin(), p[4]);
    if (name == "ucm-radtan") {
      distortion = "radtan";
      coeffs = tail(5);
    }
  } else if (name == "eucm" || name == "ds") {
    camera_model = name;
    intrinsics.insert(intrinsics.begin(), {p[4], p[5]});
  } else if (name != "pinhole") {
    throw Error(path + ": camera model '" + name + "' has no Kalibr form");
  }

  YAML::Emitter out;
  out.SetDoublePrecision(17);  // shortest form that round-trips every double
  out << YAML::BeginMap << YAML::Key << "cam0" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "camera_model" << YAML::Value << camera_model;
  out << YAML::Key << "intrinsics" << YAML::Value << YAML::Flow << intrinsics;
  out << YAML::Key << "distortion_model" << YAML::Value << distortion;
  out << YAML::Key << "distortion_coeffs" << YAML::Value << YAML::Flow << coeffs;
  out << YAML::Key << "resolution" << YAML::Value << YAML::Flow
      << std::vector<int>{camera.width(), camera.height()};
  out << YAML::EndMap << YAML::EndMap;

  std::ofstream file(path);
  if (!file) throw fileError(path, "cannot open for writing");
  file << "# omnidso: Kalibr camchain (" << name << ")\n" << out.c_str() << "\n";
  if (!file) throw fileError(path, "write failed");
}

}  // namespace omnidso
