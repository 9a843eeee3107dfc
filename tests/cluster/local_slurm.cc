#include "local_slurm.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace omnidso::test {
namespace {
namespace fs = std::filesystem;

// The program's path on PATH or in the sbin directories (not on a user's PATH everywhere).
std::string findProgram(const std::string& name) {
  std::string path = std::getenv("PATH") ? std::getenv("PATH") : "";
  path += ":/usr/sbin:/sbin:/usr/local/sbin";
  size_t start = 0;
  while (start <= path.size()) {
    const size_t colon = std::min(path.find(':', start), path.size());
    const fs::path candidate = fs::path(path.substr(start, colon - start)) / name;
    if (colon > start && ::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    start = colon + 1;
  }
  return "";
}

std::string hostName() {
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  return name;
}

bool resolvesToLoopback(const std::string& host) {
  addrinfo hints{}, *found = nullptr;
  hints.ai_family = AF_INET;
  if (::getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || !found) return false;
  const auto* address = reinterpret_cast<const sockaddr_in*>(found->ai_addr);
  const bool loopback = (ntohl(address->sin_addr.s_addr) >> 24) == 127;
  ::freeaddrinfo(found);
  return loopback;
}

// A port the kernel has just handed out on 127.0.0.1 (free a moment later, barring a race).
int freePort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  ::close(fd);
  return ntohs(address.sin_port);
}

bool canConnect(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  ::close(fd);
  return ok;
}

void writeFile(const fs::path& path, const std::string& text, fs::perms perms) {
  std::ofstream(path) << text;
  fs::permissions(path, perms);
}

}  // namespace

std::string commandOutput(const std::string& command) {
  FILE* pipe = ::popen(command.c_str(), "r");
  std::string out;
  for (int c = std::fgetc(pipe); c != EOF; c = std::fgetc(pipe)) out.push_back(char(c));
  ::pclose(pipe);
  return out;
}

std::string LocalSlurm::unavailableReason() {
  for (const char* program : {"munged", "mariadb-install-db", "mariadbd", "slurmdbd", "slurmctld",
                              "slurmd", "sbatch", "squeue", "sacct", "scancel", "sinfo"})
    if (findProgram(program).empty())
      return std::string(program) +
             " is not installed: a local Slurm needs the Debian packages slurm-wlm, slurmdbd, "
             "munge and mariadb-server (`make test-slurm` installs them)";
  if (::geteuid() != 0) return "a local Slurm runs its jobs as their owner: run the test as root";
  if (!resolvesToLoopback(hostName()))
    return "the host name '" + hostName() +
           "' does not resolve to a loopback address, so slurmctld would listen beyond it";
  return "";
}

static std::string newTemporaryFolder() {
  char name[] = "/tmp/omnidso-slurm-XXXXXX";
  if (!::mkdtemp(name)) throw std::runtime_error("mkdtemp failed");
  return name;
}

