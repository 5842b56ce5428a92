#include "capture/daemon/control_token.h"

#include <cstdlib>
#include <fstream>
#include <iterator>

#include "core/check.h"

namespace mocap::capture {

void ControlTokenSources::check() const {
  if (!flag_token.empty() && !token_file.empty())
    throw InputError("--token and --token-file", "give one of them, not both");
}

namespace {

std::string Trimmed(const std::string& text) {
  const char* space = " \t\r\n";
  const size_t first = text.find_first_not_of(space);
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(space) - first + 1);
}

std::string ReadTokenFile(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError("--token-file " + file.string(), "cannot be read");
  std::string first_line;
  std::getline(in, first_line);
  const std::string token = Trimmed(first_line);
  if (token.empty()) throw InputError("--token-file " + file.string(), "has no token on its first line");
  return token;
}

// The token is sent as "Authorization: Bearer <token>": a space or a line break would break the header
// or be cut off by the server, so the client and the daemon would disagree silently.
void CheckTokenCharacters(const std::string& token, const std::string& where) {
  for (const char c : token)
    if (static_cast<unsigned char>(c) <= ' ' || c == 0x7f)
      throw InputError(where, "the token may not contain spaces or control characters");
}

}  // namespace

std::string ResolveControlToken(const ControlTokenSources& sources) {
  sources.check();
  if (!sources.flag_token.empty()) {
    CheckTokenCharacters(sources.flag_token, "--token");
    return sources.flag_token;
  }
  if (!sources.token_file.empty()) {
    const std::string token = ReadTokenFile(sources.token_file);
    CheckTokenCharacters(token, "--token-file " + sources.token_file.string());
    return token;
  }
  if (!sources.environment) return "";
  const std::string token = Trimmed(*sources.environment);
  if (token.empty()) throw InputError(kTokenEnvironmentVariable, "is set but empty: unset it or give the token");
  CheckTokenCharacters(token, kTokenEnvironmentVariable);
  return token;
}

ControlTokenSources TokenSourcesFromEnvironment(const std::string& flag_token, const std::string& token_file) {
  ControlTokenSources sources{.flag_token = flag_token, .token_file = token_file};
  if (const char* value = std::getenv(kTokenEnvironmentVariable)) sources.environment = value;
  return sources;
}

}  // namespace mocap::capture
