#!/usr/bin/env bash
# Builds and runs the fuzzers of tests/fuzz (docs/fuzzing.md).
#
#   tests/fuzz/fuzz.sh BUILD_DIR build [NAME...]            compile the fuzzers (all without NAME)
#   tests/fuzz/fuzz.sh BUILD_DIR run NAME [libFuzzer flags]  write its seeds, run one fuzzer
#   tests/fuzz/fuzz.sh BUILD_DIR all                         build, then run every fuzzer (make fuzz)
#   tests/fuzz/fuzz.sh sources                               the instrumented sources, one per line
#   tests/fuzz/fuzz.sh names                                 the fuzzers' names, one per line
#
# BUILD_DIR is a configured, built (not MOCAP_SANITIZE) build tree: its tests/fuzz/ holds compile_flags.rsp,
# link_libs.rsp and mocap_fuzz_seeds (tests/fuzz/CMakeLists.txt). Objects, fuzzers, seeds, corpora and
# crash reproducers go to BUILD_DIR/tests/fuzz/work. An object is recompiled when its source or a header it
# includes changed (clang's depfile), a fuzzer relinked when an object or a library it links changed.
# Environment:
#   CLANGXX           clang++ to use (default clang++)
#   FUZZ_SECONDS      run time of each fuzzer (default 10; make fuzz: 300)
#   FUZZ_JOBS         compiles and fuzzers at once (default 2)
#   FUZZ_OPT          optimisation of the instrumented objects: -O1 (default, make fuzz) or -O0 (ctest's
#                     brief runs: less compile time); each level has its own WORK/obj and WORK/bin
#   FUZZ_KEEP_CORPUS  1: grow and keep WORK/NAME/corpus across runs (make fuzz); else each run starts from
#                     the seeds alone, so a brief ctest run does the same work every time
set -euo pipefail

all_fuzzers=(bop tum motive plus session png yaml mesh)

# Instrumented sources of each fuzzer besides its harness tests/fuzz/fuzz_NAME.cc: the parsers the bytes
# reach. Everything else links uninstrumented from BUILD_DIR's libraries.
sources_of() {
  local import=(src/session/import/text_parse.cc src/core/text.cc)
  case $1 in
    bop) echo src/session/import/bop_scene.cc "${import[@]}" ;;
    tum) echo src/session/import/tum.cc "${import[@]}" ;;
    motive) echo src/session/import/motive_csv.cc "${import[@]}" ;;
    plus) echo src/session/import/plus_mha.cc "${import[@]}" ;;
    session) echo src/session/manifest.cc src/session/records.cc src/session/record_file.cc src/session/json_fields.cc \
                  src/session/reader.cc src/core/text.cc ;;
    png) echo src/session/png_gray16.cc ;;
    yaml) echo src/pipeline/yaml_read.cc src/pipeline/rig.cc src/pipeline/object_library.cc src/cli/scenario_yaml.cc \
                src/cli/pointer_yaml.cc ;;
    mesh) echo src/render/mesh_file_check.cc src/render/mesh_file_check_ply.cc src/render/mesh.cc src/core/text.cc ;;
    *) echo "fuzz.sh: no fuzzer '$1' (${all_fuzzers[*]})" >&2; return 1 ;;
  esac
}

if [[ ${1:-} == names ]]; then  # the one list of fuzzers (tests/fuzz/CMakeLists.txt reads it)
  printf '%s\n' "${all_fuzzers[@]}"
  exit 0
fi
if [[ ${1:-} == sources ]]; then  # every instrumented source once (tests/fuzz/CMakeLists.txt reads it)
  for name in "${all_fuzzers[@]}"; do sources_of "$name"; done | tr ' ' '\n' | sort -u
  exit 0
fi

source_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build_dir=$(cd "$1" && pwd)
command=$2
shift 2
fuzz_dir=$build_dir/tests/fuzz
work=$fuzz_dir/work
clang=${CLANGXX:-clang++}
jobs=${FUZZ_JOBS:-2}
opt=${FUZZ_OPT:--O1}
case $opt in
  -O1) obj_dir=$work/obj bin_dir=$work/bin ;;
  -O0) obj_dir=$work/obj-O0 bin_dir=$work/bin-O0 ;;
  *) echo "fuzz.sh: FUZZ_OPT is '$opt', not -O0 or -O1" >&2; exit 2 ;;
esac

# Longest input: the seeds are cut to about this size (make_seeds.cc).
max_len_of() {
  case $1 in
    motive | plus) echo 32768 ;;
    mesh) echo 36864 ;;
    png | yaml) echo 8192 ;;
    *) echo 16384 ;;
  esac
}

object_of() { echo "$obj_dir/${1//\//_}.o"; }

# True when TARGET is missing or any of the other files is newer than it or missing.
stale() {
  local target=$1 file
  shift
  [[ -e $target ]] || return 0
  for file in "$@"; do
    [[ -e $file && ! $file -nt $target ]] || return 0
  done
  return 1
}

