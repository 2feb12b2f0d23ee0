#!/usr/bin/env bash
# ucon-foxglove-bridge during a live simulation: `deploy/ucon sim --foxglove` (the sim
# profile's foxglove line switched on), then @foxglove/ws-protocol's client (bridge_client.js:
# protocol, channels, decodable messages, read-only refusals, a stalled client's drops while
# another keeps receiving, unsubscribe). Also: the bridge listens on 127.0.0.1 only, answers a
# plain HTTP request with 426, refuses a WebSocket without the subprotocol, and stops cleanly
# on SIGINT; the run's own log (logger: LOG_METADATA, PROC_STATUS in wall clock) exports and
# reads back. Ports: LCM udpm 7901, TCP 27401.
set -u
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
UCON="$ROOT/deploy/ucon"
BUILD=${UCON_BUILD_DIR:-$ROOT/build}
export UCON_BUILD_DIR=$BUILD
export UCON_NODE_MODULES=${UCON_NODE_MODULES:-$BUILD/node/node_modules}
HERE="$ROOT/tests/foxglove"
if ! command -v node >/dev/null 2>&1; then
  echo "SKIP: node is not installed (the bridge test uses @foxglove/ws-protocol)"
  exit 77
fi
if [ ! -d "$UCON_NODE_MODULES/@foxglove/ws-protocol" ]; then
  echo "SKIP: npm packages missing in $UCON_NODE_MODULES: deploy/ucon test installs them"
  exit 77
fi
tmp=$(mktemp -d)
export UCON_RUN_DIR="$tmp/run"
URL="udpm://239.255.76.67:7901?ttl=0"
PORT=27401
. "$ROOT/tests/lib/checks.sh"
cleanup() { "$UCON" stop --grace 2 >/dev/null 2>&1; rm -rf "$tmp"; }
trap cleanup EXIT

# The pedestrians scenario with a round trip twice over, so that the run outlasts the client.
sed 's/goals: \[\[10.0, -5.0\]\]/goals: [[10.0, -5.0], [0.0, 0.0], [10.0, -5.0], [0.0, 0.0]]/' \
  "$ROOT/deploy/scenarios/pedestrians.yaml" >"$tmp/round_trip.yaml"
check "the test scenario has four goals" 'grep -q "goals: \[\[10.0, -5.0\], \[0.0, 0.0\]" "$tmp/round_trip.yaml"'
"$UCON" sim --scenario "$tmp/round_trip.yaml" --duration 60 --headless --detach --foxglove --foxglove-port $PORT \
  --log-dir "$tmp/logs" --lcm-url "$URL" >"$tmp/sim.out" 2>&1
rc=$?
cat "$tmp/sim.out"
check "deploy/ucon sim --foxglove --detach started (status $rc)" '[ $rc -eq 0 ]'
up=0
for _ in $(seq 1 100); do
  if (exec 3<>"/dev/tcp/127.0.0.1/$PORT") 2>/dev/null; then up=1; break; fi
  sleep 0.2
done
check "the bridge listens on port $PORT" '[ $up -eq 1 ]'
listen=$(ss -ltnH "sport = :$PORT" 2>/dev/null | awk '{print $4}')
check "it listens on 127.0.0.1 only (got '$listen')" '[ "$listen" = "127.0.0.1:$PORT" ]'

# A plain HTTP request: 426 with a hint; a WebSocket without the subprotocol: 400.
http=$(exec 3<>"/dev/tcp/127.0.0.1/$PORT"; printf 'GET / HTTP/1.1\r\nHost: x\r\n\r\n' >&3; timeout 5 head -n 1 <&3)
check "plain HTTP gets 426 Upgrade Required (got '${http%$'\r'}')" '[[ "$http" == "HTTP/1.1 426"* ]]'
ws=$(exec 3<>"/dev/tcp/127.0.0.1/$PORT"
     printf 'GET / HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n' >&3
     timeout 5 head -n 1 <&3)
check "a WebSocket without foxglove.websocket.v1 gets 400 (got '${ws%$'\r'}')" '[[ "$ws" == "HTTP/1.1 400"* ]]'

node "$HERE/bridge_client.js" --url "ws://127.0.0.1:$PORT" --seconds 4 >"$tmp/client.out" 2>&1
rc=$?
cat "$tmp/client.out"
check "the ws-protocol client's checks hold" '[ $rc -eq 0 ]'

"$UCON" stop --grace 5 >/dev/null 2>&1
blog="$tmp/logs/foxglove.log"
tail -n 5 "$blog" 2>/dev/null
check "the bridge stopped cleanly on SIGINT" 'grep -q "stopped: .* client connection" "$blog"'
check "the bridge logged no error" '! grep -q "\] error" "$blog"'
check "the bridge was not killed or restarted" \
  '! grep -q "foxglove (pid .*) ignored SIGINT" "$tmp/logs/supervisor.log" 2>/dev/null && [ ! -f "$UCON_RUN_DIR/procs/foxglove.restarts" ]'

# The run's own log: the logger's LOG_METADATA and the launcher's PROC_STATUS carry wall-clock
# utimes; exported and read back, they sit inside the run.
log=$(ls "$tmp"/logs/run_*_000.lcm 2>/dev/null | head -n 1)
check "the run was logged" '[ -n "$log" ]'
if [ -n "$log" ]; then
  "$BUILD/bin/ucon-mcap" "$log" -o "$tmp/run.mcap"
  rc=$?
  check "ucon-mcap exports the run's log (status $rc)" '[ $rc -eq 0 ]'
  node "$HERE/read_mcap.js" --log "$log" --mcap "$tmp/run.mcap" --no-views \
    --layout "$ROOT/deploy/foxglove/ucon-layout.json" >"$tmp/read.out" 2>&1
  rc=$?
  tail -n 5 "$tmp/read.out"
  check "the run's log reads back, with everything the shipped layout shows" '[ $rc -eq 0 ]'
fi
checks_done
