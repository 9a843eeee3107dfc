#include <fmt/core.h>

#include <omnidso/cli/shell_words.hpp>
#include <omnidso/cli/slurm_script.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso::cli {
namespace {

// sbatch reads an #SBATCH line up to its end, splitting at blanks.
std::string directive(const std::string& option, const std::string& value, const char* origin) {
  if ((option + value).find_first_of("\n\r") != std::string::npos)
    throw Error(fmt::format("{}: '{}' holds a line break", origin, value.empty() ? option : value));
  return "#SBATCH " + (value.empty() ? option : option + "=" + value) + "\n";
}

}  // namespace

std::string slurmArrayScript(const std::vector<std::vector<std::string>>& tasks,
                             const SlurmResources& resources, int max_running,
                             const std::string& output_directory) {
  if (tasks.empty()) throw Error("slurm: no runs to submit");
  if (output_directory.find_first_of(" \t\n\"'") != std::string::npos)
    throw Error("--out: '" + output_directory +
                "' holds a blank or a quote, which an #SBATCH --output line cannot; choose "
                "another --out");
  std::string pattern;  // Slurm expands %a (the array index); a literal % is %%
  for (char c : output_directory) pattern += c == '%' ? std::string("%%") : std::string(1, c);
  std::string s = "#!/bin/bash\n";
  s += "# Written by `omnidso ablate --executor slurm`: array task i performs the i-th run below\n"
       "# (the runs without a result.json when it was submitted) and writes its result.json.\n"
       "# Submitting the same `omnidso ablate` command again runs only what is still missing;\n"
       "# `omnidso ablate --collect --out OUT` builds the tables from what has finished.\n";
  s += directive("--job-name", "omnidso-ablate", "slurm");
  s += directive("--array",
                 fmt::format("0-{}{}", tasks.size() - 1,
                             max_running > 0 ? fmt::format("%{}", max_running) : ""),
                 "slurm");
  s += directive("--output", pattern + "/task-%a.out", "--out");
  s += directive("--ntasks", "1", "slurm");
  s += directive("--cpus-per-task", std::to_string(resources.cpus), "--slurm-cpus");
  if (!resources.partition.empty())
    s += directive("--partition", resources.partition, "--slurm-partition");
  if (!resources.time.empty()) s += directive("--time", resources.time, "--slurm-time");
  if (!resources.mem.empty()) s += directive("--mem", resources.mem, "--slurm-mem");
  for (const std::string& extra : resources.extra) s += directive(extra, "", "--slurm-arg");
  s += "\nset -u\ncase \"${SLURM_ARRAY_TASK_ID:?not started as a Slurm array task}\" in\n";
  for (size_t i = 0; i < tasks.size(); ++i)
    s += fmt::format("  {}) exec {} ;;\n", i, shellCommandLine(tasks[i]));
  s += "  *) echo \"omnidso: no run for array task $SLURM_ARRAY_TASK_ID\" >&2; exit 2 ;;\nesac\n";
  return s;
}

}  // namespace omnidso::cli
