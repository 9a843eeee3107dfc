#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <omnidso/cli/odometry_settings.hpp>
#include <omnidso/core/error.hpp>
#include <sstream>
#include <variant>

namespace omnidso::cli {
namespace {

// std::vector<int>: a list of integers (tracker.max_iterations, one entry per pyramid level),
// written "6,8,10" or "[6,8,10]" (as summary.json prints it) or as a YAML sequence.
using SettingTarget = std::variant<int*, double*, bool*, std::uint64_t*, std::vector<int>*>;

struct Setting {
  const char* name;
  SettingTarget target;
};

// The table: one line per option. Structural options (thread counts, differentiation mode,
// N_f, the number of points) have their own command-line flags and are not repeated here.
std::vector<Setting> settingsOf(OdometryOptions& o) {
  return {
      {"pyramid_levels", &o.pyramid_levels},
      {"content_margin_px", &o.content_margin_px},
      {"reject_targets_outside_content", &o.reject_targets_outside_content},
      {"noise_in_encoding", &o.noise_in_encoding},
      {"pattern_spread", &o.pattern_spread},
      {"max_activation_interval_px", &o.max_activation_interval_px},
      {"min_activation_quality", &o.min_activation_quality},
      {"activation_density.adaptive", &o.activation_density.adaptive},
      {"activation_density.shrink_below", &o.activation_density.shrink_below},
      {"activation_density.step", &o.activation_density.step},
      {"activation_density.min_scale", &o.activation_density.min_scale},
      {"activation.enabled", &o.activation.enabled},
      {"activation.iterations", &o.activation.iterations},
      {"activation.min_hessian", &o.activation.min_hessian},
      {"activation.min_good_residuals", &o.activation.min_good_residuals},
      {"activation.central_difference_gradients", &o.activation.central_difference_gradients},
      {"max_keyframe_interval_frames", &o.max_keyframe_interval_frames},
      {"window.intrinsics_prior_weight", &o.window.intrinsics_prior_weight},
      {"window.max_iterations", &o.window.max_iterations},
      {"window.function_tolerance", &o.window.function_tolerance},
      {"window.max_solver_time_s", &o.window.max_solver_time_s},
      {"window.dense_schur_max_size", &o.window.dense_schur_max_size},
      {"window.max_points", &o.window.max_points},
      {"window.jacobi_scaling", &o.window.jacobi_scaling},
      {"window.reuse_evaluations", &o.window.reuse_evaluations},
      {"window.keep_scale_anchor", &o.window.keep_scale_anchor},
      {"window.first_estimate_jacobians", &o.window.first_estimate_jacobians},
      {"window.native_solver", &o.window.native_solver},
      {"window.outlier_energy_per_pixel", &o.window.outlier_energy_per_pixel},
      {"window.outlier_threshold.adaptive", &o.window.outlier_threshold.adaptive},
      {"window.outlier_threshold.quantile", &o.window.outlier_threshold.quantile},
      {"window.outlier_threshold.quantile_factor", &o.window.outlier_threshold.quantile_factor},
      {"window.outlier_threshold.fixed_weight", &o.window.outlier_threshold.fixed_weight},
      {"window.outlier_threshold.fixed_energy_per_pixel",
       &o.window.outlier_threshold.fixed_energy_per_pixel},
      {"window.min_residuals_per_point", &o.window.min_residuals_per_point},
      {"window.min_residuals_to_marginalize", &o.window.min_residuals_to_marginalize},
      {"window.huber_threshold", &o.window.huber_threshold},
      {"window.affine_prior_weight_a", &o.window.affine_prior_weight_a},
      {"window.affine_prior_weight_b", &o.window.affine_prior_weight_b},
      {"window.gradient_weight_c", &o.window.gradient_weight_c},
      {"window.central_difference_gradients", &o.window.central_difference_gradients},
      {"tracker.max_iterations", &o.tracker.max_iterations},
      {"tracker.huber_threshold", &o.tracker.huber_threshold},
      {"tracker.central_difference_gradients", &o.tracker.central_difference_gradients},
      {"tracker.dilate_reference", &o.tracker.dilate_reference},
      {"tracker.dilated_retry", &o.tracker.dilated_retry},
      {"tracker.retry_max_iterations", &o.tracker.retry_max_iterations},
      {"tracker.function_tolerance", &o.tracker.function_tolerance},
      {"tracker.early_reject_factor", &o.tracker.early_reject_factor},
      {"tracker.good_enough_factor", &o.tracker.good_enough_factor},
      {"tracker.min_valid_fraction", &o.tracker.min_valid_fraction},
      {"tracker.rotation_hypothesis_rad", &o.tracker.rotation_hypothesis_rad},
      {"tracker.reversed_step_hypothesis", &o.tracker.reversed_step_hypothesis},
      {"tracker.wide_rotation_hypothesis_rad", &o.tracker.wide_rotation_hypothesis_rad},
      {"tracker.affine_prior_weight_a", &o.tracker.affine_prior_weight_a},
      {"tracker.affine_prior_weight_b", &o.tracker.affine_prior_weight_b},
      {"tracker.affine_in_reference_gauge", &o.tracker.affine_in_reference_gauge},
      {"tracker.native_solver", &o.tracker.native_solver},
      {"tracker.finest_level_second_start", &o.tracker.finest_level_second_start},
      {"tracker.second_start_gain", &o.tracker.second_start_gain},
      {"tracker.second_start_min_shift_px", &o.tracker.second_start_min_shift_px},
      {"reference_depths.neighbours", &o.reference_depths.neighbours},
      {"reference_depths.max_log_deviation", &o.reference_depths.max_log_deviation},
      {"epipolar.max_search_px", &o.epipolar.max_search_px},
      {"epipolar.converged_px", &o.epipolar.converged_px},
      {"epipolar.min_quality", &o.epipolar.min_quality},
      {"epipolar.second_best_radius_px", &o.epipolar.second_best_radius_px},
      {"epipolar.outlier_energy_per_pixel", &o.epipolar.outlier_energy_per_pixel},
      {"epipolar.huber", &o.epipolar.huber},
      {"epipolar.gn_iterations", &o.epipolar.gn_iterations},
      {"epipolar.match_sigma_px", &o.epipolar.match_sigma_px},
      {"epipolar.curve_offset_px", &o.epipolar.curve_offset_px},
      {"keyframe_decision.weight_flow_t", &o.keyframe_decision.weight_flow_t},
      {"keyframe_decision.weight_flow_rt", &o.keyframe_decision.weight_flow_rt},
      {"keyframe_decision.weight_affine", &o.keyframe_decision.weight_affine},
      {"keyframe_decision.global_weight", &o.keyframe_decision.global_weight},
      {"keyframe_decision.rmse_growth_factor", &o.keyframe_decision.rmse_growth_factor},
      {"marginalization.min_visible_fraction", &o.marginalization.min_visible_fraction},
      {"marginalization.distance_epsilon", &o.marginalization.distance_epsilon},
      {"marginalization.num_protected_newest", &o.marginalization.num_protected_newest},
      {"initializer.max_iterations_per_level", &o.initializer.max_iterations_per_level},
      {"initializer.regularizer_weight", &o.initializer.regularizer_weight},
      {"initializer.pre_snap_regularizer_weight", &o.initializer.pre_snap_regularizer_weight},
      {"initializer.pre_snap_translation_penalty", &o.initializer.pre_snap_translation_penalty},
      {"initializer.affine_prior_weight_a", &o.initializer.affine_prior_weight_a},
      {"initializer.affine_prior_weight_b", &o.initializer.affine_prior_weight_b},
      {"initializer.rotation_search_half_width", &o.initializer.rotation_search_half_width},
      {"initializer.rotation_search_step_px", &o.initializer.rotation_search_step_px},
      {"initializer.level_cell_px", &o.initializer.level_cell_px},
      {"initializer.frames_after_snap", &o.initializer.frames_after_snap},
      {"initializer.snap_translation_starts", &o.initializer.snap_translation_starts},
      {"initializer.snap_translation_start_gain", &o.initializer.snap_translation_start_gain},
      {"initializer.min_parallax_px", &o.initializer.min_parallax_px},
      {"initializer.min_parallax_deg", &o.initializer.min_parallax_deg},
      {"initializer.snap_parallax_deg", &o.initializer.snap_parallax_deg},
      {"race.rival_snap_parallax_deg", &o.race.rival_snap_parallax_deg},
      {"race.keyframes", &o.race.keyframes},
      {"race.switch_gain", &o.race.switch_gain},
      {"race.same_start_deg", &o.race.same_start_deg},
      {"race.max_frames", &o.race.max_frames},
      {"race.rival_snap_translation_start_gain", &o.race.rival_snap_translation_start_gain},
      {"initializer.max_rmse", &o.initializer.max_rmse},
      {"initializer.max_rmse_growth", &o.initializer.max_rmse_growth},
      {"initializer.min_points", &o.initializer.min_points},
      {"initializer.max_frames", &o.initializer.max_frames},
      {"initializer.huber_threshold", &o.initializer.huber_threshold},
      {"initializer.central_difference_gradients", &o.initializer.central_difference_gradients},
      {"initializer.native_solver", &o.initializer.native_solver},
      {"selection.threshold_block_size", &o.initializer.selection.threshold_block_size},
      {"selection.gradient_threshold_offset", &o.initializer.selection.gradient_threshold_offset},
      {"selection.coarser_level_factor", &o.initializer.selection.coarser_level_factor},
      {"selection.border", &o.initializer.selection.border},
      {"selection.camera_encoding", &o.initializer.selection.camera_encoding},
  };
}

// The whole text must parse as T (no trailing characters); *out is untouched otherwise.
template <typename T>
bool parseWhole(const std::string& text, T* out) {
  std::istringstream in(text);
  T value{};
  in >> value;
  if (in.fail() || !(in >> std::ws).eof()) return false;
  *out = value;
  return true;
}

// A list of integers separated by commas, optionally in brackets; not empty, nothing else.
bool parseIntList(std::string text, std::vector<int>* out) {
  const size_t first = text.find_first_not_of(" \t");
  const size_t last = text.find_last_not_of(" \t");
  if (first == std::string::npos) return false;
  text = text.substr(first, last - first + 1);
  if (text.front() == '[' || text.back() == ']') {
    if (text.size() < 2 || text.front() != '[' || text.back() != ']') return false;
    text = text.substr(1, text.size() - 2);
  }
  std::vector<int> values;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    int v = 0;
    if (!parseWhole(item, &v)) return false;
    values.push_back(v);
  }
  if (values.empty() || text.back() == ',') return false;  // getline drops a trailing empty item
  *out = std::move(values);
  return true;
}

void assign(const Setting& s, const std::string& value) {
  const bool ok = std::visit(
      [&](auto* target) {
        using T = std::remove_pointer_t<decltype(target)>;
        if constexpr (std::is_same_v<T, std::vector<int>>) {
          return parseIntList(value, target);
        } else if constexpr (std::is_same_v<T, bool>) {
          if (value == "true" || value == "1") return *target = true, true;
          if (value == "false" || value == "0") return *target = false, true;
          return false;
        } else if constexpr (std::is_unsigned_v<T>) {
          return value.find('-') == std::string::npos && parseWhole(value, target);
        } else {
          return parseWhole(value, target);
        }
      },
      s.target);
  if (!ok) throw Error(std::string("setting ") + s.name + ": cannot parse '" + value + "'");
}

// No setting of the table is meaningfully negative (counts, weights, tolerances, sizes in
// pixels) except those whose "automatic" value is below the range: pyramid_levels 0 (the
// depth from the image size), content_margin_px −1 (from the pattern) and
// initializer.snap_parallax_deg −1 (min_parallax_deg's). A negative count would size a
// vector or a loop wrongly instead of being refused.
double lowestValue(const std::string& name) {
  if (name == "content_margin_px" || name == "initializer.snap_parallax_deg") return -1.0;
  return 0.0;
}

void checkRange(const Setting& s) {
  const double lowest = lowestValue(s.name);
  const bool ok = std::visit(
      [&](auto* target) {
        using T = std::remove_pointer_t<decltype(target)>;
        if constexpr (std::is_same_v<T, std::vector<int>>) {
          return std::all_of(target->begin(), target->end(), [](int v) { return v >= 1; });
        } else if constexpr (std::is_same_v<T, bool> || std::is_unsigned_v<T>) {
          return true;
        } else {
          return static_cast<double>(*target) >= lowest;
        }
      },
      s.target);
  if (!ok) {
    if (std::holds_alternative<std::vector<int>*>(s.target))
      throw Error(std::string("setting ") + s.name + ": every entry must be at least 1");
    throw Error(std::string("setting ") + s.name +
                (lowest < 0 ? ": must be at least -1 (-1: automatic)"
                            : ": must not be negative" +
                                  std::string(std::string(s.name) == "pyramid_levels"
                                                  ? " (0: automatic)"
                                                  : "")));
  }
}

void applyYamlNode(OdometryOptions& options, const YAML::Node& node, const std::string& prefix,
                   const std::string& path) {
  if (!node.IsMap()) throw Error(path + ": expected a map of settings" +
                                 (prefix.empty() ? "" : " under '" + prefix + "'"));
  for (const auto& entry : node) {
    const int line = entry.first.Mark().line + 1;
    if (!entry.first.IsScalar()) {
      throw fileError(path, line, "a setting's name must be a plain word, not a list or map");
    }
    const std::string name = prefix + entry.first.Scalar();
    if (entry.second.IsMap()) {
      applyYamlNode(options, entry.second, name + ".", path);
    } else if (entry.second.IsScalar()) {
      try {
        applyOdometrySetting(options, name, entry.second.Scalar());
      } catch (const Error& e) {
        throw fileError(path, line, e.what());
      }
    } else if (entry.second.IsSequence()) {
      // A list setting (tracker.max_iterations: [6, 8, 10]); as "6,8,10" to the one parser.
      std::string joined;
      for (const auto& item : entry.second) {
        if (!item.IsScalar())
          throw fileError(path, line, "setting " + name + ": a list must hold plain values");
        joined += (joined.empty() ? "" : ",") + item.Scalar();
      }
      try {
        applyOdometrySetting(options, name, "[" + joined + "]");
      } catch (const Error& e) {
        throw fileError(path, line, e.what());
      }
    } else {
      throw fileError(path, line, "setting " + name + " must be a single value or a list");
    }
  }
}

}  // namespace

