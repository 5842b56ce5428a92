#include "core/check.h"

#include <cstdio>
#include <cstdlib>

namespace mocap {

void CheckFailed(const char* file, int line, const char* expr, const std::string& message) {
  std::fprintf(stderr, "mocaplabel: internal error at %s:%d: check `%s` failed%s%s\n", file, line, expr,
               message.empty() ? "" : ": ", message.c_str());
  std::abort();
}

}  // namespace mocap
