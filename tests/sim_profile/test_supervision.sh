#!/usr/bin/env bash
# Supervision through the launcher with the real processes: kill -9 of a respawnable process
# (lidar driver, then logger) -> it is running again within 2 s, `deploy/ucon status` shows the
# restart, and the new instance works (the driver configures the emulated Mid-360 again and
# LIDAR_POINTS flow; the new logger writes a new file); a process that crashes at every start is
# restarted with growing delays (back-off) while the others keep running; stop leaves nothing.
#
#   test_supervision.sh BUILD_DIR
#
# LCM on udpm port 7821; UDP on 127.0.0.1 ports 27250-27291.
set -u
BUILD=${1:?usage: test_supervision.sh BUILD_DIR}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
UCON="$ROOT/deploy/ucon"
tmp=$(mktemp -d /tmp/ucon_supervision_XXXXXX)
export UCON_BUILD_DIR="$BUILD" UCON_RUN_DIR="$tmp/run" UCON_TEST_CFG="$tmp/cfg"
URL="udpm://239.255.76.67:7821?ttl=0"
. "$ROOT/tests/lib/checks.sh"
pidof_proc() { cat "$UCON_RUN_DIR/procs/$1.pid" 2>/dev/null; }
alive() { [ -n "${1:-}" ] && kill -0 "$1" 2>/dev/null; }
cleanup() {
  "$UCON" stop --grace 2 >/dev/null 2>&1
  local f
  for f in "$UCON_RUN_DIR"/procs/*.pid; do [ -f "$f" ] && kill -KILL -- "-$(cat "$f")" 2>/dev/null; done
  [ -n "${KEEP:-}" ] && echo "kept $tmp" || rm -rf "$tmp"
}
trap cleanup EXIT

for exe in ucon-simulator ucon-lidar-driver ucon-base-controller ucon-logger; do
  [ -x "$BUILD/bin/$exe" ] || { echo "FAIL: $BUILD/bin/$exe is not built"; exit 1; }
done
# Deployed configs with this test's UDP ports (Mid-360 defaults 56000..56401 -> 27250..27291).
mkdir -p "$UCON_TEST_CFG"
for f in simulator lidar_driver base_controller logger; do
  sed -E -e 's/\b56000\b/27250/g' -e 's/\b56100\b/27260/g' -e 's/\b56101\b/27261/g' \
         -e 's/\b56300\b/27280/g' -e 's/\b56301\b/27281/g' -e 's/\b56400\b/27290/g' -e 's/\b56401\b/27291/g' \
         "$ROOT/deploy/config/$f.yaml" >"$UCON_TEST_CFG/$f.yaml"
done

# Waits until process $1 runs with a pid other than $2; prints the elapsed ms (or "timeout").
wait_back() {
  local name=$1 old=$2 t0 p
  t0=$(date +%s%N)
  while [ $(( ($(date +%s%N) - t0) / 1000000 )) -lt 5000 ]; do
    p=$(pidof_proc "$name")
    if [ -n "$p" ] && [ "$p" != "$old" ] && alive "$p"; then
      echo $(( ($(date +%s%N) - t0) / 1000000 )); return
    fi
    sleep 0.02
  done
  echo timeout
}

"$UCON" start "$ROOT/tests/sim_profile/supervised.profile" --detach --log-dir "$tmp/logs" --lcm-url "$URL" >/dev/null
sleep 3
status=$("$UCON" status)
for n in simulator lidar_driver base_controller logger; do
  check "$n is running after start" 'echo "$status" | grep -Eq "^$n +[0-9]+ +running"'
done
check "the driver configured the emulated Mid-360" 'grep -q "configured after" "$tmp/logs/lidar_driver.log"'

# 1. kill -9 the lidar driver.
old=$(pidof_proc lidar_driver)
kill -KILL "$old"
ms=$(wait_back lidar_driver "$old")
check "lidar_driver is back after kill -9 within 2 s (${ms} ms)" '[ "$ms" != timeout ] && [ "$ms" -lt 2000 ]'
sleep 2.5
status=$("$UCON" status)
echo "$status"
check "status shows lidar_driver running with 1 restart" 'echo "$status" | grep -Eq "^lidar_driver +[0-9]+ +running +1 "'
check "the respawned driver configured the sensor again" '[ "$(grep -c "configured after" "$tmp/logs/lidar_driver.log")" -ge 2 ]'
check "the events file records the kill and the respawn" \
  'grep -q "exited with status 137" "$UCON_RUN_DIR/procs/lidar_driver.events" && grep -q "respawn #1" "$UCON_RUN_DIR/procs/lidar_driver.events"'

# 2. kill -9 the logger: back within 2 s, and the new instance records into a new file.
old=$(pidof_proc logger)
files_before=$(ls "$tmp/logs"/*.lcm 2>/dev/null | wc -l)
kill -KILL "$old"
ms=$(wait_back logger "$old")
check "logger is back after kill -9 within 2 s (${ms} ms)" '[ "$ms" != timeout ] && [ "$ms" -lt 2000 ]'
sleep 2
files_after=$(ls "$tmp/logs"/*.lcm 2>/dev/null | wc -l)
check "the new logger writes a new log file ($files_before -> $files_after)" '[ "$files_after" -gt "$files_before" ]'
newest=$(ls -t "$tmp/logs"/*.lcm | head -1)
check "LIDAR_POINTS flow into the new logger's file (driver respawned earlier works)" \
  '"$BUILD/bin/ucon-logdump" "$newest" --summary 2>/dev/null | grep -Eq "^LIDAR_POINTS +[1-9]"'
status=$("$UCON" status)
check "status shows logger running with 1 restart" 'echo "$status" | grep -Eq "^logger +[0-9]+ +running +1 "'

# 3. The crash loop: restarts are spaced by a growing delay; the rest keeps running.
restarts=$(cat "$UCON_RUN_DIR/procs/crasher.restarts" 2>/dev/null || echo 0)
check "the crashing process was respawned but backed off ($restarts restarts in ~10 s, 2..6)" \
  '[ "$restarts" -ge 2 ] && [ "$restarts" -le 6 ]'
gaps=$(grep "respawn #" "$UCON_RUN_DIR/procs/crasher.events" | awk '{ split($2, t, ":"); s = t[1]*3600 + t[2]*60 + t[3];
  if (NR > 1) printf "%d ", s - prev; prev = s }')
echo "crasher: delays between respawns (s): $gaps"
check "the delays grow (back-off): $gaps" \
  'echo "$gaps" | awk "{ ok = NF >= 2; for (i = 2; i <= NF; i++) if (\$i < \$(i-1)) ok = 0; if (\$NF < 2) ok = 0; exit !ok }"'
status=$("$UCON" status)
for n in simulator lidar_driver base_controller logger; do
  check "$n still running during the crash loop" 'echo "$status" | grep -Eq "^$n +[0-9]+ +running"'
done

# 4. Stop: nothing is left.
pids=""
for f in "$UCON_RUN_DIR"/procs/*.pid; do pids="$pids $(cat "$f")"; done
"$UCON" stop --grace 3 >/dev/null 2>&1
sleep 0.3
left=0
for p in $pids; do alive "$p" && left=$((left + 1)); done
check "stop leaves no process behind ($left left)" '[ $left -eq 0 ]'

# 5. As systemd runs it (deploy/systemd/ucon-robot.service): the launcher in the foreground,
#    SIGTERM to it alone -> every process stops, exit status 0.
"$UCON" start "$ROOT/tests/sim_profile/supervised.profile" --log-dir "$tmp/logs2" --lcm-url "$URL" --grace 3 \
  >"$tmp/fg.out" 2>&1 &
fg=$!
sleep 2.5
pids=""
for f in "$UCON_RUN_DIR"/procs/*.pid; do pids="$pids $(cat "$f")"; done
kill -TERM "$fg"
wait "$fg"; rc=$?
left=0
for p in $pids; do alive "$p" && left=$((left + 1)); done
check "foreground launcher stopped by SIGTERM: exit 0 (got $rc), no process left ($left)" '[ $rc -eq 0 ] && [ $left -eq 0 ]'
check "it says why it stopped" 'grep -q "stop requested" "$tmp/fg.out"'

checks_done
