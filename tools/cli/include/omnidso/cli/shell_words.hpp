#pragma once
// Command lines as POSIX shell text, for the scripts and job lists omnidso ablate writes for
// Slurm and GNU parallel, and back: "--sshloginfile 'my hosts'" → {--sshloginfile, my hosts}.

#include <string>
#include <vector>

namespace omnidso::cli {

// 'text' with every ' written as '\'' — unless text needs no quoting ([A-Za-z0-9_./:=,+@%-]).
std::string shellQuote(const std::string& text);

// The arguments quoted and joined by spaces: a shell runs exactly argv.
std::string shellCommandLine(const std::vector<std::string>& argv);

// Splits at unquoted blanks, honouring '…', "…" (with \" and \\) and \x outside quotes; no
// expansions. Throws omnidso::Error naming `option` on an unclosed quote.
std::vector<std::string> splitShellWords(const std::string& text, const std::string& option);

}  // namespace omnidso::cli
