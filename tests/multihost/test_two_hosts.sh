#!/usr/bin/env bash
# Two computers on one machine: network namespaces ucon-hostsA-<pid> and ucon-hostsB-<pid>
# joined by a veth pair (10.213.76.1/24 and 10.213.76.2/24), each with its multicast route
# (224.0.0.0/4) on the veth. Host A runs the simulator and the Mid-360 driver (they talk raw
# UDP to each other, as the real sensor and driver do), `deploy/ucon sim --only sim,sensor`;
# host B runs odometry, perception, planner, base controller, logger and mission,
# `deploy/ucon sim --except sim,sensor`. LCM udpm with ttl=1 carries everything between them.
# Asserts: the mission reaches its goals without collision, each host ran its own processes
# and no others, none restarted, and LCM traffic crossed the veth both ways (points and
# ground truth A->B, wheel commands B->A, by the veth's counters and host B's log).
# Needs root and iproute2 (CI runs as root); otherwise skipped (exit 77).
set -u
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
UCON="$ROOT/deploy/ucon"
BUILD=${UCON_BUILD_DIR:-$ROOT/build}
URL="udpm://239.255.76.67:7840?ttl=1"
SKIP=77

if [ "$(id -u)" != 0 ]; then echo "skipped: needs root to create network namespaces (ip netns)"; exit $SKIP; fi
if ! command -v ip >/dev/null 2>&1; then echo "skipped: 'ip' (iproute2) is missing"; exit $SKIP; fi

A=ucon-hostsA-$$ B=ucon-hostsB-$$
tmp=$(mktemp -d)
. "$ROOT/tests/lib/checks.sh"
on() { local ns=$1 run=$2; shift 2; ip netns exec "$ns" env UCON_RUN_DIR="$tmp/$run" UCON_BUILD_DIR="$BUILD" "$@"; }
cleanup() {
  # Stop both hosts' profiles (their supervisors also stop when the namespace goes, but the
  # processes are ours to end), then delete the namespaces (the veth pair goes with them).
  ip netns pids "$A" >/dev/null 2>&1 && on "$A" runA "$UCON" stop --grace 2 >/dev/null 2>&1
  ip netns pids "$B" >/dev/null 2>&1 && on "$B" runB "$UCON" stop --grace 2 >/dev/null 2>&1
  local ns pid
  for ns in "$A" "$B"; do
    for pid in $(ip netns pids "$ns" 2>/dev/null); do kill -KILL "$pid" 2>/dev/null; done
    ip netns del "$ns" 2>/dev/null
  done
  rm -rf "$tmp"
}
trap cleanup EXIT

if ! ip netns add "$A" 2>"$tmp/netns.err"; then
  echo "skipped: cannot create a network namespace here: $(cat "$tmp/netns.err")"; exit $SKIP
fi
ip netns add "$B" || { echo "FAIL: ip netns add $B"; exit 1; }
set -e
ip -n "$A" link add veth0 type veth peer name veth0 netns "$B"
for pair in "$A 10.213.76.1" "$B 10.213.76.2"; do
  set -- $pair
  ip -n "$1" link set lo up
  ip -n "$1" addr add "$2/24" dev veth0
  ip -n "$1" link set veth0 up
  ip -n "$1" route add 224.0.0.0/4 dev veth0
done
set +e
counter() { ip netns exec "$1" cat "/sys/class/net/veth0/statistics/$2"; }
link_up() { [ "$(ip netns exec "$A" cat /sys/class/net/veth0/operstate)" = up ] &&
            [ "$(ip netns exec "$B" cat /sys/class/net/veth0/operstate)" = up ]; }
for _ in $(seq 1 50); do link_up && break; sleep 0.1; done
check "the veth link is up on both hosts" 'link_up'
a_tx0=$(counter "$A" tx_bytes) b_tx0=$(counter "$B" tx_bytes)

# Host B first, as the profile's order would have it (the robot's stack waits for data), then
# host A, whose simulator starts the world's clock; the mission on B ends the run.
t0=$(date +%s)
on "$B" runB "$UCON" sim --except sim,sensor --detach --headless --scenario pedestrians \
  --duration 60 --log-dir "$tmp/logsB" --lcm-url "$URL" >"$tmp/b.out" 2>&1
