#pragma once
// Dense indices for keys in order of first appearance (0, 1, 2, ...), found through an open-addressing
// table kept at most half full. The validator keys millions of points a second this way (voxel cells of a
// record's cloud, a mesh's surface samples); a node-based set or map allocated a node per key, which cost
// more than the work around it.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace mocap {

/// `Hash` must mix its low bits well: the table takes them as the slot.
template <typename Key, typename Hash>
class FirstSeenIndex {
 public:
  /// The index of `key` and whether it was new (it is in the index now).
  std::pair<uint32_t, bool> Insert(const Key& key) {
    if (2 * (keys_.size() + 1) > slots_.size()) Grow();
    size_t slot = Slot(key);
    for (; slots_[slot] != kEmpty; slot = (slot + 1) & (slots_.size() - 1))
      if (keys_[slots_[slot]] == key) return {slots_[slot], false};
    slots_[slot] = static_cast<uint32_t>(keys_.size());
    keys_.push_back(key);
    return {slots_[slot], true};
  }
  size_t size() const { return keys_.size(); }

 private:
  static constexpr uint32_t kEmpty = UINT32_MAX;
  size_t Slot(const Key& key) const { return static_cast<size_t>(Hash{}(key)) & (slots_.size() - 1); }
  void Grow() {
    slots_.assign(std::max<size_t>(1024, 2 * slots_.size()), kEmpty);
    for (size_t i = 0; i < keys_.size(); ++i) {
      size_t slot = Slot(keys_[i]);
      while (slots_[slot] != kEmpty) slot = (slot + 1) & (slots_.size() - 1);
      slots_[slot] = static_cast<uint32_t>(i);
    }
  }
  std::vector<Key> keys_;
  std::vector<uint32_t> slots_;
};

/// Fibonacci hashing with the high bits folded into the low ones.
inline uint64_t MixBits(uint64_t h) {
  h *= 0x9E3779B97F4A7C15ull;
  return h ^ (h >> 29);
}

}  // namespace mocap
