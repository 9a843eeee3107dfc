#pragma once
// What Slurm says about the tasks of one job array, as omnidso asks it:
//   squeue -h -r -t all -j JOB -o '%i|%T'
//   sacct  -n -X -P -j JOB -o JobID,State,ExitCode,Elapsed,NodeList,Reason
// Both print one line per task, "JOB_INDEX|STATE|…"; tasks that have not started yet may be
// folded into one line "JOB_[3-7%2]|PENDING|…" (expanded here). The states are Slurm's job
// states (squeue(1), sacct(1) "JOB STATE CODES"); sacct may append to one ("CANCELLED by 0").

#include <map>
#include <string>

namespace omnidso::cli {

struct SlurmTaskState {
  std::string state;       // the state code: COMPLETED, TIMEOUT, CANCELLED, …
  std::string state_text;  // as printed: "CANCELLED by 0"
  std::string exit_code;   // sacct: "RC:SIGNAL", e.g. "0:15"
  std::string elapsed;     // sacct: [D-]HH:MM:SS
  std::string node;        // sacct: NodeList
  std::string reason;      // sacct: Reason
};

// Array index → state, for the lines of job `job_id` (other lines, e.g. job steps, ignored).
// Throws omnidso::Error on a line it cannot read, quoting it.
std::map<int, SlurmTaskState> parseSlurmTaskStates(const std::string& text,
                                                   const std::string& job_id);

// Still queued or running (PENDING, RUNNING, CONFIGURING, COMPLETING, SUSPENDED, …): not an end.
bool isActiveSlurmState(const std::string& state);

// Why the task of `job_id`[index] has no result.json, in the words of runs.csv, e.g.
//   "Slurm: TIMEOUT (job 812_3 on node17 after 01:00:02, exit code 0:15)"
// task_output: the task's Slurm output file, named when the task itself failed.
std::string slurmFailureReason(const std::string& job_id, int index, const SlurmTaskState& task,
                               const std::string& task_output);

}  // namespace omnidso::cli
