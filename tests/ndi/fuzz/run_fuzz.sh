#!/usr/bin/env bash
# Builds the NDI reply fuzzer with clang++ (-fsanitize=fuzzer,address,undefined) and runs it briefly
# on a seed corpus of valid replies. Called by ctest; usable by hand for longer runs:
#   tests/ndi/fuzz/run_fuzz.sh SOURCE_DIR WORK_DIR SEEDS_BIN [extra libFuzzer flags, e.g. -max_total_time=600]
set -euo pipefail
source_dir=$1 work_dir=$2 seeds_bin=$3
shift 3
clang=${CLANGXX:-clang++}
mkdir -p "$work_dir/corpus"
"$seeds_bin" "$work_dir/corpus"
fuzzer="$work_dir/ndi_fuzz_reply"
sources=("$source_dir/tests/ndi/fuzz/fuzz_reply.cc" "$source_dir/capture/ndi/reply.cc"
         "$source_dir/capture/ndi/tracking_reply.cc" "$source_dir/capture/ndi/crc.cc")
if [[ ! -x "$fuzzer" ]] || [[ -n $(find "${sources[@]}" "$source_dir/capture/ndi" -newer "$fuzzer" -name '*.[ch]*' | head -1) ]]; then
  "$clang" -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
    -I"$source_dir" -I"$source_dir/src" "${sources[@]}" -o "$fuzzer"
fi
"$fuzzer" -runs=${NDI_FUZZ_RUNS:-30000} -max_len=512 -timeout=5 "$@" "$work_dir/corpus"
