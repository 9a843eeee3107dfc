#include <cstdio>
#include <omnidso/cli/progress.hpp>

namespace omnidso::cli {

void printProgressBar(std::size_t done, std::size_t total, const std::string& detail) {
  constexpr std::size_t kBarWidth = 40;
  const std::size_t filled = total > 0 ? done * kBarWidth / total : kBarWidth;
  std::fprintf(stderr, "\r[%s%s] %zu/%zu  %s", std::string(filled, '#').c_str(),
               std::string(kBarWidth - filled, '.').c_str(), done, total, detail.c_str());
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

}  // namespace omnidso::cli
