#pragma once
// A window point's residual blocks by target keyframe id: a sorted vector with the part of
// std::map's interface the window uses (ordered iteration, find, count, operator[], erase).
//
// Why not std::map: a point has a handful of residuals, and the window walks every point's
// residuals several times per keyframe (the native problem, the energy fingerprint twice, the
// outlier pass, marginalisation). Walking 12 000 tree nodes scattered over the heap was 4 % of a
// run's samples (perf, D2); a sorted vector keeps each point's residuals in one cache line or
// two. The order — ascending target id — is std::map's, so everything summed over it is too.

#include <ceres/problem.h>

#include <algorithm>
#include <utility>
#include <vector>

namespace omnidso {

class ResidualsByTarget {
 public:
  using value_type = std::pair<int, ceres::ResidualBlockId>;
  using iterator = std::vector<value_type>::iterator;
  using const_iterator = std::vector<value_type>::const_iterator;

  iterator begin() { return entries_.begin(); }
  iterator end() { return entries_.end(); }
  const_iterator begin() const { return entries_.begin(); }
  const_iterator end() const { return entries_.end(); }
  size_t size() const { return entries_.size(); }
  bool empty() const { return entries_.empty(); }
  void clear() { entries_.clear(); }

  iterator find(int target) {
    const iterator it = lowerBound(target);
    return it != entries_.end() && it->first == target ? it : entries_.end();
  }
  const_iterator find(int target) const {
    const const_iterator it = std::lower_bound(entries_.begin(), entries_.end(), target, before);
    return it != entries_.end() && it->first == target ? it : entries_.end();
  }
  size_t count(int target) const { return find(target) != end() ? 1 : 0; }

  // The block for `target`, inserted (null) in order if absent.
  ceres::ResidualBlockId& operator[](int target) {
    iterator it = lowerBound(target);
    if (it == entries_.end() || it->first != target) it = entries_.insert(it, {target, nullptr});
    return it->second;
  }

  // Removes one entry; the iterator after it (std::map's contract; later iterators move).
  iterator erase(iterator it) { return entries_.erase(it); }

 private:
  static bool before(const value_type& entry, int target) { return entry.first < target; }
  iterator lowerBound(int target) {
    return std::lower_bound(entries_.begin(), entries_.end(), target, before);
  }

  std::vector<value_type> entries_;  // ascending target id
};

}  // namespace omnidso
