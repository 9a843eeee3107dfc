#pragma once
// Each subcommand of the `omnidso` executable registers itself on the CLI11 app. The
// callbacks throw omnidso::Error on bad input; main() prints it and exits with status 2.

namespace CLI {
class App;
}

namespace omnidso::cli {

void registerCameraCommand(CLI::App& app);  // omnidso camera info|convert
void registerEvalCommand(CLI::App& app);    // omnidso eval (ATE, RPE)
void registerSynthCommand(CLI::App& app);    // omnidso synth (synthetic datasets)
void registerDatasetCommand(CLI::App& app);  // omnidso dataset info
void registerRunCommand(CLI::App& app);      // omnidso run (the odometry)
void registerAblateCommand(CLI::App& app);   // omnidso ablate (the paper's ablation)
void registerAblateTaskCommand(CLI::App& app);  // omnidso ablate-task (one run, in a cluster job)
void registerCalibrateCommand(CLI::App& app);  // omnidso calibrate (chessboard images)

}  // namespace omnidso::cli
