#pragma once
// A real single-node Slurm cluster in a temporary folder, for the tests of
// `omnidso ablate --executor slurm`: munged, MariaDB (for accounting), slurmdbd, slurmctld and
// slurmd from Debian's munge, mariadb-server, slurmdbd and slurm-wlm packages, each started in
// the foreground as a child of the test with a generated configuration, listening on loopback
// ports only (CommunicationParameters=NoInAddrAny,NoCtldInAddrAny; the host name must resolve
// to a loopback address), and stopped again by the destructor. SLURM_CONF points the Slurm
// commands (sbatch, squeue, sacct, scancel) of this process and its children at it meanwhile.
// Jobs run as the user of the test, which must be root (slurmd launches jobs as their owner).

#include <sys/types.h>

#include <string>
#include <utility>
#include <vector>

namespace omnidso::test {

// What `command` (run by /bin/sh) prints on stdout.
std::string commandOutput(const std::string& command);

class LocalSlurm {
 public:
  // Why this machine cannot run the cluster (a missing program, not root, ...); empty if it can.
  static std::string unavailableReason();

  // Starts every daemon in a new folder /tmp/omnidso-slurm-XXXXXX (short: munge's socket path
  // must fit in 108 bytes) and waits for the node to be idle; throws std::runtime_error with
  // the failing daemon's log otherwise. The folder is removed again by the destructor.
  LocalSlurm();
  ~LocalSlurm();
  LocalSlurm(const LocalSlurm&) = delete;
  LocalSlurm& operator=(const LocalSlurm&) = delete;

 private:
  void start(const std::string& name, const std::vector<std::string>& argv);
  void waitUntil(const std::string& name, double timeout_s, bool (*ready)(const LocalSlurm&));
  std::string logTail(const std::string& name) const;
  void stopAll();

  std::string dir_;
  std::string previous_conf_;
  bool had_conf_ = false;
  int ctld_port_ = 0, slurmd_port_ = 0, dbd_port_ = 0, db_port_ = 0;
  std::vector<std::pair<std::string, pid_t>> daemons_;  // in start order
};

}  // namespace omnidso::test
