#pragma once
// DSO's photometric camera model (Engel et al., "A Photometrically Calibrated Benchmark for
// Monocular Visual Odometry"): a raw pixel value is
//   I_raw(x) = G(t · V(x) · B(x)),
// with B the scene irradiance, V the vignette (attenuation in [0, 1]), t the exposure time
// and G the camera response. Calibration files (docs/architecture.md):
//   pcalib.txt   — the inverse response G⁻¹ as one line of 256 whitespace-separated numbers,
//                  G⁻¹(k) for pixel value k = 0..255; non-decreasing.
//   vignette.png — V as an 8- or 16-bit image, normalised by its maximum.
// Either may be absent: G⁻¹ is then the identity (k → k) and V ≡ 1.
//
// correct() returns the "energy" G⁻¹(I_raw)/V = t·B, NOT divided by the exposure time: the
// photometric residual (eq. 5) compares frames through the exposure ratio t_j/t_i (with
// the affine brightness a, b), so exposure stays a per-frame number next to the image
// instead of being folded into its intensities. toIrradiance() divides by t when the true
// irradiance B is wanted (e.g. to compare renderings).

#include <array>
#include <string>

#include "omnidso/core/image.hpp"
#include "omnidso/core/image_io.hpp"

namespace omnidso {

constexpr int kResponseSize = 256;
// G⁻¹(k) for pixel values k = 0..255.
using InverseResponse = std::array<double, kResponseSize>;

InverseResponse identityInverseResponse();

// Reads DSO's pcalib.txt (the first non-empty line; further lines are ignored as in DSO).
// Throws omnidso::Error naming the file, its line and the offending value index for a
// wrong count, a non-numeric value or a decreasing value.
InverseResponse readPcalib(const std::string& path);
void writePcalib(const std::string& path, const InverseResponse& inverse_response);

// Reads a vignette image (8- or 16-bit) and divides it by its maximum, so V ∈ [0, 1].
// Throws if the image is all zero.
ImageF readVignette(const std::string& path);
// Writes V as a 16-bit PNG (or other 16-bit format), scaled so that max V → 65535.
void writeVignette(const std::string& path, const ImageF& vignette);

class PhotometricCalibration {
 public:
  // Identity response, no vignette.
  PhotometricCalibration();
  // An empty vignette means V ≡ 1; vignette_source names it in error messages.
  PhotometricCalibration(const InverseResponse& inverse_response, ImageF vignette,
                         std::string vignette_source = "vignette");

  // Either path may be empty (absent file → identity default).
  static PhotometricCalibration fromFiles(const std::string& pcalib_path,
                                          const std::string& vignette_path);

  const InverseResponse& inverseResponseTable() const { return inverse_response_; }
  const ImageF& vignette() const { return vignette_; }
  bool hasVignette() const { return !vignette_.empty(); }

  // G⁻¹ at a pixel value in [0, 255] (clamped), linear between table entries.
  double inverseResponse(double pixel_value) const;
  // G, the inverse of the piecewise-linear G⁻¹: a pixel value in [0, 255]. Irradiance
  // below G⁻¹(0) or above G⁻¹(255) saturates; on a flat stretch of G⁻¹ the lowest pixel
  // value is returned. For the renderer: I_raw = response(t · V · B).
  double response(double irradiance) const;

  // G′(E) = dI/dE for corrected intensities E = 0, 1, …, 255 (the units of a G⁻¹ that spans
  // 0..255, as DSO's pcalib.txt does): the reciprocal slope of the piecewise-linear G⁻¹ on the
  // segment that holds G(E) (on a flat stretch, the nearest rising segment's). It maps a
  // gradient of the corrected image back into the camera's encoding, ∇I ≈ G′(E) ∇E
  // (camera_encoding.hpp: pixel selection and residual weights). All ones for the identity
  // response.
  std::array<float, kResponseSize> responseSlopeTable() const;

  // Throws omnidso::Error naming the vignette if it exists and its size differs.
  void checkImageSize(int width, int height) const;

  // G⁻¹(I_raw)/V per pixel, i.e. t·B in the units of G⁻¹ (0..255 for the identity). 8-bit
  // raw values index the table directly; 16-bit values are mapped by value/257 (so 65535
  // → 255) with linear interpolation between table entries. Pixels where V = 0 (outside a
  // fisheye's image circle) are set to 0. Throws if the vignette size differs from the
  // image size.
  ImageF correct(const RawImage& raw) const;

 private:
  void tabulateValues();

  InverseResponse inverse_response_;
  // inverseResponse(k) for k = 0..255, evaluated once: correct() reads 8-bit pixels from it.
  InverseResponse at_values_;
  ImageF vignette_;
  std::string vignette_source_;
};

// B = energy / t: the irradiance from a corrected image and its exposure time (any unit,
// used consistently). Throws if exposure is not positive.
ImageF toIrradiance(const ImageF& energy, double exposure);

}  // namespace omnidso
