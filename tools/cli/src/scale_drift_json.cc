#include <omnidso/cli/scale_drift_json.hpp>

namespace omnidso::cli {

nlohmann::json scaleDriftJson(const ScaleDrift& drift, bool with_samples) {
  nlohmann::json j = {{"window_m", drift.window_m},
                      {"percent_over_sequence", drift.percent_over_sequence},
                      {"percent_per_10m", drift.percent_per_10m},
                      {"percent_per_minute", drift.percent_per_minute},
                      {"min_ratio", drift.min_ratio},
                      {"max_ratio", drift.max_ratio},
                      {"num_samples", drift.samples.size()}};
  if (with_samples) {
    nlohmann::json samples = nlohmann::json::array();
    for (const LocalScale& s : drift.samples) samples.push_back({s.distance_m, s.time_s, s.ratio});
    j["samples"] = std::move(samples);
  }
  return j;
}

}  // namespace omnidso::cli
