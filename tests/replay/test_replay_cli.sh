#!/usr/bin/env bash
# ucon-replay and ucon-sim-record on the command line: a recorded run replays to the same
# bytes twice and matches the recording (exit 0); a different reference is named at the first
# differing message and field (exit 1); truncated or corrupt input is a clear error with the
# byte offset (exit 2), never a crash; unknown nodes and missing files are errors (exit 2).
set -u
BIN=${1:?usage: test_replay_cli.sh BIN_DIR}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$ROOT/tests/lib/checks.sh"

"$BIN/ucon-sim-record" --out "$tmp/run.lcm" --scenario crossing --duration 1.0 --nodes base_controller \
  --config-dir "$ROOT/deploy/config" --scenario-dir "$ROOT/deploy/scenarios" >"$tmp/rec.out" 2>&1
check "ucon-sim-record exits 0" '[ $? -eq 0 ]'
"$BIN/ucon-replay" --node base_controller --in "$tmp/run.lcm" --out "$tmp/a.lcm" \
  --config-from-log --compare "$tmp/run.lcm" >"$tmp/a.out" 2>&1; rc=$?
check "replay compared with the recording: exit 0 (got $rc)" '[ $rc -eq 0 ]'
check "it says identical" 'grep -q "^identical to" "$tmp/a.out"'
"$BIN/ucon-replay" --node base_controller --in "$tmp/run.lcm" --out "$tmp/b.lcm" \
  --config "$ROOT/deploy/config/base_controller.yaml" >/dev/null 2>&1
check "two replays are byte-identical" 'cmp -s "$tmp/a.lcm" "$tmp/b.lcm"'
check "output timestamps are message utimes (no wall clock): a third run is identical too" \
  '"$BIN/ucon-replay" --node base_controller --in "$tmp/run.lcm" --out "$tmp/c.lcm" >/dev/null 2>&1 && cmp -s "$tmp/a.lcm" "$tmp/c.lcm"'

sed 's/^\(  *\)kp_position:.*/\1kp_position: 0.3/' "$ROOT/deploy/config/base_controller.yaml" >"$tmp/bc.yaml"
"$BIN/ucon-replay" --node base_controller --in "$tmp/run.lcm" --out "$tmp/d.lcm" --config "$tmp/bc.yaml" \
  --compare "$tmp/a.lcm" >"$tmp/d.out" 2>&1; rc=$?
check "a different reference: exit 1 (got $rc)" '[ $rc -eq 1 ]'
check "the difference names event, channel and field" \
  'grep -Eq "^differs from .*: event [0-9]+ on BASE_WHEEL_CMD \(ucon.wheel_cmd_t\) field w_" "$tmp/d.out"'

size=$(stat -c %s "$tmp/run.lcm")
head -c $((size / 2)) "$tmp/run.lcm" >"$tmp/trunc.lcm"
"$BIN/ucon-replay" --node base_controller --in "$tmp/trunc.lcm" --out "$tmp/t.lcm" >"$tmp/t.out" 2>&1; rc=$?
check "truncated log: exit 2 (got $rc)" '[ $rc -eq 2 ]'
check "truncated log: error names the byte offset" 'grep -q "truncated event.*at byte offset [0-9]" "$tmp/t.out"'
check "truncated log: no output file left" '[ ! -e "$tmp/t.lcm" ]'
cp "$tmp/run.lcm" "$tmp/corrupt.lcm"
printf 'XXXX' | dd of="$tmp/corrupt.lcm" bs=1 seek=0 conv=notrunc 2>/dev/null
"$BIN/ucon-replay" --node base_controller --in "$tmp/corrupt.lcm" --out "$tmp/t.lcm" >"$tmp/c.out" 2>&1; rc=$?
check "corrupt log: exit 2 (got $rc)" '[ $rc -eq 2 ]'
check "corrupt log: error says bad sync word at byte offset 0" 'grep -q "bad sync word.*at byte offset 0" "$tmp/c.out"'

"$BIN/ucon-replay" --node navigator --in "$tmp/run.lcm" --out "$tmp/x.lcm" >"$tmp/n.out" 2>&1; rc=$?
check "unknown node: exit 2 naming it (got $rc)" '[ $rc -eq 2 ] && grep -q "unknown node .navigator." "$tmp/n.out"'
"$BIN/ucon-replay" --node base_controller --in "$tmp/none.lcm" --out "$tmp/x.lcm" >"$tmp/m.out" 2>&1; rc=$?
check "missing log: exit 2 (got $rc)" '[ $rc -eq 2 ] && grep -q "cannot open" "$tmp/m.out"'

checks_done
