#include <unistd.h>

#include <omnidso/cli/staged_directory.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso::cli {
namespace fs = std::filesystem;

namespace {

// "runs/a/" names the directory "a": drop a trailing separator before taking the name.
fs::path withoutTrailingSeparator(const std::string& out) {
  fs::path path = fs::path(out).lexically_normal();
  if (path.filename().empty()) path = path.parent_path();
  return path;
}

}  // namespace

StagedDirectory::StagedDirectory(const std::string& out) : out_(withoutTrailingSeparator(out)) {
  const fs::path parent = out_.has_parent_path() ? out_.parent_path() : fs::path(".");
  staging_ = parent / ("." + out_.filename().string() + ".partial-" + std::to_string(::getpid()));
  std::error_code error;
  fs::remove_all(staging_, error);
  fs::create_directories(staging_, error);
  if (error) throw fileError(out, "cannot create the output directory: " + error.message());
}

StagedDirectory::~StagedDirectory() {
  std::error_code ignored;
  if (!committed_) fs::remove_all(staging_, ignored);
}

void StagedDirectory::commit() {
  std::error_code error;
  fs::create_directories(out_, error);
  if (error) throw fileError(out_.string(), "cannot create the output directory: " + error.message());
  for (const fs::directory_entry& entry : fs::directory_iterator(staging_)) {
    fs::rename(entry.path(), out_ / entry.path().filename(), error);
    if (error) {
      throw fileError((out_ / entry.path().filename()).string(),
                      "cannot move the output into place: " + error.message());
    }
  }
  fs::remove(staging_, error);
  committed_ = true;
}

}  // namespace omnidso::cli
