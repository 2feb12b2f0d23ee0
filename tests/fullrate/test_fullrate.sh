#!/usr/bin/env bash
# Full-rate logging test (issue 7): ucon-simulator (Mid-360 at 200 000 points/s over UDP,
# ROBOT_POSE 100 Hz, SIM_GROUND_TRUTH 50 Hz), ucon-lidar-driver (LIDAR_POINTS 50 Hz,
# LIDAR_IMU 200 Hz) and ucon-base-controller (BASE_WHEEL_CMD 100 Hz, BASE_STATUS 10 Hz) run as
# processes; ucon-fullrate-pub publishes the channels of the processes not run here
# (perception, planner, operator) at their nominal rates; ucon-logger records everything for
# DURATION seconds. Then every channel's sequence numbers must be complete in the log: the
# lost count per channel is printed (target 0) and any loss fails the test.
#
#   test_fullrate.sh BIN_DIR TEST_BIN_DIR [DURATION_S=60]
#
# UDP on 127.0.0.1 ports 27200-27241, LCM on udpm port 7820.
set -u
BIN=${1:?usage: test_fullrate.sh BIN_DIR TEST_BIN_DIR [DURATION_S]}
TBIN=${2:?}
DURATION=${3:-60}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
URL="udpm://239.255.76.67:7820?ttl=0"
# The logger asks for a 4 MiB socket receive buffer (LCM's recv_buf_size; the kernel caps it at
# net.core.rmem_max). With the default (rmem_default, ~208 KiB here = 60 ms of this traffic) a
# scheduling gap of the logger's receive thread on a loaded machine loses whole point clouds.
LOGGER_URL="${URL}&recv_buf_size=${UCON_LOGGER_RCVBUF:-4194304}"
tmp=$(mktemp -d /tmp/ucon_fullrate_XXXXXX)
pids=()
cleanup() {
  local p
  for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null; done
  [ -n "${KEEP:-}" ] && echo "kept $tmp" || rm -rf "$tmp"
}
trap cleanup EXIT
for exe in "$BIN/ucon-simulator" "$BIN/ucon-lidar-driver" "$BIN/ucon-logger" "$TBIN/ucon-fullrate-pub" \
           "$TBIN/ucon-fullrate-check"; do
  [ -x "$exe" ] || { echo "FAIL: $exe is not built"; exit 1; }
done

# Configs: the deployed ones with the Mid-360 ports moved into this test's range
# (56abc -> 272ac: 56000 -> 27200, 56101 -> 27211, 56401 -> 27241, ...).
mkdir -p "$tmp/cfg" "$tmp/logs"
for f in simulator lidar_driver base_controller logger; do
  sed -E 's/\b56([0-9])0([0-9])\b/272\1\2/g' "$ROOT/deploy/config/$f.yaml" >"$tmp/cfg/$f.yaml"
done

# Kernel UDP receive-buffer overflows (all sockets of this host; other users add noise).
rcvbuf_errors() { awk '/^Udp:/ { if (++n == 2) print $6 }' /proc/net/snmp; }
cpu_ticks() { awk '{print $14 + $15}' "/proc/$1/stat" 2>/dev/null || echo 0; }

"$BIN/ucon-logger" --config "$tmp/cfg/logger.yaml" --log-dir "$tmp/logs" --run-name fullrate \
  --lcm-url "$LOGGER_URL" >"$tmp/logger.out" 2>&1 &
logger=$!; pids+=("$logger")
sleep 1.5   # the logger subscribes before anyone publishes: every seq must start at 0 in the log

"$BIN/ucon-simulator" --config "$tmp/cfg/simulator.yaml" --scenario crossing --rate 1.0 --duration 0 \
  --lcm-url "$URL" >"$tmp/simulator.out" 2>&1 &
sim=$!; pids+=("$sim")
sleep 0.3
"$BIN/ucon-lidar-driver" --config "$tmp/cfg/lidar_driver.yaml" --lcm-url "$URL" >"$tmp/driver.out" 2>&1 &
driver=$!; pids+=("$driver")
groups="perception,planner,operator"
if [ -x "$BIN/ucon-base-controller" ]; then
  "$BIN/ucon-base-controller" --config "$tmp/cfg/base_controller.yaml" --backend lcm --lcm-url "$URL" \
    >"$tmp/base.out" 2>&1 &
  base=$!; pids+=("$base")
  procs="simulator, lidar driver, base controller"
else
  groups="$groups,base"; base=""
  procs="simulator, lidar driver"
fi
"$TBIN/ucon-fullrate-pub" --lcm-url "$URL" --groups "$groups" >"$tmp/pub.out" 2>"$tmp/pub.err" &
pub=$!; pids+=("$pub")
echo "recording for ${DURATION} s: processes $procs; synthetic $groups; logger -> $tmp/logs"

t0=$(date +%s%N); c0=$(cpu_ticks "$logger"); e0=$(rcvbuf_errors)
sleep "$DURATION"
t1=$(date +%s%N); c1=$(cpu_ticks "$logger"); e1=$(rcvbuf_errors)
for p in "$sim" "$driver" "$base" "$pub"; do
  [ -n "$p" ] || continue
  kill -0 "$p" 2>/dev/null || { echo "FAIL: a publisher (pid $p) died during the run"; tail -5 "$tmp"/*.out; exit 1; }
done
# Stop the publishers first (they finish their last message), then the logger.
for p in "$pub" "$base" "$driver" "$sim"; do [ -n "$p" ] && kill -INT "$p" 2>/dev/null; done
for p in "$pub" "$base" "$driver" "$sim"; do [ -n "$p" ] && wait "$p" 2>/dev/null; done
sleep 1.0
kill -INT "$logger"; wait "$logger"; rc=$?
[ $rc -eq 0 ] || { echo "FAIL: ucon-logger exited with $rc"; cat "$tmp/logger.out"; exit 1; }
hz=$(getconf CLK_TCK)
awk -v c=$((c1 - c0)) -v hz="$hz" -v ns=$((t1 - t0)) 'BEGIN { printf "logger CPU: %.1f %% of one core\n", 100 * c / hz / (ns / 1e9) }'
tail -1 "$tmp/logger.out"
echo "UDP receive-buffer errors on this host during the run: $((e1 - e0)) (/proc/net/snmp RcvbufErrors)"

required="LIDAR_POINTS,LIDAR_IMU,ROBOT_POSE,SIM_GROUND_TRUTH,BASE_WHEEL_CMD,BASE_STATUS,PERCEPTION_OBJECTS,PERCEPTION_STATIC,PLANNER_TRAJECTORY"
"$TBIN/ucon-fullrate-check" --log-dir "$tmp/logs" --published "$tmp/pub.out" --require "$required"
rc=$?
[ $rc -eq 0 ] && echo "PASS: no message lost" || echo "FAIL: messages lost or a channel below its nominal rate"
exit $rc
