#include "omnidso/core/photometric_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <utility>
#include <vector>

#include "omnidso/core/error.hpp"

namespace omnidso {
namespace {

std::string numberText(double x) {
  std::ostringstream out;
  out << std::setprecision(17) << x;
  return out.str();
}

// G⁻¹ must be non-decreasing (a response is monotonic) and not constant, else G does not
// exist. `where` is the prefix of the message, e.g. "pcalib.txt:1".
void checkInverseResponse(const InverseResponse& table, const std::string& where) {
  for (int k = 1; k < kResponseSize; ++k) {
    if (table[k] < table[k - 1]) {
      throw Error(where + ": value at index " + std::to_string(k) + " (" +
                  numberText(table[k]) + ") is smaller than the value before it (" +
                  numberText(table[k - 1]) + "); the inverse response must be non-decreasing");
    }
  }
  if (!(table[kResponseSize - 1] > table[0])) {
    throw Error(where + ": the inverse response is constant; it must increase");
  }
}

// A whole token as a finite double, or false.
bool parseNumber(const std::string& token, double* value) {
  const char* begin = token.c_str();
  char* end = nullptr;
  *value = std::strtod(begin, &end);
  return end != begin && *end == '\0' && std::isfinite(*value);
}

// energy = G⁻¹(raw)/V per pixel (0 where V = 0), in double as always, then to float. One loop
// per kind of lookup, so that none branches per pixel on the bit depth.
template <typename InverseResponseOf>
void correctPixels(const std::uint16_t* raw, std::size_t n, const float* vignette, float* out,
                   const InverseResponseOf& inverse) {
  if (!vignette) {
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(inverse(raw[i]));
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double v = vignette[i];
    out[i] = static_cast<float>(v > 0.0 ? inverse(raw[i]) / v : 0.0);
  }
}

}  // namespace

InverseResponse identityInverseResponse() {
  InverseResponse table;
  for (int k = 0; k < kResponseSize; ++k) table[k] = k;
  return table;
}

InverseResponse readPcalib(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open photometric calibration (pcalib) file");
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") != std::string::npos) break;
  }
  if (line.find_first_not_of(" \t\r") == std::string::npos) {
    throw fileError(path, "empty file; expected one line of " +
                              std::to_string(kResponseSize) + " inverse-response values");
  }
  std::vector<double> values;
  std::istringstream tokens(line);
  std::string token;
  while (tokens >> token) {
    double value = 0.0;
    if (!parseNumber(token, &value)) {
      throw fileError(path, line_number,
                      "value at index " + std::to_string(values.size()) + " ('" + token +
                          "') is not a finite number");
    }
    values.push_back(value);
  }
  if (static_cast<int>(values.size()) != kResponseSize) {
    throw fileError(path, line_number,
                    "expected " + std::to_string(kResponseSize) +
                        " inverse-response values, found " + std::to_string(values.size()));
  }
  InverseResponse table;
  std::copy(values.begin(), values.end(), table.begin());
  checkInverseResponse(table, path + ":" + std::to_string(line_number));
  return table;
}

void writePcalib(const std::string& path, const InverseResponse& inverse_response) {
  std::ofstream out(path);
  if (!out) throw fileError(path, "cannot open for writing");
  out << std::setprecision(17);
  for (int k = 0; k < kResponseSize; ++k) out << (k ? " " : "") << inverse_response[k];
  out << '\n';
  if (!out) throw fileError(path, "write failed");
}

ImageF readVignette(const std::string& path) {
  const RawImage raw = readRawImage(path);
  const std::uint16_t* begin = raw.pixels.data();
  const std::uint16_t maximum = *std::max_element(begin, begin + raw.pixels.size());
  if (maximum == 0) throw fileError(path, "vignette image is all zero");
  ImageF vignette(raw.pixels.width(), raw.pixels.height());
  const float scale = 1.0f / static_cast<float>(maximum);
  for (std::size_t i = 0; i < raw.pixels.size(); ++i) vignette.data()[i] = begin[i] * scale;
  return vignette;
}

void writeVignette(const std::string& path, const ImageF& vignette) {
  if (vignette.empty()) throw fileError(path, "cannot write an empty vignette");
  const float* begin = vignette.data();
  const float* end = begin + vignette.size();
  const float maximum = *std::max_element(begin, end);
  const bool valid = std::all_of(begin, end, [](float x) { return std::isfinite(x) && x >= 0; });
  if (!valid || !(maximum > 0.0f)) {
    throw fileError(path, "vignette values must be finite, non-negative and not all zero");
  }
  ImageU16 pixels(vignette.width(), vignette.height());
  const double scale = 65535.0 / maximum;
  for (std::size_t i = 0; i < vignette.size(); ++i) {
    pixels.data()[i] = static_cast<std::uint16_t>(std::lround(begin[i] * scale));
  }
  writeImage(path, pixels);
}

PhotometricCalibration::PhotometricCalibration()
    : inverse_response_(identityInverseResponse()), vignette_source_("vignette") {
  tabulateValues();
}

PhotometricCalibration::PhotometricCalibration(const InverseResponse& inverse_response,
                                               ImageF vignette, std::string vignette_source)
    : inverse_response_(inverse_response),
      vignette_(std::move(vignette)),
      vignette_source_(std::move(vignette_source)) {
  checkInverseResponse(inverse_response_, "PhotometricCalibration");
  tabulateValues();
}

