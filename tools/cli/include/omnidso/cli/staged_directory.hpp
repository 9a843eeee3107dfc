#pragma once
// An output directory that appears complete or not at all: files are written into a hidden
// sibling `.NAME.partial-PID` and moved into NAME by commit(); if commit() is never reached
// (an error, a bad ground-truth file found at the end of a run) the sibling is removed and
// NAME is as it was — no partly written --out. Moves are rename(2) within one parent
// directory, so each file replaces its old version atomically.

#include <filesystem>
#include <string>

namespace omnidso::cli {

class StagedDirectory {
 public:
  // Creates the staging directory now, so that an unwritable --out fails before the work.
  explicit StagedDirectory(const std::string& out);
  ~StagedDirectory();
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  // Where to write: the staging directory.
  std::string path() const { return staging_.string(); }
  // Moves every staged file into the output directory (created if needed).
  void commit();

 private:
  std::filesystem::path out_;
  std::filesystem::path staging_;
  bool committed_ = false;
};

}  // namespace omnidso::cli