check "host B starts (status $?)" '[ -f "$tmp/runB/supervisor.pid" ]'
on "$A" runA "$UCON" sim --only sim,sensor --detach --headless --scenario pedestrians \
  --log-dir "$tmp/logsA" --lcm-url "$URL" >"$tmp/a.out" 2>&1
rc_a=$?
check "host A starts (status $rc_a)" '[ $rc_a -eq 0 ]'
for _ in $(seq 1 1500); do [ -f "$tmp/runB/supervisor.pid" ] || break; sleep 0.1; done
rc_b=$(cat "$tmp/runB/main_status" 2>/dev/null || echo "none: still running after 150 s")
wall=$(( $(date +%s) - t0 ))
a_status=$(on "$A" runA "$UCON" status)
on "$A" runA "$UCON" stop --grace 2 >/dev/null 2>&1
a_tx=$(( $(counter "$A" tx_bytes) - a_tx0 )) b_tx=$(( $(counter "$B" tx_bytes) - b_tx0 ))
echo "--- host A"; cat "$tmp/a.out"; echo "$a_status"
echo "--- host B"; cat "$tmp/b.out"; tail -n 12 "$tmp/logsB/mission.log"
echo "--- veth bytes: A->B $a_tx, B->A $b_tx; wall time ${wall} s"

check "host B's mission exits 0, got $rc_b" '[ "$rc_b" = 0 ]'
check "summary: all goals reached, no collision" \
  'grep -q "\"success\": true" "$tmp/logsB/summary.json" && grep -q "\"collisions\": 0" "$tmp/logsB/summary.json"'
check "host B ended because its mission finished" 'grep -q "mission finished (status 0)" "$tmp/runB/last_stop_reason"'
for p in simulator lidar_driver; do
  check "host A ran $p, without exit or restart" \
    '[ -f "$tmp/runA/procs/$p.started" ] && [ ! -f "$tmp/runA/procs/$p.restarts" ] && echo "$a_status" | grep -q "^$p .*running"'
  check "host B did not run $p" '[ ! -f "$tmp/runB/procs/$p.started" ]'
done
for p in odometry perception planner base_controller logger mission; do
  check "host B ran $p" '[ -f "$tmp/runB/procs/$p.started" ] && [ ! -f "$tmp/runB/procs/$p.restarts" ]'
  check "host A did not run $p" '[ ! -f "$tmp/runA/procs/$p.started" ]'
done
# The points alone are megabytes per second; B sends trajectories, wheel commands, goals.
check "LCM traffic crossed the veth from A to B ($a_tx bytes > 5 MB)" '[ "$a_tx" -gt 5000000 ]'
check "LCM traffic crossed the veth from B to A ($b_tx bytes > 20 kB)" '[ "$b_tx" -gt 20000 ]'
log=$(ls "$tmp"/logsB/run_*_000.lcm 2>/dev/null | head -n 1)
check "host B's logger wrote a log" '[ -n "$log" ] && [ -s "$log" ]'
if [ -n "$log" ]; then
  summary=$("$BUILD/bin/ucon-logdump" "$log" --summary 2>&1)
  for ch in LIDAR_POINTS SIM_GROUND_TRUTH ROBOT_POSE BASE_WHEEL_CMD PLANNER_TRAJECTORY; do
    check "host B's log holds $ch" 'echo "$summary" | grep -q "^$ch "'
  done
  # For a failure's diagnosis: what the logger on B counted as lost (gaps in the senders' seq).
  "$BUILD/bin/ucon-logdump" "$log" --channel '^LOGGER_STATUS$' 2>/dev/null |
    awk '/^#/ { n = 0; delete nm } /counter_names\[/ { i = $1; gsub(/[^0-9]/, "", i); v = $3; gsub(/"/, "", v); nm[i] = v }
         /counter_values\[/ { i = $1; gsub(/[^0-9]/, "", i); if (nm[i] ~ /seq_gaps|dropped/) last[nm[i]] = $3 }
         END { for (k in last) printf "logger on B: %s %s\n", k, last[k] }' | sort
fi
check "the run took at most 120 s of wall time (${wall} s)" '[ "$wall" -le 120 ]'
checks_done
