#pragma once
// Simulated sessions labelled by the mocaplabel binary, as a user makes them: `sim record` of the default
// scenario cut to a few frames (optionally another sensor), then `label` (packed masks by default).
#include <filesystem>
#include <string>
#include <vector>

namespace mocap::testing {

struct LabelledSession {
  std::filesystem::path dir, session, labels;
};

/// Records and labels a session under a fresh folder named `name`; gtest-fails on a failed command.
LabelledSession MakeLabelledSession(const std::string& name, int frames, const std::string& sensor = "kinect1");

/// Runs mocaplabel with `args`; returns the exit code and fills `output` (stdout + stderr).
int Mocaplabel(const std::vector<std::string>& args, std::string* output = nullptr);

}  // namespace mocap::testing
