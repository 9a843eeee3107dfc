#pragma once
// Shared by the libFuzzer targets (fuzz/*_fuzzer.cc, `make fuzz`). Every reader takes a
// path, so each input is written to a file in this process's own scratch directory and the
// reader is called on it. The contract under test (docs/architecture.md, "Bad input"): a
// reader accepts the input or throws omnidso::Error. Any other exception escapes
// LLVMFuzzerTestOneInput and aborts, and a sanitizer report, an out-of-memory or a run past
// libFuzzer's -timeout are findings too.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <omnidso/core/error.hpp>
#include <unistd.h>

namespace omnidso::fuzz {

// /tmp/omnidso-fuzz-PID: one per process, so that parallel fuzzers (ctest --parallel,
// libFuzzer -jobs) never share a file.
inline const std::filesystem::path& scratchDir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path d = std::filesystem::temp_directory_path() /
                                    ("omnidso-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

// Writes the fuzzer's bytes to RELATIVE under scratchDir() (directories created) and
// returns the full path.
inline std::string writeInput(const std::string& relative, const std::uint8_t* data,
                              std::size_t size) {
  const std::filesystem::path path = scratchDir() / relative;
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path.string();
}

// Runs a reader: omnidso::Error is the clean refusal; everything else propagates.
template <typename Reader>
int readOrRefuse(Reader&& reader) {
  try {
    reader();
  } catch (const omnidso::Error&) {
  }
  return 0;
}

}  // namespace omnidso::fuzz
