#!/usr/bin/env bash
# Launcher tests: stop kills a process that ignores SIGINT after the grace period and leaves
# no orphans; a profile naming a missing process starts nothing and exits non-zero; respawn;
# host placement with --only / --except.
set -u
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
UCON="$ROOT/deploy/ucon"
tmp=$(mktemp -d)
export UCON_RUN_DIR="$tmp/run" UCON_TEST_MARKER="ucon-launcher-test-$$-$RANDOM"
URL="udpm://239.255.76.67:7803?ttl=0"
. "$ROOT/tests/lib/checks.sh"
count() { pgrep -f "$UCON_TEST_MARKER" | wc -l; }
cleanup() { pkill -KILL -f "$UCON_TEST_MARKER" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT

# 1. Stubborn process: SIGINT ignored, SIGKILL after the grace period, no orphans.
lcm-logger --lcm-url="$URL" -c PROC_STATUS -f "$tmp/procstat.lcm" >/dev/null 2>&1 &
spy=$!
"$UCON" start "$ROOT/tests/launcher/stubborn.profile" --detach --log-dir "$tmp/logs" --lcm-url "$URL" >/dev/null
sleep 2.5
kill -INT $spy 2>/dev/null; wait $spy 2>/dev/null
if [ -x "${UCON_BUILD_DIR:-$ROOT/build}/bin/ucon-procstat" ]; then
  check "PROC_STATUS is published and names the processes" 'grep -aq stubborn "$tmp/procstat.lcm"'
fi
check "both processes and the stubborn child run" '[ "$(count)" -ge 3 ]'
status=$("$UCON" status)
check "status lists the processes as running" \
  'echo "$status" | grep -q "stubborn .*running" && echo "$status" | grep -q "polite .*running"'
t0=$(date +%s%N)
"$UCON" stop --grace 2 > "$tmp/stop.out" 2>&1
t1=$(date +%s%N)
elapsed_ms=$(( (t1 - t0) / 1000000 ))
check "stop waited for the grace period (${elapsed_ms} ms >= 2000)" '[ $elapsed_ms -ge 1900 ]'
check "stop did not hang (${elapsed_ms} ms < 10000)" '[ $elapsed_ms -lt 10000 ]'
check "stop says it used SIGKILL on the stubborn one" 'grep -q "stubborn.*SIGKILL" "$tmp/stop.out" "$tmp/logs/supervisor.log"'
sleep 0.3
check "no process (nor child) left behind" '[ "$(count)" -eq 0 ]'
check "status says not running" '"$UCON" status | grep -q "not running"'

# 2. Missing executable: nothing starts, exit status 3, the message names it.
out=$("$UCON" start "$ROOT/tests/launcher/missing.profile" --detach --log-dir "$tmp/logs" 2>&1); rc=$?
check "missing process gives exit status 3 (got $rc)" '[ $rc -eq 3 ]'
check "the message names the missing process" 'echo "$out" | grep -q "ghost"'
sleep 0.3
check "nothing was started" '[ "$(count)" -eq 0 ]'

# 3. Respawn with back-off: a crashing process is restarted, with growing delays.
"$UCON" start "$ROOT/tests/launcher/respawn.profile" --detach --log-dir "$tmp/logs" >/dev/null
sleep 4
restarts=$(cat "$UCON_RUN_DIR/procs/crasher.restarts" 2>/dev/null || echo 0)
check "crashing process was respawned (restarts=$restarts)" '[ "$restarts" -ge 2 ]'
check "back-off keeps restarts low in 4 s (restarts=$restarts <= 4)" '[ "$restarts" -le 4 ]'
"$UCON" stop --grace 1 >/dev/null 2>&1
sleep 0.3
check "respawn profile stopped cleanly" '[ "$(count)" -eq 0 ]'

# 4. Unknown commands and profiles are clear errors.
"$UCON" frobnicate >/dev/null 2>&1; rc=$?
check "unknown command exits 2 (got $rc)" '[ $rc -eq 2 ]'
"$UCON" start no-such-profile >/dev/null 2>&1; rc=$?
check "unknown profile exits 2 (got $rc)" '[ $rc -eq 2 ]'

# 5. Host placement: --only / --except start the named groups or processes and no others;
# a name that is neither is an error that starts nothing.
placement="$ROOT/tests/launcher/placement.profile"
"$UCON" start "$placement" --only sensor --detach --log-dir "$tmp/logs" --lcm-url "$URL" >"$tmp/only.out" 2>&1
sleep 1
started=$(ls "$UCON_RUN_DIR"/procs/*.started 2>/dev/null | xargs -n 1 basename 2>/dev/null | xargs)
check "--only sensor starts sensorproc alone (started: $started)" '[ "$started" = "sensorproc.started" ]'
check "--only says what runs here" 'grep -q "on this host: sensorproc" "$tmp/only.out"'
check "--only with ttl=0 warns that nothing leaves the host" 'grep -q "warning: .*ttl 0" "$tmp/only.out"'
check "status shows the selection" '"$UCON" status | grep -q "(only: sensor)"'
check "one process runs" '[ "$(count)" -eq 1 ]'
"$UCON" stop --grace 1 >/dev/null 2>&1
"$UCON" start "$placement" --except sensor,logproc --detach --log-dir "$tmp/logs" \
  --lcm-url "udpm://239.255.76.67:7803?ttl=1" >"$tmp/except.out" 2>&1
sleep 1
started=$(ls "$UCON_RUN_DIR"/procs/*.started 2>/dev/null | xargs -n 1 basename 2>/dev/null | xargs)
check "--except sensor,logproc starts navproc alone (started: $started)" '[ "$started" = "navproc.started" ]'
check "--except with ttl=1 gives no ttl warning" '! grep -q "warning" "$tmp/except.out"'
check "no process of group main: the run says it goes on until stopped" \
  'grep -q "runs until deploy/ucon stop" "$tmp/except.out"'
"$UCON" stop --grace 1 >/dev/null 2>&1
sleep 0.3
out=$("$UCON" start "$placement" --only sensr --detach --log-dir "$tmp/logs" 2>&1); rc=$?
check "--only with an unknown name exits 2 (got $rc)" '[ $rc -eq 2 ]'
check "the message names the bad name and the profile's groups" \
  'echo "$out" | grep -q "sensr" && echo "$out" | grep -q "groups: sensor nav log"'
out=$("$UCON" start "$placement" --only nav --except navproc --detach --log-dir "$tmp/logs" 2>&1); rc=$?
check "a selection that leaves nothing exits 2 (got $rc)" '[ $rc -eq 2 ] && echo "$out" | grep -q "leave no process"'
sleep 0.3
check "nothing runs after the refused starts" '[ "$(count)" -eq 0 ]'

checks_done
