#include "pipeline/content_hash.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <xxhash.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <memory>
#include <vector>

#include "core/check.h"

namespace mocap::pipeline {
namespace {

constexpr size_t kBlockBytes = size_t{1} << 20;

std::string ToHex(XXH128_hash_t hash) {
  XXH128_canonical_t canonical;
  XXH128_canonicalFromHash(&canonical, hash);
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string hex(2 * sizeof(canonical.digest), '0');
  for (size_t i = 0; i < sizeof(canonical.digest); ++i) {
    hex[2 * i] = kDigits[canonical.digest[i] >> 4];
    hex[2 * i + 1] = kDigits[canonical.digest[i] & 0xF];
  }
  return hex;
}

struct StateDeleter {
  void operator()(XXH3_state_t* state) const { XXH3_freeState(state); }
};
using StatePtr = std::unique_ptr<XXH3_state_t, StateDeleter>;

StatePtr NewState() {
  StatePtr state(XXH3_createState());
  MOCAP_CHECK(state != nullptr, "XXH3_createState failed (out of memory)");
  MOCAP_CHECK(XXH3_128bits_reset(state.get()) == XXH_OK, "XXH3_128bits_reset failed");
  return state;
}

// Closes a file descriptor on every path out of HashFileXxh3.
struct FdCloser {
  int fd;
  ~FdCloser() { ::close(fd); }
};

}  // namespace

std::string HashFileXxh3(const std::filesystem::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw InputError(file.string(), Str("cannot open for hashing: ", std::strerror(errno)));
  const FdCloser closer{fd};
  // One block per thread, reused: allocating (and faulting in) 1 MiB per file made hashing a tree of
  // 4 KiB files 5x slower than reading it.
  thread_local std::vector<char> block(kBlockBytes);
  StatePtr state = NewState();
  while (true) {
    const ssize_t got = ::read(fd, block.data(), block.size());
    if (got == 0) break;
    if (got < 0) {
      if (errno == EINTR) continue;
      throw InputError(file.string(), Str("read error while hashing: ", std::strerror(errno)));
    }
    XXH3_128bits_update(state.get(), block.data(), static_cast<size_t>(got));
  }
  return ToHex(XXH3_128bits_digest(state.get()));
}

std::string HashBytesXxh3(std::string_view bytes) {
  return ToHex(XXH3_128bits(bytes.data(), bytes.size()));
}

std::optional<FileStat> StatFile(const std::filesystem::path& file) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
  FileStat out;
  out.size_bytes = static_cast<uint64_t>(st.st_size);
  out.mtime_ns = static_cast<int64_t>(st.st_mtim.tv_sec) * 1'000'000'000 + st.st_mtim.tv_nsec;
  out.inode = static_cast<uint64_t>(st.st_ino);
  return out;
}

bool RecentlyModified(const FileStat& stat) {
  const int64_t now_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                             std::chrono::system_clock::now().time_since_epoch())
                             .count();
  return now_ns - stat.mtime_ns < kRacyWindowNs;
}

std::string TreeDigest(std::vector<TreeEntry> entries) {
  std::sort(entries.begin(), entries.end(), [](const TreeEntry& a, const TreeEntry& b) {
    return a.relative_path < b.relative_path;
  });
  StatePtr state = NewState();
  static constexpr char kNul = '\0', kNewline = '\n';
  for (const TreeEntry& entry : entries) {
    XXH3_128bits_update(state.get(), entry.relative_path.data(), entry.relative_path.size());
    XXH3_128bits_update(state.get(), &kNul, 1);
    XXH3_128bits_update(state.get(), entry.hash.data(), entry.hash.size());
    XXH3_128bits_update(state.get(), &kNewline, 1);
  }
  return ToHex(XXH3_128bits_digest(state.get()));
}

}  // namespace mocap::pipeline
