#pragma once
// The live page's files (capture/daemon/page), compiled into the daemon by page/embed.cmake: plain
// HTML, CSS and JavaScript, no build step and nothing fetched from elsewhere (docs/live-page.md).
#include <span>
#include <string_view>

namespace mocap::capture {

struct PageAsset {
  const char* path;          ///< "/" for index.html, else "/<file>"
  const char* content_type;
  std::string_view body;
};

std::span<const PageAsset> PageAssets();

}  // namespace mocap::capture