void applyOdometrySetting(OdometryOptions& options, const std::string& name, const std::string& value) {
  for (const Setting& s : settingsOf(options))
    if (name == s.name) {
      assign(s, value);
      return checkRange(s);
    }
  // One line (an error is one message), the valid names in table order.
  std::string known;
  for (const std::string& n : odometrySettingNames()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown setting '" + name + "'; the settings are: " + known);
}

void applyOdometrySettingAssignment(OdometryOptions& options, const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw Error("--set: expected NAME=VALUE, got '" + assignment + "'");
  applyOdometrySetting(options, assignment.substr(0, eq), assignment.substr(eq + 1));
}

void applyOdometryConfigFile(OdometryOptions& options, const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    if (e.mark.is_null()) throw fileError(path, e.msg);
    throw fileError(path, e.mark.line + 1, "malformed YAML: " + e.msg);
  }
  if (root.IsNull()) return;  // an empty file changes nothing
  applyYamlNode(options, root, "", path);
}

nlohmann::json odometrySettingsJson(const OdometryOptions& options) {
  OdometryOptions copy = options;
  nlohmann::json out = nlohmann::json::object();
  for (const Setting& s : settingsOf(copy))
    std::visit([&](auto* target) { out[s.name] = *target; }, s.target);
  return out;
}

std::vector<std::string> odometrySettingNames() {
  OdometryOptions o;
  std::vector<std::string> names;
  for (const Setting& s : settingsOf(o)) names.push_back(s.name);
  return names;
}

}  // namespace omnidso::cli
