#pragma once
// Port-handle setup of reference ndi-combined-api.md §4, steps 2-5: free stale handles, request a
// handle and upload the .rom for each passive tool, initialise, then enable every handle.
#include <string>
#include <utility>
#include <vector>

#include "capture/ndi/client.h"
#include "capture/ndi/link.h"

namespace mocap::ndi {

struct EnabledHandle {
  int handle = 0;
  std::string name;
};

/// Runs the setup on an initialised tracker; returns the enabled handles in tool order (tools with a
/// .rom first take their requested handles; tools without one take the remaining handles in PHSR
/// order; with no tools at all every handle is enabled as "handle-XX"). Throws ReplyError from the
/// tracker, InputError when a .rom cannot be read or there are fewer handles than tools.
std::vector<EnabledHandle> SetupTools(Link& link, const std::vector<ToolSpec>& tools, int timeout_ms);

/// "handle-0A".
std::string DefaultHandleName(int handle);

}  // namespace mocap::ndi
