// The `omnidso` command line: dispatches to the subcommands of omnidso::cli.
#include <CLI/CLI.hpp>
#include <iostream>
#include <omnidso/cli/commands.hpp>
#include <omnidso/core/error.hpp>

int main(int argc, char** argv) {
  CLI::App app{"omnidso: direct sparse odometry and photometric bundle adjustment for "
               "omnidirectional cameras"};
  app.require_subcommand(1);
  omnidso::cli::registerCameraCommand(app);
  omnidso::cli::registerEvalCommand(app);
  omnidso::cli::registerSynthCommand(app);
  omnidso::cli::registerDatasetCommand(app);
  omnidso::cli::registerRunCommand(app);
  omnidso::cli::registerAblateCommand(app);
  omnidso::cli::registerAblateTaskCommand(app);
  omnidso::cli::registerCalibrateCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0 with their text; a bad command line is bad input like a bad
    // file: one "omnidso: error:" line and status 2.
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    std::cerr << "omnidso: error: " << e.what() << " (omnidso --help)\n";
    return 2;
  } catch (const omnidso::Error& e) {
    std::cerr << "omnidso: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "omnidso: error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
