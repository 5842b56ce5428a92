#!/usr/bin/env bash
# `make demo`: the whole tool on the simulated rig (`mocaplabel demo`: simulate the default scenario, record it
# through the capture daemon, label it, validate it, score the labels against the truth, contact sheet;
# docs/demo.md), then the parts of the pipeline that run on real recordings from ../shared/realdata. Set DEMO_FRAMES to simulate fewer frames.
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
echo "== 2. the simulated rig end to end: simulate, record through the capture daemon, label, validate, score (mocaplabel demo)"
"$bin" demo --out "$out/sim" --frames "${DEMO_FRAMES:-0}"

echo
echo "== 3. a real RGB-D recording with motion-capture ground truth (TUM fr1/desk): import, then info"
"$bin" import tum "$realdata/tum_fr1_desk_9frames" --out "$out/tum_session" >/dev/null
"$bin" info "$out/tum_session"

echo
echo "== 4. real scanned meshes and poses (BOP LM-O scene 2): import, then label with overlays"
"$bin" import bop "$realdata/bop_lmo_scene2/test/000002" --models "$realdata/bop_lmo_scene2/models" \
  --out "$out/bop_session" >/dev/null
"$bin" label "$out/bop_session" --out "$out/bop_labels" --overlay

echo
echo "outputs in $out: sim/ (demo.json, contact_sheet.png, simulated/ with truth/, session/, labels/, dataset/ (BOP)), tum_session/,"
echo "bop_session/, bop_labels/ (labels.jsonl, masks, overlays in bop_labels/bop/overlay/)"
