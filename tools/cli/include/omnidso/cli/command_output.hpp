#pragma once
// Runs a program (found on PATH, like a shell would) to its end and returns what it printed:
// how omnidso talks to sbatch, squeue, sacct and GNU parallel.

#include <string>
#include <vector>

namespace omnidso::cli {

struct CommandOutput {
  bool started = false;  // false: not found or not executable (`error` says why)
  int exit_code = -1;    // -1 when killed by a signal
  std::string out, err;  // its stdout and stderr
  std::string error;

  bool succeeded() const { return started && exit_code == 0; }
  // "sbatch: exit status 1: sbatch: error: invalid partition specified: gpu" and the like.
  std::string describe() const;
};

CommandOutput runCommand(const std::vector<std::string>& argv);

}  // namespace omnidso::cli
