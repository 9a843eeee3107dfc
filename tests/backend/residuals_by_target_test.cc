#include "omnidso/backend/residuals_by_target.hpp"

#include <gtest/gtest.h>

#include <map>
#include <random>

namespace omnidso {
namespace {

ceres::ResidualBlockId fakeId(int i) { return reinterpret_cast<ceres::ResidualBlockId>(0x1000 + 16 * i); }

// Random inserts, lookups and erasures against std::map, the container it replaces: the same
// entries in the same (ascending) order after every operation.
TEST(ResidualsByTarget, BehavesAsStdMapUnderRandomEdits) {
  std::mt19937 rng(7);
  ResidualsByTarget mine;
  std::map<int, ceres::ResidualBlockId> theirs;
  for (int step = 0; step < 2000; ++step) {
    const int target = static_cast<int>(rng() % 12);
    switch (rng() % 4) {
      case 0:
      case 1:
        mine[target] = fakeId(step);
        theirs[target] = fakeId(step);
        break;
      case 2: {
        const auto a = mine.find(target);
        const auto b = theirs.find(target);
        ASSERT_EQ(a == mine.end(), b == theirs.end());
        if (a != mine.end()) {
          mine.erase(a);
          theirs.erase(b);
        }
        break;
      }
      default:
        ASSERT_EQ(mine.count(target), theirs.count(target));
        if (rng() % 50 == 0) {
          mine.clear();
          theirs.clear();
        }
    }
    ASSERT_EQ(mine.size(), theirs.size());
    ASSERT_EQ(mine.empty(), theirs.empty());
    auto b = theirs.begin();
    for (const auto& [t, id] : mine) {
      ASSERT_EQ(t, b->first);
      ASSERT_EQ(id, b->second);
      ++b;
    }
  }
}

// erase(it) returns the next entry, so erasing while walking visits every other entry once.
TEST(ResidualsByTarget, EraseWhileWalkingReturnsTheNextEntry) {
  ResidualsByTarget r;
  for (int t : {5, 1, 3, 9, 7}) r[t] = fakeId(t);
  std::vector<int> seen;
  for (auto it = r.begin(); it != r.end();) {
    seen.push_back(it->first);
    it = it->first % 3 == 0 ? r.erase(it) : std::next(it);
  }
  EXPECT_EQ(seen, (std::vector<int>{1, 3, 5, 7, 9}));
  std::vector<int> left;
  for (const auto& [t, id] : r) left.push_back(t);
  EXPECT_EQ(left, (std::vector<int>{1, 5, 7}));
  EXPECT_EQ(r.find(3), r.end());
  EXPECT_EQ(r.find(5)->second, fakeId(5));
}

}  // namespace
}  // namespace omnidso
