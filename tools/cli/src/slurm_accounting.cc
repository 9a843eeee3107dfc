#include <fmt/core.h>

#include <omnidso/cli/ablation_plan.hpp>
#include <omnidso/cli/slurm_accounting.hpp>
#include <omnidso/core/error.hpp>
#include <set>
#include <sstream>
#include <vector>

namespace omnidso::cli {
namespace {

std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out(1);
  for (char c : line) {
    if (c == '|')
      out.emplace_back();
    else
      out.back().push_back(c);
  }
  return out;
}

// "3", "[3-7]", "[1,4-5%2]" → the indices.
std::vector<int> arrayIndices(const std::string& text, const std::string& line) {
  auto number = [&](const std::string& s) {
    size_t used = 0;
    int v = -1;
    try {
      v = std::stoi(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != s.size() || v < 0)
      throw Error("slurm: cannot read the array index '" + s + "' in '" + line + "'");
    return v;
  };
  if (text.empty() || text.front() != '[') return {number(text)};
  if (text.back() != ']') throw Error("slurm: cannot read the array range in '" + line + "'");
  std::string ranges = text.substr(1, text.size() - 2);
  ranges = ranges.substr(0, ranges.find('%'));
  std::vector<int> indices;
  for (const std::string& range : splitList(ranges, "slurm: '" + line + "'")) {
    const size_t dash = range.find('-');
    const int first = number(range.substr(0, dash));
    const int last = dash == std::string::npos ? first : number(range.substr(dash + 1));
    for (int i = first; i <= last; ++i) indices.push_back(i);
  }
  return indices;
}

}  // namespace

std::map<int, SlurmTaskState> parseSlurmTaskStates(const std::string& text,
                                                   const std::string& job_id) {
  std::map<int, SlurmTaskState> tasks;
  std::istringstream in(text);
  std::string line;
  const std::string prefix = job_id + "_";
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> f = fields(line);
    if (f.size() < 2) throw Error("slurm: cannot read the line '" + line + "'");
    if (f[0].rfind(prefix, 0) != 0) continue;  // another job, or a step such as 812_3.batch
    const std::string index_text = f[0].substr(prefix.size());
    if (index_text.find('.') != std::string::npos) continue;
    SlurmTaskState s;
    s.state_text = f[1];
    s.state = f[1].substr(0, f[1].find(' '));
    if (f.size() > 2) s.exit_code = f[2];
    if (f.size() > 3) s.elapsed = f[3];
    if (f.size() > 4) s.node = f[4];
    if (f.size() > 5) s.reason = f[5];
    for (int index : arrayIndices(index_text, line)) tasks[index] = s;
  }
  return tasks;
}

bool isActiveSlurmState(const std::string& state) {
  static const std::set<std::string> active = {
      "PENDING",   "RUNNING",     "CONFIGURING",  "COMPLETING", "SUSPENDED",
      "REQUEUED",  "REQUEUE_FED", "REQUEUE_HOLD", "RESIZING",   "RESV_DEL_HOLD",
      "SIGNALING", "STAGE_OUT",   "STOPPED"};
  return active.count(state) > 0;
}

std::string slurmFailureReason(const std::string& job_id, int index, const SlurmTaskState& task,
                               const std::string& task_output) {
  std::string where = fmt::format("job {}_{}", job_id, index);
  if (!task.node.empty() && task.node != "None assigned") where += " on " + task.node;
  if (!task.elapsed.empty()) where += " after " + task.elapsed;
  if (!task.exit_code.empty()) where += ", exit code " + task.exit_code;
  // Reasons that only say why the task waited are no reason for its end.
  static const std::set<std::string> waiting = {
      "", "None", "JobArrayTaskLimit", "Priority", "Resources", "BeginTime", "Dependency"};
  if (!waiting.count(task.reason)) where += ", reason " + task.reason;
  std::string text = fmt::format("Slurm: {} ({})", task.state_text, where);
  if (task.state == "FAILED" || task.state == "COMPLETED")
    text += "; the task ended without a result.json, see " + task_output;
  return text;
}

}  // namespace omnidso::cli
