// ParameterSlots: lowest free slot first, addresses in slot order, clear errors.
#include <gtest/gtest.h>

#include <omnidso/backend/parameter_slots.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso {
namespace {

TEST(ParameterSlots, HandsOutConsecutiveSlotsThenReusesTheLowestFreedFirst) {
  ParameterSlots slots(8);
  double* a = slots.acquire();
  double* b = slots.acquire();
  double* c = slots.acquire();
  double* d = slots.acquire();
  EXPECT_EQ(b, a + 1);
  EXPECT_EQ(c, a + 2);
  EXPECT_EQ(d, a + 3);
  slots.release(c);
  slots.release(a);
  EXPECT_EQ(slots.numUsed(), 2);
  EXPECT_EQ(slots.acquire(), a);  // the lowest of the freed slots, not the latest
  EXPECT_EQ(slots.acquire(), c);
  EXPECT_EQ(slots.acquire(), a + 4);  // then never-used ones
  EXPECT_EQ(slots.numUsed(), 5);
}

TEST(ParameterSlots, AcquiredSlotsStartAtZero) {
  ParameterSlots slots(2);
  double* a = slots.acquire();
  *a = 3.5;
  slots.release(a);
  EXPECT_EQ(*slots.acquire(), 0.0);
}

TEST(ParameterSlots, FullArrayAndForeignOrFreePointersAreErrors) {
  ParameterSlots slots(2);
  double* a = slots.acquire();
  slots.acquire();
  EXPECT_THROW(slots.acquire(), Error);
  double elsewhere = 0.0;
  EXPECT_THROW(slots.release(&elsewhere), Error);
  slots.release(a);
  EXPECT_THROW(slots.release(a), Error);
  EXPECT_THROW(ParameterSlots(0), Error);
}

}  // namespace
}  // namespace omnidso
