#pragma once
// Each subcommand of the `omnidso` executable registers itself on the CLI11 app. The
// callbacks throw omnidso::Error on bad input; main() prints it and exits with status 2.

namespace CLI {
class App;
}

namespace omnidso::cli {

void registerCameraCommand(CLI::App& app);  // omnidso camera info|convert

}  // namespace omnidso::cli
