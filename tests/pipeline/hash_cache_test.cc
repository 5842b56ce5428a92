#include <gtest/gtest.h>
#include <unistd.h>
#include <xxhash.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "core/check.h"
#include "pipeline/content_hash.h"
#include "pipeline/hash_cache.h"

namespace mocap::pipeline {
namespace {
namespace fs = std::filesystem;

class HashCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::path(::testing::TempDir()) /
            ("mocap_hash_cache_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    cache_dir_ = root_ / "cache";
  }
  void TearDown() override { fs::remove_all(root_); }

  // A file an hour old: older than the racy window, so its hash may be cached.
  fs::path WriteOld(const std::string& name, const std::string& bytes) {
    const fs::path file = root_ / name;
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    fs::last_write_time(file, fs::file_time_type::clock::now() - std::chrono::hours(1));
    return file;
  }

  fs::path root_, cache_dir_;
};

std::string OneShotHex(const std::string& bytes) {
  XXH128_canonical_t canonical;
  XXH128_canonicalFromHash(&canonical, XXH3_128bits(bytes.data(), bytes.size()));
  std::string hex;
  char digit[3];
  for (unsigned char byte : canonical.digest) {
    std::snprintf(digit, sizeof(digit), "%02x", byte);
    hex += digit;
  }
  return hex;
}

TEST_F(HashCacheTest, StreamingFileHashEqualsOneShotXxh3) {
  std::string bytes(2 * 1024 * 1024 + 12345, '\0');  // two full 1 MiB blocks and a partial one
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>((i * 2654435761u) >> 13);
  const fs::path file = WriteOld("big.bin", bytes);
  EXPECT_EQ(HashFileXxh3(file), OneShotHex(bytes));
  EXPECT_EQ(HashFileXxh3(file).size(), 32u);
  EXPECT_EQ(HashBytesXxh3("mocaplabel"), OneShotHex("mocaplabel"));
  EXPECT_EQ(HashFileXxh3(WriteOld("empty", "")), OneShotHex(""));
  try {
    HashFileXxh3(root_ / "nope");
    FAIL() << "missing file hashed";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), (root_ / "nope").string());
  }
}

TEST_F(HashCacheTest, SurvivesCorruptionAndDropsGoneFiles) {
  const fs::path file = WriteOld("f.bin", "payload");
  const FileStat stat = *StatFile(file);
  {
    HashCache cache(cache_dir_);
    cache.Hash(file, stat);
    EXPECT_EQ(cache.files_hashed(), 1);
  }
  {
    std::ofstream(HashCacheFile(cache_dir_), std::ios::app) << "garbage\tline\n\n";
    HashCache cache(cache_dir_);
    EXPECT_EQ(cache.Hash(file, stat), HashBytesXxh3("payload"));
    EXPECT_EQ(cache.files_hashed(), 0);
  }
  const fs::path gone = WriteOld("gone.bin", "x");
  {
    HashCache cache(cache_dir_);
    cache.Hash(gone, *StatFile(gone));
    fs::remove(gone);
  }
  EXPECT_EQ(HashCache(cache_dir_).entries(), 1u);
}

TEST_F(HashCacheTest, ConcurrentSavesMerge) {
  const fs::path a = WriteOld("a.bin", "a"), b = WriteOld("b.bin", "b");
  HashCache first(cache_dir_), second(cache_dir_);  // both loaded before either saves
  first.Hash(a, *StatFile(a));
  second.Hash(b, *StatFile(b));
  first.Save();
  second.Save();
  HashCache later(cache_dir_);
  later.Hash(a, *StatFile(a));
  later.Hash(b, *StatFile(b));
  EXPECT_EQ(later.files_hashed(), 0);
}

TEST_F(HashCacheTest, RecentlyModifiedFileIsHashedButNotCached) {
  const fs::path file = root_ / "fresh.bin";
  std::ofstream(file) << "fresh";
  HashCache cache(cache_dir_);
  EXPECT_EQ(cache.Hash(file, *StatFile(file)), HashBytesXxh3("fresh"));
  EXPECT_EQ(cache.Hash(file, *StatFile(file)), HashBytesXxh3("fresh"));
  EXPECT_EQ(cache.files_hashed(), 2);
  EXPECT_EQ(cache.entries(), 0u);
}

TEST_F(HashCacheTest, DefaultDirFollowsTheEnvironment) {
  ::setenv("MOCAPLABEL_CACHE_DIR", cache_dir_.c_str(), 1);
  EXPECT_EQ(DefaultHashCacheDir(), cache_dir_);
  ::unsetenv("MOCAPLABEL_CACHE_DIR");
  ::setenv("XDG_CACHE_HOME", root_.c_str(), 1);
  EXPECT_EQ(DefaultHashCacheDir(), root_ / "mocaplabel");
  ::unsetenv("XDG_CACHE_HOME");
}

}  // namespace
}  // namespace mocap::pipeline
