// The command lines omnidso writes into Slurm scripts and GNU parallel job lists: a shell
// must run exactly the argv they were made from, and --parallel-args splits like a shell.
#include <gtest/gtest.h>

#include <cstdio>
#include <omnidso/cli/shell_words.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso {
namespace {

// What /bin/sh makes of `line`: its words, one per output line.
std::vector<std::string> wordsOfShell(const std::string& line) {
  const std::string command = "for w in " + line + "; do printf '%s\\n' \"$w\"; done";
  FILE* pipe = ::popen(("/bin/sh -c " + cli::shellQuote(command)).c_str(), "r");
  std::vector<std::string> words;
  std::string word;
  for (int c = std::fgetc(pipe); c != EOF; c = std::fgetc(pipe))
    c == '\n' ? (words.push_back(word), word.clear()) : word.push_back(static_cast<char>(c));
  ::pclose(pipe);
  return words;
}

const std::vector<std::string> kAwkwardArguments = {"/opt/omnidso/bin/omnidso",
                                                    "run",
                                                    "/data/my seq",
                                                    "it's",
                                                    "a\"b",
                                                    "$HOME",
                                                    "`id`",
                                                    "*",
                                                    "--set",
                                                    "photometric.huber=9",
                                                    "",
                                                    "x\\y"};

TEST(ShellWordsTest, AShellRunsExactlyTheQuotedArguments) {
  const std::string line = cli::shellCommandLine(kAwkwardArguments);
  EXPECT_EQ(wordsOfShell(line), kAwkwardArguments) << line;
  EXPECT_EQ(cli::splitShellWords(line, "--x"), kAwkwardArguments);
  EXPECT_EQ(cli::shellQuote("--keyframes=5"), "--keyframes=5");  // left readable
}

TEST(ShellWordsTest, SplitsParallelArgumentsLikeAShell) {
  EXPECT_EQ(
      cli::splitShellWords("  --sshloginfile 'my hosts'  --delay \"0.5\" -S a\\ b ", "--x"),
      (std::vector<std::string>{"--sshloginfile", "my hosts", "--delay", "0.5", "-S", "a b"}));
  EXPECT_TRUE(cli::splitShellWords("   ", "--x").empty());
  EXPECT_THROW(cli::splitShellWords("--sshlogin 'host", "--parallel-args"), Error);
}

}  // namespace
}  // namespace omnidso
