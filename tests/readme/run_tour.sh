#!/usr/bin/env bash
# Runs the README's tour (the fenced block between the "tour:begin" and "tour:end" markers) command by
# command, in order, as a user would from a checkout next to ../shared: each command must exit 0.
#   tests/readme/run_tour.sh SOURCE_DIR SHARED_DIR MOCAPLABEL WORK_DIR
# The work dir gets a checkout-like layout: WORK/repo (the working directory, with meshes/ and calib/
# linked from the source tree) beside WORK/shared (linked to SHARED_DIR), so the README's relative
# paths resolve, and `mocaplabel` resolves to the binary under test.
set -euo pipefail
source_dir=$(realpath "$1") shared_dir=$(realpath "$2") binary=$(realpath "$3") work=$4
rm -rf "$work"
mkdir -p "$work/repo" "$work/bin"
ln -s "$shared_dir" "$work/shared"
ln -s "$source_dir/meshes" "$work/repo/meshes"
ln -s "$source_dir/calib" "$work/repo/calib"
ln -s "$binary" "$work/bin/mocaplabel"
export PATH="$work/bin:$PATH"
# The block's lines; a trailing backslash continues a command on the next line.
commands=$(awk '/<!-- tour:begin -->/ {on = 1; next} /<!-- tour:end -->/ {on = 0} on && !/^```/' "$source_dir/README.md")
[[ -n $commands ]] || { echo "README.md: no tour block (<!-- tour:begin --> ... <!-- tour:end -->)"; exit 1; }
cd "$work/repo"
n=0
while IFS= read -r line; do
  command=$line
  while [[ $command == *\\ ]] && IFS= read -r next; do command="${command%\\}${next}"; done
  command=${command%%#*}  # the README's comments
  [[ -z ${command// } ]] && continue
  n=$((n + 1))
  echo "== tour step $n: $command"
  start=$SECONDS
  if ! bash -c "$command" > "$work/step$n.log" 2>&1; then
    echo "FAILED (exit $?): $command"
    tail -20 "$work/step$n.log"
    exit 1
  fi
  echo "   ok in $((SECONDS - start)) s"
done <<< "$commands"
echo "all $n tour steps succeeded"
