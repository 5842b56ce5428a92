#pragma once
// Nesting depth of a JSON text, measured before parsing it: nlohmann's parser keeps a stack entry per
// open bracket and destroys nested values recursively, so a body of a million '[' costs hundreds of
// MB and can overflow the stack. A scan of brackets outside strings is linear and allocates nothing.
#include <string_view>

namespace mocap::capture {

/// Deepest nesting of [] and {} outside JSON strings (0 for a scalar). The scan stops as soon as
/// the depth exceeds stop_above_depth and returns that depth. Malformed text is the parser's
/// business: unbalanced brackets are not an error here.
int JsonNestingDepth(std::string_view text, int stop_above_depth);

}  // namespace mocap::capture
