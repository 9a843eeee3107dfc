#pragma once
// The progress bar of the long-running subcommands (on stderr, only when it is a terminal):
//   [########................] 120/500  <detail>

#include <cstddef>
#include <string>

namespace omnidso::cli {

void printProgressBar(std::size_t done, std::size_t total, const std::string& detail);

}  // namespace omnidso::cli
