// The activation density (activation_density.hpp): the grid's cell scale s steps down while
// the window holds fewer than shrink_below · N_p points and back up otherwise, within
// [min_scale, 1].
#include <gtest/gtest.h>

#include <limits>
#include <omnidso/core/error.hpp>
#include <omnidso/frontend/activation_density.hpp>

namespace omnidso {
namespace {

constexpr int kNp = 2000;

TEST(ActivationDensity, StepsDownWhileTheWindowHoldsTooFewPoints) {
  ActivationDensity density;  // shrink below 0.5 N_p = 1000, step 0.2
  EXPECT_EQ(density.scale(), 1.0);
  const double expected[] = {0.8, 0.6, 0.4, 0.2, 0.0, 0.0};
  for (double s : expected) EXPECT_NEAR(density.update(500, kNp), s, 1e-12);
  // 999 is short of 1000 too: one more call at the floor stays there.
  EXPECT_NEAR(density.update(999, kNp), 0.0, 1e-12);
}

TEST(ActivationDensity, StepsBackUpOnceTheWindowIsNoLongerShort) {
  ActivationDensity density;
  density.update(500, kNp);
  density.update(500, kNp);                             // 0.6
  EXPECT_NEAR(density.update(1000, kNp), 0.8, 1e-12);   // at 0.5 N_p: not short
  EXPECT_NEAR(density.update(500, kNp), 0.6, 1e-12);
  EXPECT_NEAR(density.update(1500, kNp), 0.8, 1e-12);
  EXPECT_NEAR(density.update(1500, kNp), 1.0, 1e-12);
  EXPECT_EQ(density.update(4000, kNp), 1.0);  // never above the full cell
  density.update(100, kNp);
  density.reset();
  EXPECT_EQ(density.scale(), 1.0);
}

TEST(ActivationDensity, RespectsItsFloorAndCanBeSwitchedOff) {
  ActivationDensityOptions floor;
  floor.min_scale = 0.5;
  ActivationDensity bounded(floor);
  for (int i = 0; i < 10; ++i) bounded.update(0, kNp);
  EXPECT_NEAR(bounded.scale(), 0.5, 1e-12);

  ActivationDensityOptions fixed;
  fixed.adaptive = false;
  ActivationDensity off(fixed);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(off.update(0, kNp), 1.0);
}

TEST(ActivationDensity, RefusesOptionsWithoutAMeaning) {
  const auto with = [](auto edit) {
    ActivationDensityOptions o;
    edit(o);
    return o;
  };
  EXPECT_NO_THROW(ActivationDensity(with([](auto& o) { o.shrink_below = 1.5; })));
  EXPECT_THROW(ActivationDensity(with([](auto& o) { o.shrink_below = -0.1; })), Error);
  EXPECT_THROW(ActivationDensity(with([](auto& o) { o.step = 0.0; })), Error);
  EXPECT_THROW(ActivationDensity(with([](auto& o) { o.step = 1.5; })), Error);
  EXPECT_THROW(ActivationDensity(with([](auto& o) { o.min_scale = 1.2; })), Error);
  EXPECT_THROW(ActivationDensity(with([](auto& o) {
                 o.shrink_below = std::numeric_limits<double>::infinity();
               })),
               Error);
}

}  // namespace
}  // namespace omnidso
