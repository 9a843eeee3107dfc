#pragma once
// Calibration files: Kalibr camchain / camera YAML, DSO's camera.txt, EuRoC's sensor.yaml
// (ASL layout) and KITTI odometry's calib.txt. All readers check what they read and throw
// omnidso::Error whose message names the file and the field (YAML) or line (text files).
//
// Kalibr (`cam0:` level optional):
//   camera_model: pinhole | omni | eucm | ds
//   intrinsics:   pinhole [fu, fv, pu, pv]; omni [xi, fu, fv, pu, pv];
//                 eucm [alpha, beta, fu, fv, pu, pv]; ds [xi, alpha, fu, fv, pu, pv]
//   distortion_model: none | radtan | equidistant | fov  (pinhole+equidistant = kb4;
//                 pinhole+fov = fov; pinhole/omni + radtan = pinhole-radtan / ucm-radtan)
//   distortion_coeffs: [k1, k2, p1, p2] (radtan), [k1, k2, k3, k4] (equidistant) or [w] (fov)
//   resolution: [width, height]
//
// DSO camera.txt (github.com/JakobEngel/dso, "Geometric Calibration File"):
//   line 1: MODEL fx fy cx cy extra...   with MODEL one of
//             Pinhole fx fy cx cy 0
//             RadTan fx fy cx cy k1 k2 p1 p2          (keyword optional: 8 numbers)
//             KannalaBrandt | EquiDistant fx fy cx cy k1 k2 k3 k4
//             FOV fx fy cx cy w                       (keyword optional: 5 numbers; DSO's
//                                                      original ATAN format, TUM monoVO's)
//             UCM fx fy cx cy xi     — this project's extension for the unified model
//                                      (aliases Unified, UnifiedModel, Omni); upstream DSO
//                                      has no omnidirectional model.
//           Relative intrinsics as DSO reads them: when cx < 1 and cy < 1 the four values are
//           fractions of the image size and fx·w, fy·h, cx·w − 0.5, cy·h − 0.5 are used (the
//           −0.5 moves DSO's pixel-corner origin to our pixel-centre origin).
//   line 2: in_width in_height  (the raw image: the Camera returned has this size)
//   line 3: crop | full | none | "fx fy cx cy 0"  (DSO's rectification target; read, checked
//           for form and otherwise ignored: this project runs on the raw model)
//   line 4: out_width out_height
//   Files are written with absolute intrinsics, line 3 `none` and line 4 = line 2.
//
// EuRoC sensor.yaml: camera_model pinhole, intrinsics [fu, fv, cu, cv], distortion_model
// radial-tangential (or none), distortion_coefficients [k1, k2, p1, p2], resolution [w, h],
// T_BS {rows: 4, cols: 4, data: 16 numbers, row-major} = T_body_sensor. The first line
// `%YAML:1.0` (OpenCV style, not valid YAML) is skipped.
//
// KITTI odometry calib.txt (dataset/sequences/NN/calib.txt): lines `P0: 12 numbers`, `P1:`,
// `P2:`, `P3:` (the rectified projections of image_0..image_3) and `Tr:` (velodyne → camera
// 0), each a 3×4 matrix row-major. Only P0 = K·[I|t] is read (t = 0 for camera 0; a skew or
// rotation is refused): fx = P0[0], cx = P0[2], fy = P0[5], cy = P0[6], a pinhole without
// distortion (the images are rectified), the principal point with the top-left pixel's
// centre at (0, 0) as ours. The file has no image size: it comes from the images, so
// loadKittiCalib takes it and loadCalibration refuses.
//
// Kalibr's camera–IMU extrinsics: `T_cam_imu`, four rows of four numbers, maps IMU-frame
// coordinates into the camera frame (x_cam = T_cam_imu · x_imu), so T_body_sensor =
// T_cam_imu⁻¹ with the IMU as the body. TUM VI ships them in `dso/camchain.yaml`.

#include <optional>
#include <string>

#include "omnidso/cameras/camera.hpp"
#include "omnidso/core/se3.hpp"

namespace omnidso {

enum class CalibrationFormat { kKalibr, kDsoCameraTxt, kEurocSensor, kKittiCalib };

// Looks at the content: a line starting with `P0:` (not in a .yaml/.yml file) → KITTI;
// YAML with `T_BS` or `distortion_coefficients` → EuRoC; YAML with `cam0` or `camera_model`
// → Kalibr; otherwise camera.txt. Throws for unreadable files and for a .yaml/.yml file
// that is not valid YAML.
CalibrationFormat detectCalibrationFormat(const std::string& path);

// Kalibr, camera.txt or sensor.yaml (detectCalibrationFormat). Throws for KITTI's
// calib.txt, which needs the image size (loadKittiCalib).
Camera loadCalibration(const std::string& path);

Camera loadKalibr(const std::string& path);
Camera loadDsoCameraTxt(const std::string& path);
// A `pinhole` Camera of width × height from P0. Throws, naming the file and line, when there
// is no P0 line, it has other than 12 numbers, a field is not a finite number, P0 is not of
// the form K·[I|t] (a skew, a rotation), or fx or fy ≤ 0.
Camera loadKittiCalib(const std::string& path, int width, int height);

struct SensorCalibration {
  Camera camera;
  SE3d T_body_sensor;
};
SensorCalibration loadEurocSensor(const std::string& path);
// cam0's T_cam_imu of a Kalibr file; nullopt when the file has none. Throws for a matrix that
// is not 4×4 numbers or not a rigid transformation.
std::optional<SE3d> loadKalibrCamImu(const std::string& path);

// Writes `cam0:` with camera_model, intrinsics, distortion_model, distortion_coeffs,
// resolution. Every model of CameraModelVariant has a Kalibr form.
void saveKalibr(const std::string& path, const Camera& camera);
// The camera.txt keyword of a model (Pinhole, RadTan, KannalaBrandt, FOV, UCM); empty for the
// models camera.txt cannot hold (eucm, ds, ucm-radtan).
std::string dsoCameraTxtKeyword(const std::string& model_name);
// Throws omnidso::Error for models camera.txt cannot hold (eucm, ds, ucm-radtan).
void saveDsoCameraTxt(const std::string& path, const Camera& camera);

}  // namespace omnidso
