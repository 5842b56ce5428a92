#pragma once
// Shards: a session's work split into frame ranges (stage.h Shard) that run apart (on all cores, or as
// cluster jobs) and merge into the run one pass writes. Each shard is a whole run of its own, published
// whole with its own run.json (its `shard` field set); the merge checks that the shards cover the frames
// once each and read the same inputs, then writes the run a single pass would have written: labels.jsonl
// byte for byte, the frame files moved in place.
#include <filesystem>
#include <vector>

#include "pipeline/stage.h"

namespace mocap::pipeline {

/// `count` contiguous frame ranges covering [0, frames): the first frames % count get one frame more.
std::vector<Shard> SplitShards(int64_t frames, int count);
/// Where shard `shard` of the run at `out` is written: <out>.shards/NNN-of-MMM.
std::filesystem::path ShardDir(const std::filesystem::path& out, const Shard& shard);

/// Merges finished label-run shards into the label run at `out` (published whole). Throws InputError
/// when a shard is missing or unfinished, the ranges do not tile the frames, or the shards read
/// different inputs. The shard folders are emptied (their files moved) and removed.
void MergeLabelShards(const std::vector<std::filesystem::path>& shard_dirs, const std::filesystem::path& out);

/// Merges finished validation-run shards (of one label run) into the validation run at `out`:
/// validation.jsonl in the order one pass writes it, the summary and report made from the merged records.
void MergeValidationShards(const std::vector<std::filesystem::path>& shard_dirs, const std::filesystem::path& out);

}  // namespace mocap::pipeline
