#pragma once
// Runs the command block of a doc as a user types it into one shell, so the doc and its test cannot
// drift apart: the block follows a marker line `<!-- tour: ... -->` in a ```sh fence. Each line is one
// command: `NAME=value` alone is a variable (the runner's own values win), `... &` runs in the
// background and is waited for until it prints its first line (where it listens), `kill %N ...` stops
// those with SIGTERM and expects exit 0, `mocaplabel ...` runs the binary under test, anything else
// goes to /bin/sh. Variables ($T) are substituted, and so are the replacements given (a fixed port
// of the doc by a free one). Test support only.
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "process.h"

namespace mocap::testing {

/// The command lines of the block after `marker` in `doc` (comments and blank lines dropped, `\`
/// continuations joined). Throws std::runtime_error when the marker or the fence is missing.
std::vector<std::string> ReadTourCommands(const std::filesystem::path& doc, const std::string& marker);

struct TourOptions {
  std::string mocaplabel;                        ///< the binary standing for `mocaplabel`
  std::map<std::string, std::string> variables;  ///< $NAME -> value
  std::map<std::string, std::string> replace;    ///< text -> text, in commands and in `files` after each command
  std::vector<std::filesystem::path> files;      ///< files the replacements also apply to (a copied rig)
  std::filesystem::path log_dir;                 ///< one log per command: NN.log
  int timeout_s = 120;                           ///< per foreground command
};

class TourRunner {
 public:
  explicit TourRunner(TourOptions options) : options_(std::move(options)) {}
  /// Runs one line; throws std::runtime_error (with the command's log) when it fails.
  void Run(const std::string& line);
  /// What a foreground command printed on stdout, by its index in the run.
  const std::vector<std::string>& outputs() const { return outputs_; }

 private:
  std::string Substitute(std::string text) const;
  void PatchFiles() const;
  void Kill(const std::vector<std::string>& jobs);
  void Spawn(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env, bool background,
             const std::string& line);

  TourOptions options_;
  std::vector<std::unique_ptr<ChildProcess>> background_;
  std::vector<std::string> outputs_;
  int count_ = 0;
};

}  // namespace mocap::testing
