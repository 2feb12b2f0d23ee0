#!/usr/bin/env bash
# End to end: `deploy/ucon sim` headless with every process of the sim profile (the goal is
# usually reached after 9-18 simulated seconds; the run is capped at 30). Asserts: goal reached, no collision, every process alive until the mission
# ended it (none exited or respawned), the log written and replayable, the picture drawn.
set -u
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
UCON="$ROOT/deploy/ucon"
BUILD=${UCON_BUILD_DIR:-$ROOT/build}
tmp=$(mktemp -d)
export UCON_RUN_DIR="$tmp/run"
URL="udpm://239.255.76.67:7960?ttl=0"
. "$ROOT/tests/lib/checks.sh"
cleanup() { "$UCON" stop --grace 1 >/dev/null 2>&1; rm -rf "$tmp"; }
trap cleanup EXIT

"$UCON" sim --scenario pedestrians --duration 30 --headless --log-dir "$tmp/logs" --lcm-url "$URL" \
  >"$tmp/sim.out" 2>&1
rc=$?
tail -n 15 "$tmp/sim.out"
check "deploy/ucon sim exits 0 (mission succeeded), got $rc" '[ $rc -eq 0 ]'
check "summary says all goals reached" 'grep -q "all goals reached" "$tmp/sim.out"'
check "summary JSON: success, no collision" \
  'grep -q "\"success\": true" "$tmp/logs/summary.json" && grep -q "\"collisions\": 0" "$tmp/logs/summary.json"'
check "the run ended because the mission finished" 'grep -q "mission finished (status 0)" "$UCON_RUN_DIR/last_stop_reason"'
for p in simulator lidar_driver odometry perception planner base_controller logger; do
  check "$p was started" '[ -f "$UCON_RUN_DIR/procs/$p.started" ]'
  check "$p never exited or restarted before the end" \
    '[ ! -f "$UCON_RUN_DIR/procs/$p.exited" ] && [ ! -f "$UCON_RUN_DIR/procs/$p.restarts" ]'
done
log=$(ls "$tmp"/logs/run_*_000.lcm 2>/dev/null | head -n 1)
check "a log was written" '[ -n "$log" ] && [ -s "$log" ]'
if [ -n "$log" ]; then
  summary=$("$BUILD/bin/ucon-logdump" "$log" --summary 2>&1)
  for ch in LOG_METADATA LIDAR_POINTS ROBOT_POSE ODOMETRY_STATUS PERCEPTION_OBJECTS PLANNER_TRAJECTORY BASE_WHEEL_CMD SIM_GROUND_TRUTH; do
    check "log holds $ch" 'echo "$summary" | grep -q "^$ch "'
  done
  for node in perception planner base_controller odometry; do
    "$BUILD/bin/ucon-replay" --node $node --in "$log" --out "$tmp/$node.a.lcm" --config-from-log >"$tmp/replay.out" 2>&1
    r1=$?
    "$BUILD/bin/ucon-replay" --node $node --in "$log" --out "$tmp/$node.b.lcm" --config-from-log >/dev/null 2>&1
    check "ucon-replay --node $node runs on the recorded log (status $r1)" '[ $r1 -eq 0 ]'
    check "replaying $node twice gives identical bytes" 'cmp -s "$tmp/$node.a.lcm" "$tmp/$node.b.lcm"'
  done
  check "a picture of the run was drawn" '[ -s "${log%_000.lcm}.png" ]'
  check "the odometry's accuracy was printed" 'grep -q "ucon: odometry: .*RPE\|ucon: odometry: .*final drift" "$tmp/sim.out"'
fi
checks_done
