#!/usr/bin/env bash
# Regenerates the golden replay outputs in tests/data/replay — deliberately: run it only when a
# change to the simulator, the driver, a node or a config is meant to change what the nodes
# publish, then review `git diff --stat tests/data` and commit the new files with that change.
#
#   scripts/regen-golden.sh [--build-dir DIR] [--scenario S] [--duration SECONDS]
#
# What it does: records the golden scenario in-process (ucon-sim-record, no LCM — the same
# bytes on every machine): simulator + lidar driver + perception + base controller in a closed
# loop, the base following a scripted minimum-jerk plan (so the robot's motion does not depend
# on the planner, and a planner change moves only planner.lcm). Then it replays every node this
# build has over the recording (ucon-replay --config-from-log; the planner consumes the
# recorded PERCEPTION_*), stores each node's outputs as tests/data/replay/<node>.lcm and writes
# MANIFEST (scenario, duration, nodes in the loop, per-channel digest of the recording).
# test_replay's ReplayGolden test reads MANIFEST, records the same run and compares.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${UCON_BUILD_DIR:-$ROOT/build}
SCENARIO=crossing
DURATION=2.0
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) BUILD=$2; shift ;;
    --scenario) SCENARIO=$2; shift ;;
    --duration) DURATION=$2; shift ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    *) echo "regen-golden: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
DATA=$ROOT/tests/data/replay

[ -f "$BUILD/CMakeCache.txt" ] || cmake -S "$ROOT" -B "$BUILD" -G Ninja >/dev/null
cmake --build "$BUILD" --target ucon-sim-record ucon-replay -j 2 >/dev/null
NODES=$("$BUILD/bin/ucon-replay" --list | paste -sd, -)
LOOP=$("$BUILD/bin/ucon-replay" --list | grep -Ex 'perception|base_controller' | paste -sd, -)
echo "regen-golden: scenario $SCENARIO, ${DURATION} s, nodes in the loop: $LOOP (+ scripted plan); replayed: $NODES"

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$BUILD/bin/ucon-sim-record" --out "$tmp/input.lcm" --scenario "$SCENARIO" --duration "$DURATION" \
  --nodes "$LOOP" --config-dir "$ROOT/deploy/config" --scenario-dir "$ROOT/deploy/scenarios" \
  --print-digest >"$tmp/record.txt"
grep -v '^input ' "$tmp/record.txt"

mkdir -p "$DATA" "$tmp/out"
{
  echo "# Golden replay outputs. Written by scripts/regen-golden.sh on $(date -u +%F) — do not edit by hand."
  echo "scenario $SCENARIO"
  echo "duration_s $DURATION"
  echo "nodes $LOOP"
  grep '^input ' "$tmp/record.txt"
} >"$tmp/MANIFEST"
for node in ${NODES//,/ }; do
  # A node that was in the loop must reproduce what it published there (--compare).
  cmp_args=()
  [[ ",$LOOP," == *",$node,"* ]] && cmp_args=(--compare "$tmp/input.lcm")
  "$BUILD/bin/ucon-replay" --node "$node" --in "$tmp/input.lcm" --out "$tmp/out/$node.lcm" --config-from-log \
    "${cmp_args[@]}" | sed 's/^/  /'
  echo "golden $node $node.lcm" >>"$tmp/MANIFEST"
done
# Everything succeeded: replace the old files.
rm -f "$DATA"/*.lcm
mv "$tmp"/out/*.lcm "$DATA"/
mv "$tmp/MANIFEST" "$DATA/MANIFEST"
echo "regen-golden: wrote $DATA:"
ls -l "$DATA"
if git -C "$ROOT" rev-parse >/dev/null 2>&1; then git -C "$ROOT" status --short -- tests/data; fi
