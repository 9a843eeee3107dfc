// The recorded time a run covers, from which `omnidso run` reports its real-time factor.
#include <gtest/gtest.h>

#include <omnidso/cli/run_outputs.hpp>
#include <omnidso/core/dataset.hpp>

namespace omnidso::cli {
namespace {

DatasetIndex framesAt(double rate_hz, int n) {
  DatasetIndex index;
  for (int i = 0; i < n; ++i) {
    DatasetFrame f;
    f.timestamp_s = 1000.0 + i / rate_hz;
    index.frames.push_back(f);
  }
  return index;
}

// 11 frames at 20 Hz: ten periods between the first and the last timestamp, plus the last
// frame's own period — 0.55 s, so a run of 0.275 s of wall time is 2× real time.
TEST(ProcessedSequenceSeconds, IsTheTimestampSpanPlusOnePeriod) {
  const DatasetIndex index = framesAt(20.0, 11);
  EXPECT_NEAR(processedSequenceSeconds(index, 11), 0.55, 1e-9);
  EXPECT_NEAR(processedSequenceSeconds(index, 11) / 0.275, 2.0, 1e-9);
}

// --max-frames: only the frames processed count; more than the dataset holds is the dataset.
TEST(ProcessedSequenceSeconds, CountsOnlyTheProcessedFrames) {
  const DatasetIndex index = framesAt(20.0, 11);
  EXPECT_NEAR(processedSequenceSeconds(index, 1), 0.05, 1e-9);
  EXPECT_NEAR(processedSequenceSeconds(index, 4), 0.20, 1e-9);
  EXPECT_NEAR(processedSequenceSeconds(index, 100), 0.55, 1e-9);
  EXPECT_EQ(processedSequenceSeconds(index, 0), 0.0);
}

// One frame: no frame rate, so no recorded time and no real-time factor.
TEST(ProcessedSequenceSeconds, IsZeroWithoutAFrameRate) {
  EXPECT_EQ(processedSequenceSeconds(framesAt(20.0, 1), 1), 0.0);
  EXPECT_EQ(processedSequenceSeconds(DatasetIndex{}, 5), 0.0);
}

}  // namespace
}  // namespace omnidso::cli
