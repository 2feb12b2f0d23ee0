#!/usr/bin/env bash
# ucon-mcap end to end: a 20 s simulation (the whole stack, recorded in-process) exported and
# read back by the official @mcap/core reader (read_mcap.js: every channel, the log's message
# counts, valid schemas, the point cloud layout, the views, CRCs and indexes), in zstd and lz4;
# then a truncated and a corrupted copy of the log: a clear error naming the byte offset of the
# damaged event, exit status 2, and a valid MCAP holding exactly the events before it.
set -u
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${UCON_BUILD_DIR:-$ROOT/build}
export UCON_NODE_MODULES=${UCON_NODE_MODULES:-$BUILD/node/node_modules}
HERE="$ROOT/tests/foxglove"
if ! command -v node >/dev/null 2>&1; then
  echo "SKIP: node is not installed (the MCAP read-back uses @mcap/core)"
  exit 77
fi
if [ ! -d "$UCON_NODE_MODULES/@mcap/core" ]; then
  echo "SKIP: npm packages missing in $UCON_NODE_MODULES: deploy/ucon test installs them"
  exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$ROOT/tests/lib/checks.sh"

"$BUILD/bin/ucon-sim-record" --out "$tmp/run.lcm" --scenario crossing --duration 20 --nodes all >"$tmp/rec.out" 2>&1
check "a 20 s simulation was recorded" '[ -s "$tmp/run.lcm" ]' || { cat "$tmp/rec.out"; exit 1; }

for comp in zstd lz4; do
  "$BUILD/bin/ucon-mcap" "$tmp/run.lcm" -o "$tmp/run_$comp.mcap" --compression $comp >"$tmp/mcap.out" 2>&1
  rc=$?
  cat "$tmp/mcap.out"
  check "ucon-mcap ($comp) exits 0 (got $rc)" '[ $rc -eq 0 ]'
  node "$HERE/read_mcap.js" --log "$tmp/run.lcm" --mcap "$tmp/run_$comp.mcap" >"$tmp/read.out" 2>&1
  rc=$?
  tail -n 25 "$tmp/read.out"
  check "@mcap/core reads the $comp export back and every check holds" '[ $rc -eq 0 ]'
done

# Offsets of the log's events (28-byte big-endian headers), to damage one in the middle.
offsets=$(python3 - "$tmp/run.lcm" <<'EOF'
import struct, sys
b = open(sys.argv[1], "rb").read()
at, n = 0, 0
while at + 28 <= len(b):
    ch, dl = struct.unpack(">ii", b[at + 20:at + 28])
    print(at)
    at += 28 + ch + dl
EOF
)
total=$(echo "$offsets" | wc -l)
keep=$((total / 2))
cut_at=$(echo "$offsets" | sed -n "$((keep + 1))p")
check "the log has events to cut ($total)" '[ "$total" -gt 100 ]'

# Truncated in the middle of event number keep (0-based): 40 bytes into it.
head -c $((cut_at + 40)) "$tmp/run.lcm" >"$tmp/truncated.lcm"
"$BUILD/bin/ucon-mcap" "$tmp/truncated.lcm" -o "$tmp/truncated.mcap" >"$tmp/t.out" 2>"$tmp/t.err"
rc=$?
cat "$tmp/t.err"
check "truncated log: exit status 2 (got $rc)" '[ $rc -eq 2 ]'
check "truncated log: the error names the byte offset $cut_at" 'grep -q "truncated event.*at byte offset $cut_at\$" "$tmp/t.err"'
node "$HERE/read_mcap.js" --log "$tmp/run.lcm" --mcap "$tmp/truncated.mcap" --events $keep >"$tmp/read.out" 2>&1
rc=$?
tail -n 3 "$tmp/read.out"
check "truncated log: the MCAP is valid and holds the $keep events before the damage" '[ $rc -eq 0 ]'

# Corrupted: the sync word of the same event overwritten.
cp "$tmp/run.lcm" "$tmp/corrupt.lcm"
printf '\x00\x00\x00\x00' | dd of="$tmp/corrupt.lcm" bs=1 seek="$cut_at" conv=notrunc status=none
"$BUILD/bin/ucon-mcap" "$tmp/corrupt.lcm" -o "$tmp/corrupt.mcap" >"$tmp/c.out" 2>"$tmp/c.err"
rc=$?
cat "$tmp/c.err"
check "corrupt log: exit status 2 (got $rc)" '[ $rc -eq 2 ]'
check "corrupt log: the error names the byte offset $cut_at" 'grep -q "bad sync word.*at byte offset $cut_at\$" "$tmp/c.err"'
node "$HERE/read_mcap.js" --log "$tmp/run.lcm" --mcap "$tmp/corrupt.mcap" --events $keep >"$tmp/read.out" 2>&1
rc=$?
tail -n 3 "$tmp/read.out"
check "corrupt log: the MCAP is valid and holds the $keep events before the damage" '[ $rc -eq 0 ]'

# Bad input is a clear error.
"$BUILD/bin/ucon-mcap" "$tmp/missing.lcm" -o "$tmp/x.mcap" >/dev/null 2>"$tmp/m.err"
rc=$?
check "missing log: exit 2 with a message naming it" '[ $rc -eq 2 ] && grep -q "missing.lcm: cannot open" "$tmp/m.err"'
"$BUILD/bin/ucon-mcap" "$tmp/run.lcm" -o "$tmp/x.mcap" --planner-config "$tmp/none.yaml" >/dev/null 2>"$tmp/p.err"
rc=$?
check "missing planner config: exit 2 with a message" '[ $rc -eq 2 ] && grep -q "planner-config" "$tmp/p.err"'
checks_done
