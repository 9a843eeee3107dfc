#include <fmt/core.h>

#include <algorithm>
#include <omnidso/cli/ablation_tables.hpp>
#include <omnidso/core/metrics.hpp>

namespace omnidso::cli {
namespace {

// A median with the number of runs it used out of the runs there were.
struct Measured {
  std::optional<double> value;
  size_t used = 0;
  size_t total = 0;
  size_t missing = 0;  // not finished (yet): neither used nor failed
};

using CellField = std::optional<double> CellSummary::*;

std::string number(double v, int precision, bool sign = false) {
  return sign ? fmt::format("{:+.{}f}", v, precision) : fmt::format("{:.{}f}", v, precision);
}

// "failed k/n", "missing m/n", or both, for the runs a value leaves out.
std::string leftOut(const Measured& m, const std::string& prefix = "") {
  std::vector<std::string> parts;
  if (const size_t failed = m.total - m.used - m.missing)
    parts.push_back(fmt::format("{}failed {}/{}", prefix, failed, m.total));
  if (m.missing) parts.push_back(fmt::format("{}missing {}/{}", prefix, m.missing, m.total));
  return parts.empty() ? "" : parts.size() == 1 ? parts[0] : parts[0] + ", " + parts[1];
}

std::string display(const Measured& m, int precision) {
  if (m.total == 0) return "—";
  if (!m.value) return m.used == 0 ? leftOut(m) : "n/a";
  const std::string v = number(*m.value, precision);
  return m.used < m.total ? fmt::format("{} ({})", v, leftOut(m)) : v;
}

std::string plain(const std::optional<double>& v) { return v ? fmt::format("{:.9g}", *v) : ""; }

std::vector<std::string> csvFields(const Measured& m) {
  return {plain(m.value), std::to_string(m.used), std::to_string(m.total)};
}

template <typename T>
void appendUnique(std::vector<T>& list, const T& item) {
  if (std::find(list.begin(), list.end(), item) == list.end()) list.push_back(item);
}

struct Axes {
  std::vector<std::string> datasets, camera_models;
  std::vector<int> keyframes;
  explicit Axes(const std::vector<CellSummary>& cells) {
    for (const CellSummary& c : cells) {
      appendUnique(datasets, c.cell.dataset_name);
      appendUnique(camera_models, c.cell.camera_model);
      appendUnique(keyframes, c.cell.keyframes);
    }
  }
};

const CellSummary* findCell(const std::vector<CellSummary>& cells, const std::string& dataset,
                            const std::string& model, int keyframes) {
  for (const CellSummary& c : cells)
    if (c.cell.dataset_name == dataset && c.cell.camera_model == model &&
        c.cell.keyframes == keyframes)
      return &c;
  return nullptr;
}

Measured measured(const CellSummary* c, CellField field) {
  if (!c) return {};
  return {c->*field, c->succeeded, c->runs.size(), c->missing};
}

std::string kf(int n) { return "Kf" + std::to_string(n); }

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

AblationTable tableRmse(const Axes& axes, const std::vector<CellSummary>& cells) {
  const int reference = axes.keyframes.front();
  AblationTable t{"table1_rmse.csv",
                  "Table I: keyframe ATE RMSE per sequence and method",
                  fmt::format("Keyframe ATE RMSE after Sim(3) alignment, in metres and in % of "
                              "the ground-truth path, and the scale drift (change of the local "
                              "scale over the run, %; `omnidso eval` explains it), at N_f = {}.",
                              reference),
                  {},
                  {}};
  t.markdown.header = {"dataset"};
  t.csv.header = {"dataset"};
  for (const std::string& model : axes.camera_models) {
    t.markdown.header.insert(t.markdown.header.end(),
                             {model + " RMSE [m]", model + " [% of path]",
                              model + " scale drift [%]"});
    t.csv.header.insert(t.csv.header.end(),
                        {model + " rmse_m", model + " runs_used", model + " runs",
                         model + " rmse_percent_of_path", model + " scale_drift_percent"});
  }
  for (const std::string& dataset : axes.datasets) {
    std::vector<std::string> md{dataset}, csv{dataset};
    for (const std::string& model : axes.camera_models) {
      const CellSummary* c = findCell(cells, dataset, model, reference);
      const Measured rmse = measured(c, &CellSummary::rmse_m);
      const Measured percent = measured(c, &CellSummary::rmse_percent_of_path);
      const Measured drift = measured(c, &CellSummary::scale_drift_percent);
      md.push_back(display(rmse, 4));
      md.push_back(percent.value ? number(*percent.value, 2) : display(percent, 2));
      md.push_back(drift.value ? number(*drift.value, 2) : display(drift, 2));
      for (const std::string& f : csvFields(rmse)) csv.push_back(f);
      csv.push_back(plain(percent.value));
      csv.push_back(plain(drift.value));
    }
    t.markdown.rows.push_back(md);
    t.csv.rows.push_back(csv);
  }
  return t;
}

AblationTable tableLength(const std::vector<DatasetFacts>& datasets) {
  AblationTable t{"table2_length.csv",
                  "Table II: trajectory length",
                  "Ground-truth path length over the frames the runs use.",
                  {},
                  {}};
  t.markdown.header = {"dataset", "frames", "duration [s]", "length [m]"};
  t.csv.header = {"dataset", "frames", "duration_s", "gt_length_m"};
  for (const DatasetFacts& d : datasets) {
    t.markdown.rows.push_back(
        {d.name, std::to_string(d.frames), number(d.duration_s, 1), number(d.gt_length_m, 2)});
    t.csv.rows.push_back(
        {d.name, std::to_string(d.frames), plain(d.duration_s), plain(d.gt_length_m)});
  }
  return t;
}

AblationTable tableRmsePerKeyframes(const Axes& axes, const std::vector<CellSummary>& cells) {
  AblationTable t{"table3_rmse_per_keyframes.csv",
                  "Table III: RMSE per number of keyframes N_f",
                  "Keyframe ATE RMSE in metres per active-keyframe count N_f.",
                  {},
                  {}};
  t.markdown.header = {"dataset", "camera model"};
  t.markdown.label_columns = 2;
  t.csv.header = {"dataset", "camera_model"};
  for (int n : axes.keyframes) {
    t.markdown.header.push_back(kf(n) + " [m]");
    t.csv.header.insert(t.csv.header.end(),
                        {kf(n) + " rmse_m", kf(n) + " runs_used", kf(n) + " runs"});
  }
  for (const std::string& dataset : axes.datasets)
    for (const std::string& model : axes.camera_models) {
      std::vector<std::string> md{dataset, model}, csv{dataset, model};
      for (int n : axes.keyframes) {
        const Measured m = measured(findCell(cells, dataset, model, n), &CellSummary::rmse_m);
        md.push_back(display(m, 4));
        for (const std::string& f : csvFields(m)) csv.push_back(f);
      }
      t.markdown.rows.push_back(md);
      t.csv.rows.push_back(csv);
    }
  return t;
}

std::string differenceText(int n, int reference, const Measured& a, const Measured& b) {
  if (!a.value || !b.value) {
    std::vector<std::string> why;
    if (!a.value) why.push_back(kf(n) + " " + display(a, 4));
    if (!b.value) why.push_back(kf(reference) + " " + display(b, 4));
    return "n/a (" + joined(why) + ")";
  }
  std::string text = number(*a.value - *b.value, 4, true);
  std::vector<std::string> partial;
  if (a.used < a.total) partial.push_back(leftOut(a, kf(n) + " "));
  if (b.used < b.total) partial.push_back(leftOut(b, kf(reference) + " "));
  if (!partial.empty()) text += " (" + joined(partial) + ")";
  return text;
}

AblationTable tableDifferences(const Axes& axes, const std::vector<CellSummary>& cells) {
  const int reference = axes.keyframes.front();
  AblationTable t{"table4_rmse_differences.csv",
                  "Table IV: RMSE differences to the reference N_f",
                  fmt::format("Median RMSE with N_f keyframes minus that with the reference N_f = "
                              "{}, in metres (negative: more accurate).",
                              reference),
                  {},
                  {}};
  t.markdown.header = {"dataset", "camera model"};
  t.markdown.label_columns = 2;
  t.csv.header = {"dataset", "camera_model"};
  for (size_t i = 1; i < axes.keyframes.size(); ++i) {
    t.markdown.header.push_back(kf(axes.keyframes[i]) + " − " + kf(reference) + " [m]");
    t.csv.header.push_back(kf(axes.keyframes[i]) + "-" + kf(reference) + " m");
  }
  for (const std::string& dataset : axes.datasets)
    for (const std::string& model : axes.camera_models) {
      std::vector<std::string> md{dataset, model}, csv{dataset, model};
      const Measured b = measured(findCell(cells, dataset, model, reference), &CellSummary::rmse_m);
      for (size_t i = 1; i < axes.keyframes.size(); ++i) {
        const int n = axes.keyframes[i];
        const Measured a = measured(findCell(cells, dataset, model, n), &CellSummary::rmse_m);
        md.push_back(differenceText(n, reference, a, b));
        csv.push_back(a.value && b.value ? plain(*a.value - *b.value) : "");
      }
      t.markdown.rows.push_back(md);
      t.csv.rows.push_back(csv);
    }
  return t;
}

AblationTable tableTiming(const Axes& axes, const std::vector<CellSummary>& cells) {
  AblationTable t{"table5_timing.csv",
                  "Table V: tracking and mapping time per N_f",
                  "Median over the successful runs of all datasets of each run's mean tracking "
                  "time per frame and mean mapping time per keyframe, in ms. Runs that share "
                  "the machine (--jobs > 1) slow each other down.",
                  {},
                  {}};
  t.markdown.header = {"camera model", "N_f", "tracking [ms/frame]", "mapping [ms/keyframe]"};
  t.csv.header = {"camera_model", "keyframes", "tracking_ms_per_frame", "mapping_ms_per_keyframe",
                  "runs_used",    "runs"};
  for (const std::string& model : axes.camera_models)
    for (int n : axes.keyframes) {
      std::vector<double> tracking, mapping;
      size_t used = 0, total = 0, missing = 0;
      for (const std::string& dataset : axes.datasets) {
        const CellSummary* c = findCell(cells, dataset, model, n);
        if (!c) continue;
        total += c->runs.size();
        missing += c->missing;
        for (const RunResult& r : c->runs) {
          if (!r.ok) continue;
          ++used;
          if (r.tracking_ms) tracking.push_back(*r.tracking_ms);
          if (r.mapping_ms) mapping.push_back(*r.mapping_ms);
        }
      }
      const Measured track{medianOf(tracking), used, total, missing},
          map{medianOf(mapping), used, total, missing};
      t.markdown.rows.push_back({model, std::to_string(n), display(track, 1),
                                 map.value ? number(*map.value, 1) : display(map, 1)});
      t.csv.rows.push_back({model, std::to_string(n), plain(track.value), plain(map.value),
                            std::to_string(used), std::to_string(total)});
    }
  return t;
}

}  // namespace

std::optional<double> medianOf(const std::vector<double>& values) {
  if (values.empty()) return std::nullopt;
  return computeStatistics(values).median;
}

CellSummary summarizeCell(const AblationCell& cell, std::vector<RunResult> runs) {
  CellSummary s;
  s.cell = cell;
  s.runs = std::move(runs);
  std::vector<double> rmse, percent, drift, tracking, mapping;
  std::vector<std::pair<double, size_t>> by_rmse;
  for (size_t i = 0; i < s.runs.size(); ++i) {
    const RunResult& r = s.runs[i];
    s.missing += r.missing;
    if (!r.ok) continue;
    ++s.succeeded;
    if (r.rmse_m) {
      rmse.push_back(*r.rmse_m);
      by_rmse.push_back({*r.rmse_m, i});
    }
    if (r.rmse_percent_of_path) percent.push_back(*r.rmse_percent_of_path);
    if (r.scale_drift_percent) drift.push_back(*r.scale_drift_percent);
    if (r.tracking_ms) tracking.push_back(*r.tracking_ms);
    if (r.mapping_ms) mapping.push_back(*r.mapping_ms);
  }
  s.rmse_m = medianOf(rmse);
  s.rmse_percent_of_path = medianOf(percent);
  s.scale_drift_percent = medianOf(drift);
  s.tracking_ms = medianOf(tracking);
  s.mapping_ms = medianOf(mapping);
  if (!by_rmse.empty()) {
    std::sort(by_rmse.begin(), by_rmse.end());
    s.median_run = by_rmse[(by_rmse.size() - 1) / 2].second;
  }
  return s;
}

std::vector<AblationTable> ablationTables(const std::vector<DatasetFacts>& datasets,
                                          const std::vector<CellSummary>& cells) {
  const Axes axes(cells);
  if (axes.keyframes.empty()) return {};
  return {tableRmse(axes, cells), tableLength(datasets), tableRmsePerKeyframes(axes, cells),
          tableDifferences(axes, cells), tableTiming(axes, cells)};
}

}  // namespace omnidso::cli
