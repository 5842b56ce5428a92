#include "capture/ndi/tool_setup.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "core/check.h"

namespace mocap::ndi {
namespace {

constexpr int kMaxPinitRounds = 3;  // wired tools can appear after the first round (§4)

std::vector<uint8_t> ReadRom(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path, "cannot open the tool definition (.rom) file");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (bytes.empty()) throw InputError(path, "tool definition (.rom) file is empty");
  if (bytes.size() > 0xFFFF) throw InputError(path, Str("tool definition is ", bytes.size(), " bytes, more than PVWR can address"));
  return bytes;
}

std::vector<HandleInfo> QueryHandles(Link& link, HandleQuery query, int timeout_ms) {
  const std::string command = PhsrCommand(query);
  const std::string text = link.Command(command, timeout_ms);
  Parsed<std::vector<HandleInfo>> handles = ParsePhsr(text);
  if (!handles.ok()) throw ReplyError(ReplyError::Kind::kMalformed, 0, command + ": " + handles.error.ToString());
  return std::move(*handles.value);
}

int RequestPassiveHandle(Link& link, const std::string& rom_path, int timeout_ms) {
  const std::string command = PhrqPassiveCommand();
  const Parsed<int> handle = ParseHandleReply(link.Command(command, timeout_ms));
  if (!handle.ok()) throw ReplyError(ReplyError::Kind::kMalformed, 0, command + ": " + handle.error.ToString());
  const std::vector<uint8_t> rom = ReadRom(rom_path);
  for (size_t address = 0; address < rom.size(); address += kPvwrChunkBytes) {
    const size_t size = std::min<size_t>(kPvwrChunkBytes, rom.size() - address);
    link.Command(PvwrCommand(*handle.value, static_cast<int>(address), std::span(rom).subspan(address, size)), timeout_ms);
  }
  return *handle.value;
}

}  // namespace

std::string DefaultHandleName(int handle) {
  char name[16];
  std::snprintf(name, sizeof(name), "handle-%02X", handle & 0xFF);
  return name;
}

std::vector<EnabledHandle> SetupTools(Link& link, const std::vector<ToolSpec>& tools, int timeout_ms) {
  for (const HandleInfo& stale : QueryHandles(link, HandleQuery::kToBeFreed, timeout_ms))
    link.Command(PhfCommand(stale.handle), timeout_ms);
  std::vector<std::pair<int, const ToolSpec*>> requested;
  for (const ToolSpec& tool : tools)
    if (!tool.rom_path.empty()) requested.emplace_back(RequestPassiveHandle(link, tool.rom_path, timeout_ms), &tool);
  for (int round = 0; round < kMaxPinitRounds; ++round) {
    const std::vector<HandleInfo> uninitialised = QueryHandles(link, HandleQuery::kUninitialised, timeout_ms);
    if (uninitialised.empty()) break;
    for (const HandleInfo& h : uninitialised) link.Command(PinitCommand(h.handle), timeout_ms);
  }
  std::vector<const ToolSpec*> wired;
  for (const ToolSpec& tool : tools)
    if (tool.rom_path.empty()) wired.push_back(&tool);
  std::vector<EnabledHandle> enabled;
  size_t next_wired = 0;
  for (const HandleInfo& h : QueryHandles(link, HandleQuery::kUnenabled, timeout_ms)) {
    const auto own = std::find_if(requested.begin(), requested.end(), [&](const auto& r) { return r.first == h.handle; });
    const ToolSpec* tool = own != requested.end() ? own->second
                           : next_wired < wired.size() ? wired[next_wired++] : nullptr;
    if (tool == nullptr && !tools.empty()) continue;  // a handle nobody asked for stays disabled
    link.Command(PenaCommand(h.handle, tool ? tool->mode : ToolMode::kDynamic), timeout_ms);
    enabled.push_back({h.handle, tool ? tool->name : DefaultHandleName(h.handle)});
  }
  if (next_wired < wired.size())
    throw InputError("tools", Str(wired.size(), " tools without a .rom file, but the tracker has only ", next_wired,
                                  " further port handles"));
  // Report in tool order, so samples list bodies as the caller listed them.
  std::stable_sort(enabled.begin(), enabled.end(), [&](const EnabledHandle& a, const EnabledHandle& b) {
    auto rank = [&](const std::string& name) {
      for (size_t i = 0; i < tools.size(); ++i)
        if (tools[i].name == name) return i;
      return tools.size();
    };
    return rank(a.name) < rank(b.name);
  });
  return enabled;
}

}  // namespace mocap::ndi
