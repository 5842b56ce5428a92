#pragma once
// Three-tier error policy (DESIGN.md "Errors"):
//  - MOCAP_CHECK: a broken invariant (a bug) aborts with file:line and the message.
//  - InputError: bad input (files, config, protocol bytes, CLI arguments) is thrown with what, where and
//    what would fix it; the CLI prints e.what() as one line and exits non-zero.
//  - Expected outcomes (a timeout, a missing marker, a rejected label) are values in results.
#include <sstream>
#include <stdexcept>
#include <string>

namespace mocap {

/// Bad input. `where` names the file and position (file:line, byte offset, frame index).
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& where, const std::string& what)
      : std::runtime_error(where.empty() ? what : where + ": " + what), where_(where) {}
  const std::string& where() const { return where_; }

 private:
  std::string where_;
};

[[noreturn]] void CheckFailed(const char* file, int line, const char* expr, const std::string& message);

/// Builds a message from stream-able parts: Str("frame ", i, " of ", n).
template <typename... Args>
std::string Str(const Args&... args) {
  std::ostringstream out;
  (out << ... << args);
  return out.str();
}

}  // namespace mocap

#define MOCAP_CHECK(expr, ...)                                                          \
  do {                                                                                  \
    if (!(expr)) ::mocap::CheckFailed(__FILE__, __LINE__, #expr, ::mocap::Str(__VA_ARGS__)); \
  } while (0)
