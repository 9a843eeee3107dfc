#pragma once
// OUT/ablation.json: marks OUT as an ablation directory and records the grid it was asked
// for — the datasets, camera models, N_f, runs, seeds, the options passed to every run and
// the timeout — so that `omnidso ablate --collect --out OUT` can rebuild the same plan (and
// the same tables) without the original command line, e.g. after a cluster job ended.

#include <omnidso/cli/ablation_plan.hpp>
#include <string>

namespace omnidso::cli {

struct AblationManifest {
  AblationSpec spec;
  double timeout_s = 0;  // per run; 0: none
  int jobs = 1;          // runs at a time (Slurm: the array's %M)
};

void writeAblationManifest(const std::string& out_dir, const AblationPlan& plan,
                           const AblationManifest& manifest);

// Throws omnidso::Error naming OUT/ablation.json when it is missing, unreadable, or written by
// an omnidso too old to record the grid.
AblationManifest readAblationManifest(const std::string& out_dir);

}  // namespace omnidso::cli