# Compiles one source into its object unless that is newer than the source, every header its depfile
# lists and the compile flags.
# Temporary names carry the shell's pid: ctest runs several `run NAME` at once, and each rebuilds what
# is stale, so two may compile the same shared source (src/core/text.cc) at the same time.
compile() {
  local source=$1 object deps=()
  object=$(object_of "$source")
  if [[ -f $object.d ]]; then
    read -r -a deps <<< "$(sed -e 's/\\$//' -e 's/^[^:]*://' "$object.d" | tr '\n' ' ')"
    stale "$object" "${deps[@]}" "$source_dir/$source" "$fuzz_dir/compile_flags.rsp" || return 0
  fi
  echo "fuzz.sh: compiling $source" >&2
  "$clang" -std=c++20 "$opt" -gline-tables-only -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address,undefined \
    -fno-sanitize-recover=undefined -w @"$fuzz_dir/compile_flags.rsp" -I"$source_dir/tests/fuzz" \
    -MMD -MF "$object.d.tmp.$$" -c "$source_dir/$source" -o "$object.tmp.$$"
  mv "$object.tmp.$$" "$object"
  mv "$object.d.tmp.$$" "$object.d"
}

# Links a fuzzer unless it is newer than its objects, link_libs.rsp and the libraries that lists.
link() {
  local name=$1 fuzzer=$bin_dir/fuzz_$1 objects=() libs=() source
  for source in tests/fuzz/fuzz_$name.cc $(sources_of "$name"); do objects+=("$(object_of "$source")"); done
  read -r -a libs <<< "$(grep -E '^/.*\.(a|so[.0-9]*)$' "$fuzz_dir/link_libs.rsp" | tr '\n' ' ')"
  stale "$fuzzer" "${objects[@]}" "$fuzz_dir/link_libs.rsp" "${libs[@]}" || return 0
  echo "fuzz.sh: linking fuzz_$name" >&2
  "$clang" -fsanitize=fuzzer,address,undefined "${objects[@]}" @"$fuzz_dir/link_libs.rsp" -o "$fuzzer.tmp.$$"
  mv "$fuzzer.tmp.$$" "$fuzzer"
}

build() {
  local names=("$@") sources=() name
  [[ ${#names[@]} -gt 0 ]] || names=("${all_fuzzers[@]}")
  for name in "${names[@]}"; do
    sources+=(tests/fuzz/fuzz_$name.cc $(sources_of "$name"))
  done
  mkdir -p "$obj_dir" "$bin_dir"
  export -f compile link stale object_of sources_of
  export clang source_dir fuzz_dir work opt obj_dir bin_dir
  printf '%s\n' "${sources[@]}" | sort -u | xargs -P "$jobs" -I{} bash -c 'set -euo pipefail; compile "$1"' _ {}
  printf '%s\n' "${names[@]}" | xargs -P "$jobs" -I{} bash -c 'set -euo pipefail; link "$1"' _ {}
}

# Writes the seeds and runs one fuzzer for FUZZ_SECONDS from its corpus, the seeds and the reproducers of
# the bugs it found (tests/fuzz/regressions/NAME; libFuzzer runs every input there at the start); its
# exit status is the fuzzer's.
run() {
  local name=$1
  shift
  local dir=$work/$name
  rm -rf "$dir/seeds" "$dir/tmp"
  mkdir -p "$dir/seeds" "$dir/tmp" "$dir/corpus"
  [[ ${FUZZ_KEEP_CORPUS:-0} == 1 ]] || { rm -rf "$dir/corpus"; mkdir -p "$dir/corpus"; }
  "$fuzz_dir/mocap_fuzz_seeds" "$name" "$dir/seeds"
  TMPDIR=$dir/tmp ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1} \
    UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
    "$bin_dir/fuzz_$name" -max_total_time="${FUZZ_SECONDS:-10}" -max_len="$(max_len_of "$name")" -timeout=10 \
    -rss_limit_mb=2048 -malloc_limit_mb=512 -print_final_stats=1 -artifact_prefix="$dir/" "$@" "$dir/corpus" "$dir/seeds" \
    $(find "$source_dir/tests/fuzz/regressions/$name" -maxdepth 0 2>/dev/null)
}

case $command in
  build) build "$@" ;;
  run)
    name=$1
    shift
    sources_of "$name" > /dev/null
    build "$name"
    run "$name" "$@"
    ;;
  all)
    build
    export -f run max_len_of
    export work fuzz_dir source_dir bin_dir
    printf '%s\n' "${all_fuzzers[@]}" |
      xargs -P "$jobs" -I{} bash -c \
        'run "$1" > "$work/$1.log" 2>&1 && echo "fuzz_$1: ok" || echo "fuzz_$1: FAILED (see $work/$1.log)"' _ {} |
      tee "$work/summary.txt"
    ! grep -q FAILED "$work/summary.txt"
    ;;
  *) echo "usage: fuzz.sh BUILD_DIR build [NAME...] | run NAME [flags] | all" >&2; exit 2 ;;
esac
