#!/usr/bin/env bash
# `make demo`: runs the parts of the pipeline that exist today end to end, on real recordings from
# ../shared/realdata and on the simulated rig's scenario. The full simulated-rig demo (`mocaplabel demo`:
# simulate, record through the capture daemon, label, validate, score against the truth) is not built yet.
set -euo pipefail
bin=${1:?usage: demo.sh MOCAPLABEL OUT_DIR}
out=${2:?usage: demo.sh MOCAPLABEL OUT_DIR}
root=$(cd "$(dirname "$0")/.." && pwd)
realdata=${MOCAP_REALDATA:-$root/../shared/realdata}
rm -rf "$out"
mkdir -p "$out"

echo "== 1. headless rendering check (mocaplabel doctor)"
"$bin" doctor

echo
echo "== 2. a real RGB-D recording with motion-capture ground truth (TUM fr1/desk): import, then info"
"$bin" import tum "$realdata/tum_fr1_desk_9frames" --out "$out/tum_session" >/dev/null
"$bin" info "$out/tum_session"

echo
echo "== 3. real scanned meshes and poses (BOP LM-O scene 2): import, then label with overlays"
"$bin" import bop "$realdata/bop_lmo_scene2/test/000002" --models "$realdata/bop_lmo_scene2/models" \
  --out "$out/bop_session" >/dev/null
"$bin" label "$out/bop_session" --out "$out/bop_labels" --overlay

echo
echo "== 4. the simulated rig's default scenario: objects, motions and tracker streams"
"$bin" sim check --objects "$root/meshes/objects.yaml"

echo
echo "outputs in $out: tum_session/, bop_session/, bop_labels/ (labels.jsonl, masks, overlays in bop_labels/bop/overlay/)"
