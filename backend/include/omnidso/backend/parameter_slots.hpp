#pragma once
// Storage for many one-value parameter blocks (the window's inverse distances) in one array,
// handed out lowest free index first.
//
// Why not the heap: Ceres orders the blocks of an elimination group by memory address
// (ceres::OrderedGroups keeps a std::set<double*>), and that order is the order in which the
// Schur complement sums its terms. Heap addresses depend on every earlier allocation — even
// on the length of the command line — so the same input could give results differing in the
// last bits, which grow over a sequence. Slots of one array make the order a function of the
// sequence of acquire/release calls alone.

#include <functional>
#include <memory>
#include <queue>
#include <vector>

namespace omnidso {

class ParameterSlots {
 public:
  // Reserves `capacity` slots (address space only: a slot's page is touched when first used).
  explicit ParameterSlots(int capacity);

  // The lowest free slot. Throws omnidso::Error when all `capacity` slots are in use.
  double* acquire();
  // Returns a slot of this array. Throws omnidso::Error for any other pointer or a free slot.
  void release(double* slot);

  int capacity() const { return capacity_; }
  int numUsed() const { return next_unused_ - static_cast<int>(released_.size()); }

 private:
  int capacity_;
  std::unique_ptr<double[]> storage_;
  int next_unused_ = 0;  // slots at and above it were never handed out
  std::priority_queue<int, std::vector<int>, std::greater<int>> released_;  // lowest on top
  std::vector<bool> in_use_;
};

}  // namespace omnidso
