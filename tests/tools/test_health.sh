#!/usr/bin/env bash
# ucon-health on a live LCM bus: --help; a malformed URL is a clear error (exit 1); a running
# base controller's status is listed with its health, a process named with --expect but silent
# is listed as such; BASE_STATUS (another type on a *_STATUS channel) is not mistaken for one.
#
#   test_health.sh BUILD_DIR        LCM on udpm port 7831.
set -u
BUILD=${1:?usage: test_health.sh BUILD_DIR}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
HEALTH="$BUILD/bin/ucon-health"
URL="udpm://239.255.76.67:7831?ttl=0"
. "$ROOT/tests/lib/checks.sh"
[ -x "$HEALTH" ] || { echo "FAIL: $HEALTH is not built"; exit 1; }
[ -x "$BUILD/bin/ucon-base-controller" ] || { echo "FAIL: ucon-base-controller is not built"; exit 1; }

out=$("$HEALTH" --help 2>&1); rc=$?
check "--help exits 0 and names --listen and --expect" '[ $rc -eq 0 ] && echo "$out" | grep -q -- --listen && echo "$out" | grep -q -- --expect'
out=$("$HEALTH" --lcm-url "nonsense://x" --listen 0.2 2>&1); rc=$?
check "a malformed URL: exit 1 and an error that names it ($out)" '[ $rc -eq 1 ] && echo "$out" | grep -q "error"'
out=$("$HEALTH" --listen 0 2>&1); rc=$?
check "--listen 0 is refused (exit $rc)" '[ $rc -ne 0 ]'

"$BUILD/bin/ucon-base-controller" --config "$ROOT/deploy/config/base_controller.yaml" --lcm-url "$URL" \
  >/dev/null 2>&1 &
bc=$!
trap 'kill -INT $bc 2>/dev/null; wait $bc 2>/dev/null' EXIT
sleep 0.5
out=$("$HEALTH" --lcm-url "$URL" --listen 2.5 --expect base_controller,perception); rc=$?
echo "$out"
check "exit 0" '[ $rc -eq 0 ]'
check "the base controller is listed OK (idle, nothing wrong)" 'echo "$out" | grep -Eq "^base_controller +OK "'
check "it has no fault counter (none counted yet)" '! echo "$out" | grep -q "faults:"'
check "the silent process is named" 'echo "$out" | grep -Eq "^perception +- +no status heard in 2.5 s"'
check "BASE_STATUS (base_status_t) is not listed as a process" '! echo "$out" | grep -q "BASE_STATUS"'

checks_done
