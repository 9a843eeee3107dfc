#pragma once
// Writes a synthetic sequence as a dataset in the TUM mono/omni layout
// (../shared/design.md; read back by omnidso/core/dataset.hpp):
//   images/ID.png      8-bit frames, ID zero-padded to 5 digits (more when needed)
//   times.txt          `ID timestamp_s exposure_ms` (shortest round-trip decimals)
//   camchain.yaml      Kalibr calibration; camera.txt too where DSO has the model
//   pcalib.txt         G⁻¹ at 0..255 (photometric_model.hpp)
//   vignette.png       16-bit V, normalised by its maximum
//   groundtruth.txt    TUM format, T_world_cam at the frame timestamps

#include <functional>
#include <string>

#include <omnidso/synth/synthetic_sequence.hpp>

namespace omnidso::synth {

struct DatasetWriteOptions {
  bool overwrite = false;  // otherwise a non-empty output directory is refused
  // Called after each frame with (frames written, total).
  std::function<void(int, int)> progress;
};

// Renders every remaining frame of the sequence and writes the dataset. Throws
// omnidso::Error naming the directory if it is not empty (and overwrite is off) or cannot
// be written. With overwrite, only what a dataset consists of is removed first (images/
// and the files above), never anything else in the directory.
void writeSyntheticDataset(SyntheticSequence& sequence, const std::string& out_dir,
                           const DatasetWriteOptions& options = {});

// The zero-padded frame ID ("00042" for 42 of up to 100000 frames).
std::string frameId(int index, int num_frames);

}  // namespace omnidso::synth
