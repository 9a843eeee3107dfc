// Timestamp association (definitions in metrics.hpp).
#include <algorithm>
#include <cmath>
#include <omnidso/core/error.hpp>
#include <omnidso/core/metrics.hpp>
#include <queue>
#include <tuple>

namespace omnidso {
namespace {

// The candidates of one estimated pose in order of increasing |Δt| (ties: lower
// ground-truth index), walking outwards from its timestamp in the sorted ground truth.
class CandidateStream {
 public:
  CandidateStream(const Trajectory& gt, double t, double max_dt) : gt_(gt), t_(t), max_dt_(max_dt) {
    const auto first_not_before = std::lower_bound(
        gt.begin(), gt.end(), t, [](const StampedPose& p, double s) { return p.timestamp < s; });
    right_ = static_cast<std::ptrdiff_t>(first_not_before - gt.begin());
    left_ = right_ - 1;
  }

  // The current candidate (|Δt|, ground-truth index), or nothing when exhausted.
  std::optional<std::pair<double, size_t>> current() const {
    if (left_ < 0 && right_ >= static_cast<std::ptrdiff_t>(gt_.size())) return std::nullopt;
    const double left_dt = left_ >= 0 ? t_ - gt_[static_cast<size_t>(left_)].timestamp : kNone;
    const double right_dt = right_ < static_cast<std::ptrdiff_t>(gt_.size())
                                ? gt_[static_cast<size_t>(right_)].timestamp - t_
                                : kNone;
    const bool take_left = left_dt <= right_dt;
    const double dt = take_left ? left_dt : right_dt;
    if (!(dt <= max_dt_)) return std::nullopt;
    return std::make_pair(dt, static_cast<size_t>(take_left ? left_ : right_));
  }

  void advancePast(size_t gt_index) {
    if (static_cast<std::ptrdiff_t>(gt_index) == left_) {
      --left_;
    } else {
      ++right_;
    }
  }

 private:
  static constexpr double kNone = HUGE_VAL;
  const Trajectory& gt_;
  double t_;
  double max_dt_;
  std::ptrdiff_t left_ = 0;
  std::ptrdiff_t right_ = 0;
};

}  // namespace

Association associate(const Trajectory& gt, const Trajectory& est, double max_dt) {
  if (!(max_dt >= 0.0)) throw Error("association: max_dt must be >= 0");
  std::vector<CandidateStream> streams;
  streams.reserve(est.size());
  // Min-heap of (|Δt|, gt index, est index): the global order of TUM's sorted pair list.
  using Entry = std::tuple<double, size_t, size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  for (size_t i = 0; i < est.size(); ++i) {
    streams.emplace_back(gt, est[i].timestamp, max_dt);
    if (const auto c = streams.back().current()) heap.emplace(c->first, c->second, i);
  }
  std::vector<bool> gt_used(gt.size(), false);
  Association matches;
  while (!heap.empty()) {
    const auto [dt, j, i] = heap.top();
    heap.pop();
    if (!gt_used[j]) {
      gt_used[j] = true;
      matches.emplace_back(j, i);
      continue;  // estimate i is matched: its other candidates are dropped
    }
    streams[i].advancePast(j);
    if (const auto c = streams[i].current()) heap.emplace(c->first, c->second, i);
  }
  std::sort(matches.begin(), matches.end());
  return matches;
}

Association associateByIndex(const Trajectory& gt, const Trajectory& est) {
  Association matches;
  for (size_t k = 0; k < std::min(gt.size(), est.size()); ++k) matches.emplace_back(k, k);
  return matches;
}

}  // namespace omnidso
