#pragma once
// Where the control API's token comes from. `--token T` is visible to every user in `ps` and in shell
// history, so the daemon and the clients also take it from a file (`--token-file F`) or from the
// environment (MOCAPLABEL_TOKEN), which other users cannot read.
#include <filesystem>
#include <optional>
#include <string>

namespace mocap::capture {

inline constexpr const char* kTokenEnvironmentVariable = "MOCAPLABEL_TOKEN";

struct ControlTokenSources {
  std::string flag_token{};                  ///< --token (empty: not given)
  std::filesystem::path token_file{};        ///< --token-file (empty: not given)
  std::optional<std::string> environment{};  ///< the value of MOCAPLABEL_TOKEN when it is set
  /// Throws InputError when both --token and --token-file are given.
  void check() const;
};

/// The token: --token, else the first line of --token-file (surrounding whitespace removed), else
/// MOCAPLABEL_TOKEN; "" when none is given. Throws InputError for an unreadable or empty file, an empty
/// variable, or a token with whitespace or control characters (it travels in an HTTP header).
std::string ResolveControlToken(const ControlTokenSources& sources);

/// The sources of this process: the flags given and MOCAPLABEL_TOKEN from the environment.
ControlTokenSources TokenSourcesFromEnvironment(const std::string& flag_token, const std::string& token_file);

}  // namespace mocap::capture