void PhotometricCalibration::tabulateValues() {
  for (int k = 0; k < kResponseSize; ++k) at_values_[k] = inverseResponse(k);
}

PhotometricCalibration PhotometricCalibration::fromFiles(const std::string& pcalib_path,
                                                         const std::string& vignette_path) {
  const InverseResponse table =
      pcalib_path.empty() ? identityInverseResponse() : readPcalib(pcalib_path);
  ImageF vignette = vignette_path.empty() ? ImageF() : readVignette(vignette_path);
  return PhotometricCalibration(table, std::move(vignette), vignette_path);
}

double PhotometricCalibration::inverseResponse(double pixel_value) const {
  const double x = std::clamp(pixel_value, 0.0, kResponseSize - 1.0);
  const int k = std::min(static_cast<int>(x), kResponseSize - 2);
  const double f = x - k;
  return (1.0 - f) * inverse_response_[k] + f * inverse_response_[k + 1];
}

double PhotometricCalibration::response(double irradiance) const {
  const auto& g = inverse_response_;
  if (irradiance <= g.front()) return 0.0;
  if (irradiance >= g.back()) return kResponseSize - 1.0;
  // First k with G⁻¹(k) ≥ irradiance; G⁻¹(k−1) < irradiance by the checks above.
  const int k = static_cast<int>(std::lower_bound(g.begin(), g.end(), irradiance) - g.begin());
  if (g[k] == irradiance) return k;
  return (k - 1) + (irradiance - g[k - 1]) / (g[k] - g[k - 1]);
}

std::array<float, kResponseSize> PhotometricCalibration::responseSlopeTable() const {
  const auto& g = inverse_response_;
  auto rise = [&](int k) { return g[k + 1] - g[k]; };  // G⁻¹ on segment [k, k + 1]
  std::array<float, kResponseSize> slope{};
  for (int e = 0; e < kResponseSize; ++e) {
    int k = std::clamp(static_cast<int>(response(e)), 0, kResponseSize - 2);
    // A flat stretch (G⁻¹ non-decreasing): the nearest rising segment, upward first.
    for (int step = 1; rise(k) <= 0.0 && step < kResponseSize; ++step) {
      if (k + step <= kResponseSize - 2 && rise(k + step) > 0.0) k += step;
      else if (k - step >= 0 && rise(k - step) > 0.0) k -= step;
    }
    slope[e] = static_cast<float>(1.0 / rise(k));
  }
  return slope;
}

void PhotometricCalibration::checkImageSize(int width, int height) const {
  if (!hasVignette()) return;
  if (vignette_.width() != width || vignette_.height() != height) {
    throw fileError(vignette_source_,
                    "vignette is " + std::to_string(vignette_.width()) + "x" +
                        std::to_string(vignette_.height()) + " but the image is " +
                        std::to_string(width) + "x" + std::to_string(height));
  }
}

ImageF PhotometricCalibration::correct(const RawImage& raw) const {
  if (raw.bit_depth != 8 && raw.bit_depth != 16) {
    throw Error("PhotometricCalibration::correct: unsupported bit depth " +
                std::to_string(raw.bit_depth) + " (8 or 16)");
  }
  checkImageSize(raw.pixels.width(), raw.pixels.height());
  // G⁻¹ is a function of the raw value alone, so it is read from a table per raw value whose
  // entries are inverseResponse() itself — bit-identical to evaluating it per pixel. 8-bit
  // values index the 256 entries made at construction (a value above 255, which no decoder
  // gives, clamps to 255 as inverseResponse does). 16-bit values span 0..65535 = 257 · 255,
  // so value/257 lands on the 8-bit scale; a table of their 65536 entries is made per image
  // and only pays off on images of more pixels than that.
  const std::size_t n = raw.pixels.size();
  const std::uint16_t* in = raw.pixels.data();
  const bool eight_bit = raw.bit_depth == 8;
  const double to_table = eight_bit ? 1.0 : 1.0 / 257.0;
  std::vector<double> table16;
  if (!eight_bit && n > 65536) {
    table16.resize(65536);
    for (std::size_t k = 0; k < table16.size(); ++k) table16[k] = inverseResponse(k * to_table);
  }
  ImageF energy(raw.pixels.width(), raw.pixels.height());
  const float* vignette = hasVignette() ? vignette_.data() : nullptr;
  if (eight_bit) {
    const double* table = at_values_.data();
    correctPixels(in, n, vignette, energy.data(), [table](std::uint16_t value) {
      return table[std::min<std::uint16_t>(value, kResponseSize - 1)];
    });
  } else if (!table16.empty()) {
    const double* table = table16.data();
    correctPixels(in, n, vignette, energy.data(),
                  [table](std::uint16_t value) { return table[value]; });
  } else {
    correctPixels(in, n, vignette, energy.data(),
                  [&](std::uint16_t value) { return inverseResponse(value * to_table); });
  }
  return energy;
}

ImageF toIrradiance(const ImageF& energy, double exposure) {
  if (!(exposure > 0.0) || !std::isfinite(exposure)) {
    throw Error("toIrradiance: exposure time must be positive, got " + numberText(exposure));
  }
  ImageF irradiance(energy.width(), energy.height());
  const float inverse = static_cast<float>(1.0 / exposure);
  for (std::size_t i = 0; i < energy.size(); ++i) irradiance.data()[i] = energy.data()[i] * inverse;
  return irradiance;
}

}  // namespace omnidso
