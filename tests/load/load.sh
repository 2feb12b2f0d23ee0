#!/usr/bin/env bash
# A loaded computer: `deploy/ucon sim` with a CPU hog beside it (stress-ng, one worker per core
# by default), then perception and the planner replayed (ucon-replay, lock step, no deadline)
# on the log of that very run. The replay is what the node gives for the same inputs with all
# the CPU it wants, so the difference is what the load cost: perception's MOTA (ucon-mot on
# the live tracks and on the replayed ones, against the same ground truth) and the planner's
# success (share of its planning cycles that give a trajectory to follow). load_check.py
# judges: every run reaches its goal without collision, and each difference is at most
# --max-drop points. Not part of `deploy/ucon test`; see docs/running.md, "A loaded computer".
set -u
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
UCON="$ROOT/deploy/ucon"
BUILD=${UCON_BUILD_DIR:-$ROOT/build}

workers=$(nproc) runs=3 scenario=pedestrians out="" url=${LCM_DEFAULT_URL:-"udpm://239.255.76.67:7667?ttl=0"}
max_drop=3 pose=odometry duration=60
usage() {
  cat <<'EOT'
Usage: tests/load/load.sh [options]
  --workers N     stress-ng CPU workers beside the run (default: one per core, nproc); 0 = no
                  load (the replay must then agree with the live run)
  --runs K        runs of the scenario (default 3)
  --scenario S    scenario (default pedestrians)
  --pose P        odometry (default) | ground_truth, as deploy/ucon sim --pose
  --duration S    simulated seconds of each run, the scenario's goals driven in a loop
                  (deploy/ucon sim --loop; default 60)
  --max-drop P    largest allowed loss of MOTA or planner success against the replay [points]
                  (default 3)
  --out DIR       where the logs, the replays and load.json go (default logs/load_<date>)
  --lcm-url U     LCM URL (default $LCM_DEFAULT_URL or the launcher's)
Needs stress-ng (apt-get install stress-ng) when --workers is above 0. Exit status 0 when every
check passes, 1 when one fails, 2 on bad usage or a run that did not start.
EOT
}
while [ $# -gt 0 ]; do
  case "$1" in
    --workers) workers=$2; shift ;;
    --runs) runs=$2; shift ;;
    --scenario) scenario=$2; shift ;;
    --pose) pose=$2; shift ;;
    --duration) duration=$2; shift ;;
    --max-drop) max_drop=$2; shift ;;
    --out) out=$2; shift ;;
    --lcm-url) url=$2; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "load: unknown option $1 (--help)" >&2; exit 2 ;;
  esac
  shift
done
for v in workers runs duration; do
  [[ "${!v}" =~ ^[0-9]+$ ]] || { echo "load: --$v takes a whole number, not '${!v}'" >&2; exit 2; }
done
[[ "$max_drop" =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "load: --max-drop takes a number, not '$max_drop'" >&2; exit 2; }
[ "$runs" -ge 1 ] || { echo "load: --runs must be at least 1" >&2; exit 2; }
if [ "$workers" -gt 0 ] && ! command -v stress-ng >/dev/null; then
  echo "load: stress-ng is not installed: deploy/install-deps.sh tools (or apt-get install stress-ng), or run with --workers 0" >&2
  exit 2
fi
for b in ucon-mot ucon-replay ucon-logdump; do
  [ -x "$BUILD/bin/$b" ] || { echo "load: $BUILD/bin/$b missing: build first (deploy/ucon build)" >&2; exit 2; }
done
[ -n "$out" ] || out="$ROOT/logs/load_$(date +%Y%m%d_%H%M%S)"
mkdir -p "$out" || exit 2
out=$(cd "$out" && pwd)

hog=""
stop_hog() { [ -n "$hog" ] && kill -TERM "$hog" 2>/dev/null && wait "$hog" 2>/dev/null; hog=""; }
trap 'echo "load: interrupted"; stop_hog; "$UCON" stop --grace 5 >/dev/null 2>&1; exit 1' INT TERM

# Planning cycles by PLANNER_TRAJECTORY status in a log: "ok stop goal invalid".
plan_counts() {
  "$BUILD/bin/ucon-logdump" "$1" --channel '^PLANNER_TRAJECTORY$' |
    awk '/^  status = / { n[$3]++ } END { printf "%d %d %d %d\n", n[0], n[1], n[2], n[3] }'
}

echo "load: $runs run(s) of $scenario for $duration s, $workers stress-ng CPU worker(s) beside each; results in $out"
for i in $(seq 1 "$runs"); do
  d="$out/run_$i"
  mkdir -p "$d"
  export UCON_RUN_DIR="$d/supervisor"
  if [ "$workers" -gt 0 ]; then
    stress-ng --cpu "$workers" --timeout 1800s --quiet >"$d/stress-ng.out" 2>&1 &
    hog=$!
  fi
  "$UCON" sim --scenario "$scenario" --pose "$pose" --loop --duration "$duration" --headless --log-dir "$d/logs" --lcm-url "$url" >"$d/sim.out" 2>&1
  rc=$?
  stop_hog
  logs=$(ls "$d"/logs/run_*.lcm 2>/dev/null | sort)
  if [ -z "$logs" ] || [ ! -f "$d/logs/summary.json" ]; then
    tail -n 20 "$d/sim.out"; echo "load: run $i did not start or left no log (exit $rc)" >&2; exit 2
  fi
  # A run longer than the logger's file size is split: the parts concatenate into one log.
  log="$d/run.lcm"
  cat $logs >"$log"
  echo "load: run $i: $(tail -n 1 "$d/sim.out")"
  "$BUILD/bin/ucon-mot" --log "$log" --json --allow-truncated >"$d/mot_live.json" 2>"$d/mot_live.err"
  "$BUILD/bin/ucon-replay" --node perception --in "$log" --out "$d/perception_replay.lcm" --config-from-log \
    >"$d/perception_replay.out" 2>&1 || { cat "$d/perception_replay.out"; echo "load: perception replay failed" >&2; exit 2; }
  "$BUILD/bin/ucon-mot" --log "$log" --objects-log "$d/perception_replay.lcm" --json --allow-truncated \
    >"$d/mot_replay.json" 2>"$d/mot_replay.err"
  "$BUILD/bin/ucon-replay" --node planner --in "$log" --out "$d/planner_replay.lcm" --config-from-log \
    >"$d/planner_replay.out" 2>&1 || { cat "$d/planner_replay.out"; echo "load: planner replay failed" >&2; exit 2; }
  plan_counts "$log" >"$d/plan_live.txt"
  plan_counts "$d/planner_replay.lcm" >"$d/plan_replay.txt"
  rm -f "$log" "$d/perception_replay.lcm" "$d/planner_replay.lcm"  # large; the run's logs stay
done

python3 "$ROOT/tests/load/load_check.py" --dir "$out" --runs "$runs" --workers "$workers" \
  --scenario "$scenario" --max-drop "$max_drop" --json "$out/load.json"
