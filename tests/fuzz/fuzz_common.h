#pragma once
// Helpers shared by the fuzz harnesses (tests/fuzz/fuzz_*.cc, docs/fuzzing.md).
//
// Every harness feeds bytes to a parser the way a user's file reaches it and accepts exactly two
// outcomes: a value, or mocap::InputError. Anything else is a finding: a crash or sanitizer report, a
// hang (-timeout), a leak, or another exception escaping (it would reach the user without saying
// where the bad input is), which Unexpected() turns into an abort with the message.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/check.h"

namespace mocap::fuzz {

/// A scratch folder for this process under $TMPDIR (fuzz.sh points it into the build tree), removed at
/// exit. Harnesses whose parser takes a path write the input's bytes here once per input.
inline const std::filesystem::path& ScratchDir() {
  struct Scratch {
    std::filesystem::path dir;
    Scratch() : dir(std::filesystem::temp_directory_path() / ("mocap_fuzz_" + std::to_string(::getpid()))) {
      std::filesystem::create_directories(dir);
    }
    ~Scratch() {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  };
  static const Scratch scratch;
  return scratch.dir;
}

/// A fresh empty folder `name` in the scratch folder.
inline std::filesystem::path FreshDir(const std::string& name) {
  const std::filesystem::path dir = ScratchDir() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void WriteFile(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) {
    std::fprintf(stderr, "fuzz harness: cannot write %s\n", path.c_str());
    std::abort();
  }
}

/// `data` split at NUL bytes into at most `max_parts` parts (the last keeps any further NULs): one input
/// holds several files. Text files hold no NUL, so a seed is the files joined with '\0'.
inline std::vector<std::string_view> SplitParts(std::string_view data, size_t max_parts) {
  std::vector<std::string_view> parts;
  while (parts.size() + 1 < max_parts) {
    const size_t nul = data.find('\0');
    if (nul == std::string_view::npos) break;
    parts.push_back(data.substr(0, nul));
    data.remove_prefix(nul + 1);
  }
  parts.push_back(data);
  return parts;
}

/// A non-InputError exception escaped a parser: report it as a finding.
[[noreturn]] inline void Unexpected(const char* harness, const std::exception& e) {
  std::fprintf(stderr, "%s: exception other than InputError escaped: %s\n", harness, e.what());
  std::abort();
}

/// Runs `parse`; InputError is the expected answer to bad bytes, any other exception a finding.
template <typename Parse>
void ExpectValueOrInputError(const char* harness, Parse&& parse) {
  try {
    parse();
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    Unexpected(harness, e);
  }
}

}  // namespace mocap::fuzz