LocalSlurm::LocalSlurm() : dir_(newTemporaryFolder()) {
  const fs::path d(dir_);
  for (const char* sub : {"munge", "socket", "db", "state", "spool", "log"})
    fs::create_directories(d / sub);
  fs::permissions(d, fs::perms(0755));
  fs::permissions(d / "socket", fs::perms(0755));  // munged insists on it
  fs::permissions(d / "munge", fs::perms(0700));
  std::random_device random;
  std::string key(1024, '\0');
  for (char& c : key) c = static_cast<char>(random());
  writeFile(d / "munge/munge.key", key, fs::perms(0600));
  ctld_port_ = freePort(), slurmd_port_ = freePort(), dbd_port_ = freePort(), db_port_ = freePort();
  const std::string host = hostName(), socket = (d / "socket/munge.socket").string();
  writeFile(
      d / "slurm.conf",
      "ClusterName=omnidsotest\nSlurmctldHost=" + host +
          "(127.0.0.1)\n"
          "SlurmctldPort=" +
          std::to_string(ctld_port_) + "\nSlurmdPort=" + std::to_string(slurmd_port_) +
          "\nCommunicationParameters=NoInAddrAny,NoCtldInAddrAny\n"
          "AuthType=auth/munge\nCredType=cred/munge\nAuthInfo=socket=" +
          socket +
          "\n"
          "SlurmUser=root\nSlurmdUser=root\nStateSaveLocation=" +
          dir_ +
          "/state\n"
          "SlurmdSpoolDir=" +
          dir_ + "/spool\nSlurmctldPidFile=" + dir_ +
          "/slurmctld.pid\n"
          "SlurmdPidFile=" +
          dir_ + "/slurmd.pid\nSlurmctldLogFile=" + dir_ +
          "/log/slurmctld.log\n"
          "SlurmdLogFile=" +
          dir_ +
          "/log/slurmd.log\nProctrackType=proctrack/linuxproc\n"
          "TaskPlugin=task/none\nMpiDefault=none\nSelectType=select/cons_tres\n"
          "SelectTypeParameters=CR_Core\nJobAcctGatherType=jobacct_gather/none\n"
          "AccountingStorageType=accounting_storage/slurmdbd\nAccountingStorageHost=127.0.0.1\n"
          "AccountingStoragePort=" +
          std::to_string(dbd_port_) + "\nAccountingStoragePass=" + socket +
          "\nReturnToService=2\nKillWait=5\nNodeName=" + host + " NodeAddr=127.0.0.1 CPUs=" +
          std::to_string(std::max(1u, std::thread::hardware_concurrency())) +
          " State=UNKNOWN\nPartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP\n",
      fs::perms(0644));
  writeFile(d / "slurmdbd.conf",
            "AuthType=auth/munge\nAuthInfo=socket=" + socket +
                "\nDbdHost=localhost\n"
                "DbdAddr=127.0.0.1\nDbdPort=" +
                std::to_string(dbd_port_) +
                "\nSlurmUser=root\n"
                "LogFile=" +
                dir_ + "/log/slurmdbd.log\nPidFile=" + dir_ +
                "/slurmdbd.pid\n"
                "StorageType=accounting_storage/mysql\nStorageHost=127.0.0.1\nStoragePort=" +
                std::to_string(db_port_) +
                "\nStorageUser=root\nStorageLoc=slurm_acct_db\n"
                "CommunicationParameters=NoInAddrAny\n",
            fs::perms(0600));  // slurmdbd refuses a readable one
  had_conf_ = std::getenv("SLURM_CONF") != nullptr;
  if (had_conf_) previous_conf_ = std::getenv("SLURM_CONF");
  ::setenv("SLURM_CONF", (d / "slurm.conf").c_str(), 1);  // slurmdbd finds its file beside it

  try {
    start("munged",
          {findProgram("munged"), "-F", "--key-file=" + dir_ + "/munge/munge.key",
           "--socket=" + socket, "--pid-file=" + dir_ + "/munge/munged.pid",
           "--log-file=" + dir_ + "/log/munged.log", "--seed-file=" + dir_ + "/munge/seed"});
    waitUntil("munged", 20,
              [](const LocalSlurm& s) { return fs::exists(s.dir_ + "/socket/munge.socket"); });
    const std::string install = findProgram("mariadb-install-db") +
                                " --no-defaults --datadir=" + dir_ +
                                "/db/data --user=root --auth-root-authentication-method=normal"
                                " --skip-test-db > " +
                                dir_ + "/log/mariadb-install.log 2>&1";
    if (std::system(install.c_str()) != 0)
      throw std::runtime_error("mariadb-install-db failed:\n" + logTail("mariadb-install"));
    // No network beyond loopback, no grant tables: slurmdbd logs in without a password.
    start("mariadb", {findProgram("mariadbd"), "--no-defaults", "--datadir=" + dir_ + "/db/data",
                      "--socket=" + dir_ + "/db/mysql.sock", "--port=" + std::to_string(db_port_),
                      "--bind-address=127.0.0.1", "--user=root", "--skip-grant-tables",
                      "--innodb-buffer-pool-size=64M", "--pid-file=" + dir_ + "/db/mariadb.pid"});
    waitUntil("mariadb", 60, [](const LocalSlurm& s) { return canConnect(s.db_port_); });
    start("slurmdbd", {findProgram("slurmdbd"), "-D"});
    waitUntil("slurmdbd", 60, [](const LocalSlurm& s) { return canConnect(s.dbd_port_); });
    start("slurmctld", {findProgram("slurmctld"), "-D", "-i"});
    waitUntil("slurmctld", 60, [](const LocalSlurm& s) { return canConnect(s.ctld_port_); });
    start("slurmd", {findProgram("slurmd"), "-D"});
    waitUntil("slurmd", 60, [](const LocalSlurm&) {
      return commandOutput("sinfo -h -o %t 2>/dev/null").rfind("idle", 0) == 0;
    });
  } catch (...) {
    stopAll();
    throw;
  }
}

LocalSlurm::~LocalSlurm() { stopAll(); }

void LocalSlurm::start(const std::string& name, const std::vector<std::string>& argv) {
  const std::string log = dir_ + "/log/" + name + ".out";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int rc = ::posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot start " + argv[0]);
  daemons_.push_back({name, pid});
}

void LocalSlurm::waitUntil(const std::string& name, double timeout_s,
                           bool (*ready)(const LocalSlurm&)) {
  const auto start = std::chrono::steady_clock::now();
  while (!ready(*this)) {
    int status = 0;
    const pid_t pid = daemons_.back().second;
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      daemons_.pop_back();
      throw std::runtime_error(name + " exited:\n" + logTail(name));
    }
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > timeout_s)
      throw std::runtime_error(name + " not ready after " + std::to_string(timeout_s) + " s:\n" +
                               logTail(name));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

std::string LocalSlurm::logTail(const std::string& name) const {
  std::string text;
  for (const std::string& file : {dir_ + "/log/" + name + ".out", dir_ + "/log/" + name + ".log"}) {
    std::ifstream in(file);
    const std::string all(std::istreambuf_iterator<char>(in), {});
    text += all.size() > 3000 ? all.substr(all.size() - 3000) : all;
  }
  return text;
}

void LocalSlurm::stopAll() {
  if (!daemons_.empty()) std::system("scancel --user=root > /dev/null 2>&1");
  for (auto it = daemons_.rbegin(); it != daemons_.rend(); ++it) {
    ::kill(it->second, SIGTERM);
    int status = 0;
    for (int i = 0; i < 150 && ::waitpid(it->second, &status, WNOHANG) == 0; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (::waitpid(it->second, &status, WNOHANG) == 0) {
      ::kill(it->second, SIGKILL);
      ::waitpid(it->second, &status, 0);
    }
  }
  daemons_.clear();
  std::error_code ignored;
  fs::remove_all(dir_, ignored);
  if (had_conf_)
    ::setenv("SLURM_CONF", previous_conf_.c_str(), 1);
  else
    ::unsetenv("SLURM_CONF");
}

}  // namespace omnidso::test
