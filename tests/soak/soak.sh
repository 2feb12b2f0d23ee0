#!/usr/bin/env bash
# Soak: the whole simulated stack for N minutes with the mission driving the scenario's goals
# in a loop (deploy/ucon sim --loop), every process's resident memory sampled every few
# seconds into a CSV; at the end soak_check.py judges the run: RSS growth after the first
# minute, the logger's loss counters, restarts, collisions. Not part of `deploy/ucon test`
# (it takes as long as it runs); see docs/running.md, "Long runs (soak)".
set -u
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
UCON="$ROOT/deploy/ucon"
BUILD=${UCON_BUILD_DIR:-$ROOT/build}

minutes=30 scenario=pedestrians out="" url=${LCM_DEFAULT_URL:-"udpm://239.255.76.67:7667?ttl=0"}
sample_s=10 warmup_s=60 max_growth_pct=5 pose=odometry
usage() {
  cat <<'EOT'
Usage: tests/soak/soak.sh [options]
  --minutes N          how long the simulation runs, in simulated minutes (default 30)
  --scenario S         scenario whose goals are looped (default pedestrians)
  --pose P             odometry (default) | ground_truth, as deploy/ucon sim --pose
  --out DIR            where the CSV, the JSON and the run's logs go (default logs/soak_<date>)
  --lcm-url U          LCM URL (default $LCM_DEFAULT_URL or the launcher's)
  --sample-s S         seconds between memory samples (default 10)
  --warmup-s S         memory is judged against its value this long after the start (default 60)
  --max-growth-pct P   largest allowed RSS growth after the warm-up [%] (default 5)
Exit status 0 when every check passes, 1 when one fails, 2 on bad usage or a run that
did not start. Writes DIR/rss.csv (t_s, process, pid, rss_kb, restarts) and DIR/soak.json.
EOT
}
while [ $# -gt 0 ]; do
  case "$1" in
    --minutes) minutes=$2; shift ;;
    --scenario) scenario=$2; shift ;;
    --pose) pose=$2; shift ;;
    --out) out=$2; shift ;;
    --lcm-url) url=$2; shift ;;
    --sample-s) sample_s=$2; shift ;;
    --warmup-s) warmup_s=$2; shift ;;
    --max-growth-pct) max_growth_pct=$2; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "soak: unknown option $1 (--help)" >&2; exit 2 ;;
  esac
  shift
done
for v in minutes sample_s warmup_s max_growth_pct; do
  [[ "${!v}" =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "soak: --${v//_/-} takes a number, not '${!v}'" >&2; exit 2; }
done
[ -n "$out" ] || out="$ROOT/logs/soak_$(date +%Y%m%d_%H%M%S)"
mkdir -p "$out" || exit 2
out=$(cd "$out" && pwd)
# A run folder of its own: the soak never touches (nor is stopped by) another profile's.
export UCON_RUN_DIR="$out/run"
duration_s=$(awk -v m="$minutes" 'BEGIN { printf "%d", m * 60 }')
csv="$out/rss.csv"

stop_run() { "$UCON" stop --grace 5 >/dev/null 2>&1; }
trap 'echo "soak: interrupted"; stop_run; exit 1' INT TERM

echo "soak: $minutes min of scenario $scenario in a loop; samples every ${sample_s} s into $csv"
"$UCON" sim --scenario "$scenario" --pose "$pose" --loop --duration "$duration_s" --headless \
  --detach --log-dir "$out/logs" --lcm-url "$url" >"$out/launch.out" 2>&1
if [ ! -f "$UCON_RUN_DIR/supervisor.pid" ]; then
  cat "$out/launch.out"; echo "soak: the run did not start" >&2; exit 2
fi
t0=$(date +%s.%N)
echo "t_s,process,pid,rss_kb,restarts" >"$csv"
# Until the supervisor ends the run (the mission stops at the duration), with a margin for a
# simulation slower than real time.
deadline=$(( $(date +%s) + duration_s * 2 + 300 ))
next=0
while [ -f "$UCON_RUN_DIR/supervisor.pid" ]; do
  if [ "$(date +%s)" -ge $deadline ]; then echo "soak: still running at the deadline: stopping it"; stop_run; break; fi
  now=$(date +%s.%N)
  t=$(awk -v a="$now" -v b="$t0" 'BEGIN { printf "%.1f", a - b }')
  if awk -v t="$t" -v n="$next" 'BEGIN { exit !(t >= n) }'; then
    for f in "$UCON_RUN_DIR"/procs/*.pid; do
      [ -f "$f" ] || continue
      name=$(basename "$f" .pid) pid=$(cat "$f")
      rss=$(awk '/^VmRSS:/ { print $2 }' "/proc/$pid/status" 2>/dev/null)
      restarts=$(cat "$UCON_RUN_DIR/procs/$name.restarts" 2>/dev/null || echo 0)
      echo "$t,$name,$pid,${rss:--1},$restarts" >>"$csv"
    done
    next=$(awk -v n="$next" -v s="$sample_s" 'BEGIN { print n + s }')
    [ $(( ${next%.*} % 300 )) -eq 0 ] && echo "soak: $(awk -v t="$t" 'BEGIN { printf "%.0f", t / 60 }') min"
  fi
  sleep 1
done
wall=$(awk -v a="$(date +%s.%N)" -v b="$t0" 'BEGIN { printf "%.0f", a - b }')
echo "soak: run ended after $wall s ($(cat "$UCON_RUN_DIR/last_stop_reason" 2>/dev/null))"

# What the logger counted at the end: the last LOGGER_STATUS of the last log file.
last_log=$(ls "$out"/logs/run_*.lcm 2>/dev/null | sort | tail -n 1)
if [ -n "$last_log" ]; then
  "$BUILD/bin/ucon-logdump" "$last_log" --channel '^LOGGER_STATUS$' >"$out/logger_status.txt" 2>&1
fi
exited=$(cd "$UCON_RUN_DIR/procs" 2>/dev/null && ls *.exited 2>/dev/null | sed 's/\.exited$//' | xargs)
python3 "$ROOT/tests/soak/soak_check.py" --csv "$csv" --summary "$out/logs/summary.json" \
  --logger-status "$out/logger_status.txt" --stop-reason "$(cat "$UCON_RUN_DIR/last_stop_reason" 2>/dev/null)" \
  --exited-before-end "$exited" --warmup-s "$warmup_s" --max-growth-pct "$max_growth_pct" \
  --wall-s "$wall" --minutes "$minutes" --scenario "$scenario" --json "$out/soak.json"
