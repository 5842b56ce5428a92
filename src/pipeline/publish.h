#pragma once
// Outputs published whole (DESIGN.md "Errors": never a partial output presented as complete): every
// command that writes a folder (label, validate, demo, export, relabel) writes it as <out>.partial and
// renames it to <out> only once it is complete. A killed run leaves <out>.partial, never an <out> that
// looks finished; an earlier output at <out> stays until the new one replaces it.
#include <filesystem>
#include <string>

namespace mocap::pipeline {

class PartialOutput {
 public:
  /// `marker`: the file every finished output of this kind holds (label_manifest.json, ...). Throws
  /// InputError when `out` exists and is neither empty nor an earlier output of this kind (`kind` names
  /// it in the message). Removes a .partial folder an earlier killed run left.
  PartialOutput(std::filesystem::path out, std::string marker, std::string kind);
  /// An output abandoned by an exception (bad input found mid-run) is removed: only a killed run leaves
  /// its .partial folder behind.
  ~PartialOutput();
  PartialOutput(const PartialOutput&) = delete;
  PartialOutput& operator=(const PartialOutput&) = delete;

  const std::filesystem::path& dir() const { return partial_; }  ///< where to write
  const std::filesystem::path& out() const { return out_; }

  /// Checks the marker is there, replaces an earlier output, renames the partial folder into place and
  /// rewrites the paths that runs nested in it recorded (run.json and the run manifests name their
  /// inputs by absolute path, and an input written inside this output has moved with it).
  void Publish();

 private:
  std::filesystem::path out_, partial_;
  std::string marker_, kind_;
  int exceptions_at_start_ = 0;
  bool published_ = false;
};

/// <out>.partial.
std::filesystem::path PartialPath(const std::filesystem::path& out);

/// Rewrites every string value of the JSON file that starts with `from` to start with `to` instead.
void RelocateJsonPaths(const std::filesystem::path& file, const std::string& from, const std::string& to);

}  // namespace mocap::pipeline
