#!/usr/bin/env bash
# Stale inputs in the live simulation (the sim profile's processes, --pose odometry): the robot
# drives toward a goal and, one at a time, a process is frozen with kill -STOP and later resumed
# with kill -CONT:
#   a. the planner     -> PLANNER_TRAJECTORY stale: the base controller ramps the wheels to zero
#                         within its bound and BASE_STATUS says "trajectory stale";
#   b. perception      -> PERCEPTION_OBJECTS stale: the planner stops planning through stale
#                         obstacles (PLANNER_STATUS says so, its trajectory is a stop) and the
#                         wheels come to rest within the bound;
#   c. the odometry    -> ROBOT_POSE stale: the controller brakes within its bound, BASE_STATUS
#                         says "pose stale", perception and the planner say so on their status.
# After each resume the robot tracks a plan again. Each bound is computed from the shipped
# config (docs/robot.md, "Stale inputs"), checked in message time (utime) from the last message
# of the frozen process to the first zero wheel command; the wall time from the kill -STOP is
# printed beside it. Every stale case must also show in `deploy/ucon status` (health view).
#
#   test_stale_inputs.sh BUILD_DIR        (KEEP=1 keeps the logs)
#
# LCM on udpm port 7832; UDP on 127.0.0.1 ports 27500-27541.
set -u
BUILD=${1:?usage: test_stale_inputs.sh BUILD_DIR}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
UCON="$ROOT/deploy/ucon"
tmp=$(mktemp -d /tmp/ucon_stale_XXXXXX)
export UCON_BUILD_DIR="$BUILD" UCON_RUN_DIR="$tmp/run" UCON_TEST_CFG="$tmp/cfg"
URL="udpm://239.255.76.67:7832?ttl=0"
SCENARIO="$ROOT/tests/sim_profile/stale_inputs.yaml"
. "$ROOT/tests/lib/checks.sh"
pidof_proc() { cat "$UCON_RUN_DIR/procs/$1.pid" 2>/dev/null; }
wall_us() { date +%s%6N; }
cleanup() {
  local f
  for f in "$UCON_RUN_DIR"/procs/*.pid; do [ -f "$f" ] && kill -CONT -- "-$(cat "$f")" 2>/dev/null; done
  "$UCON" stop --grace 2 >/dev/null 2>&1
  for f in "$UCON_RUN_DIR"/procs/*.pid; do [ -f "$f" ] && kill -KILL -- "-$(cat "$f")" 2>/dev/null; done
  [ -n "${KEEP:-}" ] && echo "kept $tmp" || rm -rf "$tmp"
}
trap cleanup EXIT
t_begin=$(date +%s)

for exe in ucon-simulator ucon-lidar-driver ucon-odometry ucon-perception ucon-planner ucon-base-controller \
           ucon-logger ucon-goal ucon-logdump ucon-health; do
  [ -x "$BUILD/bin/$exe" ] || { echo "FAIL: $BUILD/bin/$exe is not built"; exit 1; }
done

# ---- The deployed configs, with this test's UDP ports, as `deploy/ucon sim --pose odometry`
# makes them (odometry started at the scenario's start, no ground-truth ROBOT_POSE).
mkdir -p "$UCON_TEST_CFG"
for f in "$ROOT"/deploy/config/*.yaml; do
  sed -E -e 's/\b56000\b/27500/g' -e 's/\b56100\b/27510/g' -e 's/\b56101\b/27511/g' \
         -e 's/\b56200\b/27520/g' -e 's/\b56201\b/27521/g' \
         -e 's/\b56300\b/27530/g' -e 's/\b56301\b/27531/g' -e 's/\b56400\b/27540/g' -e 's/\b56401\b/27541/g' \
         "$f" >"$UCON_TEST_CFG/$(basename "$f")"
done
start=$("$BUILD/bin/ucon-odometry" --config "$UCON_TEST_CFG/odometry.yaml" --scenario "$SCENARIO" --print-start-pose) ||
  { echo "FAIL: cannot read the scenario's start pose"; exit 1; }
sed -i "s/^\(  pose: \)\[[^]]*\]/\1[$start]/" "$UCON_TEST_CFG/odometry.yaml"
sed -i 's/^pose_source: .*/pose_source: none/' "$UCON_TEST_CFG/simulator.yaml"

# ---- The bounds, from the shipped config (key lookup: top-level "key:" or "section:\n  key:").
yget() {  # file section key  (section "" = top level)
  awk -v sec="$2" -v key="$3" '
    /^[A-Za-z_]+:/ { cur = $1; sub(/:$/, "", cur) }
    { line = $0; sub(/#.*/, "", line) }
    sec == "" && line ~ "^" key ":" { sub("^" key ":[ ]*", "", line); print line + 0; exit }
    sec != "" && cur == sec && line ~ "^  " key ":" { sub("^  " key ":[ ]*", "", line); print line + 0; exit }
  ' "$ROOT/deploy/config/$1.yaml"
}
BC=base_controller
traj_timeout=$(yget $BC watchdog trajectory_timeout_s); pose_timeout=$(yget $BC watchdog pose_timeout_s)
lin_decel=$(yget $BC watchdog stop_linear_decel); ang_decel=$(yget $BC watchdog stop_angular_decel)
ctl_rate=$(yget $BC control rate_hz); max_speed=$(yget $BC control max_speed); max_yaw_rate=$(yget $BC control max_yaw_rate)
obj_age=$(yget planner objects max_age_s); plan_rate=$(yget planner "" rate_hz); latency=$(yget planner "" latency_s)
plan_vmax=$(yget planner optimizer max_velocity); plan_amax=$(yget planner optimizer max_acceleration)
for v in traj_timeout pose_timeout lin_decel ang_decel ctl_rate max_speed max_yaw_rate obj_age plan_rate latency plan_vmax plan_amax; do
  [ -n "${!v}" ] && [ "${!v}" != 0 ] || { echo "FAIL: config value $v not found in deploy/config"; exit 1; }
done
# Controller watchdog: timeout + one control period + the longest ramp the limits allow.
ramp=$(awk -v a="$max_speed" -v b="$lin_decel" -v c="$max_yaw_rate" -v d="$ang_decel" 'BEGIN { r = a / b; if (c / d > r) r = c / d; print r }')
bound_a=$(awk -v t="$traj_timeout" -v r="$ctl_rate" -v m="$ramp" 'BEGIN { printf "%.3f", t + 1 / r + m }')
bound_c=$(awk -v t="$pose_timeout" -v r="$ctl_rate" -v m="$ramp" 'BEGIN { printf "%.3f", t + 1 / r + m }')
# Planner: obstacles older than max_age_s -> at its next cycle a stop plan from now + latency
# braking at the optimiser's acceleration from at most its speed; the controller follows it.
bound_b=$(awk -v a="$obj_age" -v p="$plan_rate" -v l="$latency" -v v="$plan_vmax" -v m="$plan_amax" -v r="$ctl_rate" \
  'BEGIN { printf "%.3f", a + 1 / p + l + v / m + 1 / r }')
echo "bounds from deploy/config: trajectory stale ${bound_a} s, objects stale ${bound_b} s, pose stale ${bound_c} s"

# ---- Start the stack, let the odometry initialise (standstill), send the goal.
"$UCON" start "$ROOT/tests/sim_profile/stale_inputs.profile" --detach --log-dir "$tmp/logs" --lcm-url "$URL" >/dev/null ||
  { echo "FAIL: the profile did not start"; exit 1; }
sleep 4
"$BUILD/bin/ucon-goal" --x 44 --y 0 --lcm-url "$URL" >/dev/null || echo "FAIL: ucon-goal"
sleep 5

declare -A T_STOP T_CONT STATUS_OUT
# One case: freeze process $2 (case $1), wait, take `deploy/ucon status`, resume, let it drive.
freeze() {  # case process seconds_before_status
  local c=$1 proc=$2 pid
  pid=$(pidof_proc "$proc")
  T_STOP[$c]=$(wall_us)
  kill -STOP "$pid"
  sleep "$3"
  local t_status
  t_status=$(wall_us)
  STATUS_OUT[$c]=$("$UCON" status 2>&1)
  T_CONT[$c]=$(wall_us)
  kill -CONT "$pid"
  echo "case $c: $proc stopped for $(( (T_CONT[$c] - T_STOP[$c]) / 1000 )) ms (deploy/ucon status took $(( (T_CONT[$c] - t_status) / 1000 )) ms)"
}
freeze a planner 1.8
sleep 3
freeze b perception 2.2
sleep 3
freeze c odometry 1.8
sleep 5
status_end=$("$UCON" status 2>&1)
"$UCON" stop --grace 3 >/dev/null 2>&1
echo "run done after $(( $(date +%s) - t_begin )) s"

# ---- Read the log.
log=$(ls -t "$tmp/logs"/*.lcm 2>/dev/null | head -1)
[ -n "$log" ] || { echo "FAIL: no log written"; exit 1; }
# One line per message: channel, log time (wall us), then the fields of interest as key=value.
"$BUILD/bin/ucon-logdump" "$log" \
  --channel 'BASE_WHEEL_CMD|BASE_STATUS|PLANNER_TRAJECTORY|PLANNER_STATUS|PERCEPTION_OBJECTS|ROBOT_POSE' 2>/dev/null |
  awk '
    function flush() { if (ch != "") print ch "\t" t "\t" rec; ch = ""; rec = "" }
    /^#/ { flush(); ch = $3; t = $2; sub(/^t=/, "", t); next }
    /^  [a-z_]+(\[[0-9]+\])? = / {
      k = $1; v = $0; sub(/^  [a-z_]+(\[[0-9]+\])? = /, "", v); gsub(/\t/, " ", v)
      if (k ~ /^(utime|vx|vy|wz|enable|state|reason|status|valid|health|message)$/ || k ~ /^timing_(names|max_ms)\[[0-9]+\]$/)
        rec = rec k "=" v "\t"
    }
    END { flush() }' >"$tmp/events.tsv"
echo "log: $(wc -l <"$tmp/events.tsv") messages of interest (read after $(( $(date +%s) - t_begin )) s)"

# field NAME from a line of events.tsv
ev() { awk -F'\t' -v ch="$1" -v lo="$2" -v hi="$3" '$1 == ch && $2 >= lo && $2 < hi' "$tmp/events.tsv"; }
field() { tr '\t' '\n' | sed -n "s/^$1=//p"; }

# Analysis of one stop: prints "zero_msg_ms zero_wall_ms speed_before v_trig ramp_ms" or "none".
#   $1 case, $2 channel of the frozen input, $3 "exact" (all-zero command) or "rest" (|v|, |wz| <= 0.05)
analyse() {
  local c=$1 in_ch=$2 mode=$3 t0=${T_STOP[$1]} t1=${T_CONT[$1]}
  awk -F'\t' -v in_ch="$in_ch" -v t0="$t0" -v t1="$t1" -v mode="$mode" '
    function get(k,   i, kv) { for (i = 3; i <= NF; i++) { if (index($i, k "=") == 1) return substr($i, length(k) + 2) } return "" }
    $2 < t0 - 3000000 || $2 >= t1 { next }
    $1 == in_ch && $2 < t1 { last_in = get("utime") }
    $1 == "BASE_WHEEL_CMD" {
      vx = get("vx"); vy = get("vy"); wz = get("wz"); u = get("utime"); s = sqrt(vx * vx + vy * vy)
      if ($2 < t0) { before = s; next }
      if (zero_u) next
      if (s > peak) { peak = s }
      at_rest = (mode == "exact") ? (vx == 0 && vy == 0 && wz == 0) : (s <= 0.05 && (wz < 0 ? -wz : wz) <= 0.05)
      if (at_rest) { zero_u = u; zero_t = $2 }
    }
    END {
      if (!zero_u || !last_in) { print "none"; exit }
      printf "%.0f %.0f %.3f %.3f\n", (zero_u - last_in) / 1000, (zero_t - t0) / 1000, before, peak
    }' "$tmp/events.tsv"
}
# The stop ramp of the controller: from the tick its BASE_STATUS names `$2` to the first zero
# command: prints "v_at_trigger ramp_ms" (the ramp may not be shorter than v / decel - a period).
# The speed at the trigger is the last command before that tick by utime: the log may hold the
# tick's own (already reduced) command before its status.
ramp_of() {
  local c=$1 why=$2 t0=${T_STOP[$1]} t1=${T_CONT[$1]}
  awk -F'\t' -v t0="$t0" -v t1="$t1" -v why="$why" '
    function get(k,   i) { for (i = 3; i <= NF; i++) { if (index($i, k "=") == 1) return substr($i, length(k) + 2) } return "" }
    $2 < t0 || $2 >= t1 { next }
    $1 == "BASE_STATUS" && !trig && index(get("reason"), why) { trig = get("utime") + 0 }
    $1 == "BASE_WHEEL_CMD" {
      n++; cu[n] = get("utime") + 0; vx = get("vx"); vy = get("vy"); wz = get("wz")
      cv[n] = sqrt(vx * vx + vy * vy); cz[n] = (vx == 0 && vy == 0 && wz == 0)
    }
    END {
      if (!trig) { print "none"; exit }
      bu = -1; zu = -1
      for (i = 1; i <= n; i++) {
        if (cu[i] < trig && cu[i] > bu) { bu = cu[i]; v = cv[i] }
        if (cu[i] >= trig && cz[i] && (zu < 0 || cu[i] < zu)) zu = cu[i]
      }
      if (bu < 0 || zu < 0) { print "none"; exit }
      printf "%.3f %.0f\n", v, (zu - trig) / 1000
    }' "$tmp/events.tsv"
}
# After the resume: the controller tracks again (BASE_STATUS state 1) and drives (|v| > 0.2).
resumed() {
  local c=$1 t1=${T_CONT[$1]}
  awk -F'\t' -v t1="$t1" '
    function get(k,   i) { for (i = 3; i <= NF; i++) { if (index($i, k "=") == 1) return substr($i, length(k) + 2) } return "" }
    $2 < t1 || $2 > t1 + 8000000 { next }
    $1 == "BASE_STATUS" && get("state") == 1 { tracking = 1 }
    $1 == "BASE_WHEEL_CMD" && tracking { vx = get("vx"); vy = get("vy"); if (sqrt(vx * vx + vy * vy) > 0.2) { print "yes"; exit } }
  ' "$tmp/events.tsv"
}
le() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a <= b) }'; }
# The planner's longest cycle [ms] (PLANNER_STATUS timing plan_total, max per period) around case $1.
plan_compute_ms() {
  awk -F'\t' -v lo="$(( T_STOP[$1] - 2000000 ))" -v hi="${T_CONT[$1]}" '
    $1 != "PLANNER_STATUS" || $2 < lo || $2 >= hi { next }
    { for (i = 3; i <= NF; i++) if ($i ~ /^timing_names\[[0-9]+\]="plan_total"$/) {
        idx = $i; sub(/^timing_names\[/, "", idx); sub(/\].*/, "", idx); key = "timing_max_ms[" idx "]="
        for (j = 3; j <= NF; j++) if (index($j, key) == 1) { v = substr($j, length(key) + 1) + 0; if (v > m) m = v }
      } }
    END { printf "%.0f\n", m }' "$tmp/events.tsv"
}
# A counter's value in a `deploy/ucon status` text (0 when not listed).
cnt() { echo "$1" | grep -oE "\b$2=[0-9]+" | head -1 | cut -d= -f2 | grep . || echo 0; }

report() {  # case what bound_s analysis
  echo "case $1 ($2): $(echo "$4" | awk -v b="$3" '{ printf "first zero wheel command %s ms after the last input (message time; bound %.0f ms), %s ms after kill -STOP (wall); speed before %s m/s", $1, b * 1000, $2, $3 }')"
}

# a. Planner frozen.
A=$(analyse a PLANNER_TRAJECTORY exact)
report a "PLANNER_TRAJECTORY stale" "$bound_a" "$A"
check "a: the robot was moving when the planner froze ($(echo "$A" | cut -d' ' -f3) m/s)" \
  '[ "$A" != none ] && le 0.3 "$(echo "$A" | cut -d" " -f3)"'
check "a: all-zero wheel command within ${bound_a} s of the last trajectory" \
  '[ "$A" != none ] && le "$(echo "$A" | cut -d" " -f1)" "$(awk -v b="$bound_a" "BEGIN { print b * 1000 }")"'
check "a: BASE_STATUS says trajectory stale" \
  'ev BASE_STATUS "${T_STOP[a]}" "${T_CONT[a]}" | grep -q "reason=\"watchdog: trajectory stale"'
R=$(ramp_of a "trajectory stale")
check "a: the ramp respects stop_linear_decel (${R% *} m/s to 0 in ${R#* } ms; >= v/decel - 1 period)" \
  '[ "$R" != none ] && le "$(awk -v v="${R% *}" -v d="$lin_decel" -v r="$ctl_rate" "BEGIN { print (v / d - 1 / r) * 1000 - 1 }")" "${R#* }"'
check "a: status shows base_controller WARN 'watchdog: trajectory stale'" \
  'echo "${STATUS_OUT[a]}" | grep -Eq "^base_controller +WARN +watchdog: trajectory stale"'
check "a: status counts it (stops_trajectory_stale=$(cnt "${STATUS_OUT[a]}" stops_trajectory_stale))" \
  '[ "$(cnt "${STATUS_OUT[a]}" stops_trajectory_stale)" -ge 1 ]'
check "a: status shows the frozen planner silent" 'echo "${STATUS_OUT[a]}" | grep -Eq "^planner +- +no status heard"'
check "a: tracking again after kill -CONT" '[ "$(resumed a)" = yes ]'

# b. Perception frozen. The planner notices at its next cycle, which may start only when the one
# under way ends: its compute time (measured, PLANNER_STATUS) adds to the config's bound.
B=$(analyse b PERCEPTION_OBJECTS rest)
plan_ms=$(plan_compute_ms b)
bound_b=$(awk -v b="$bound_b" -v c="$plan_ms" 'BEGIN { printf "%.3f", b + c / 1000 }')
echo "case b: the planner's longest cycle then: $plan_ms ms (added to the bound)"
report b "PERCEPTION_OBJECTS stale" "$bound_b" "$B"
check "b: the robot was moving when perception froze ($(echo "$B" | cut -d' ' -f3) m/s)" \
  '[ "$B" != none ] && le 0.3 "$(echo "$B" | cut -d" " -f3)"'
check "b: wheels at rest (|v|, |wz| <= 0.05) within ${bound_b} s of the last objects" \
  '[ "$B" != none ] && le "$(echo "$B" | cut -d" " -f1)" "$(awk -v b="$bound_b" "BEGIN { print b * 1000 }")"'
check "b: the planner publishes stop trajectories (status 1)" \
  'ev PLANNER_TRAJECTORY "${T_STOP[b]}" "${T_CONT[b]}" | grep -q "status=1"'
check "b: PLANNER_STATUS says the obstacles are stale" \
  'ev PLANNER_STATUS "${T_STOP[b]}" "${T_CONT[b]}" | grep -q "message=\"moving obstacles stale"'
check "b: status shows planner ERROR 'moving obstacles stale or missing: stopping'" \
  'echo "${STATUS_OUT[b]}" | grep -Eq "^planner +ERROR +moving obstacles stale or missing: stopping"'
check "b: status counts it (result_stop_stale_objects)" 'echo "${STATUS_OUT[b]}" | grep -Eq "result_stop_stale_objects=[1-9]"'
check "b: status shows the frozen perception silent" 'echo "${STATUS_OUT[b]}" | grep -Eq "^perception +- +no status heard"'
check "b: tracking again after kill -CONT" '[ "$(resumed b)" = yes ]'

# c. Odometry (the pose source) frozen.
C=$(analyse c ROBOT_POSE exact)
report c "ROBOT_POSE stale" "$bound_c" "$C"
check "c: the robot was moving when the odometry froze ($(echo "$C" | cut -d' ' -f3) m/s)" \
  '[ "$C" != none ] && le 0.3 "$(echo "$C" | cut -d" " -f3)"'
check "c: all-zero wheel command within ${bound_c} s of the last pose" \
  '[ "$C" != none ] && le "$(echo "$C" | cut -d" " -f1)" "$(awk -v b="$bound_c" "BEGIN { print b * 1000 }")"'
check "c: BASE_STATUS says pose stale" 'ev BASE_STATUS "${T_STOP[c]}" "${T_CONT[c]}" | grep -q "reason=\"watchdog: pose stale"'
R=$(ramp_of c "pose stale")
check "c: the ramp respects stop_linear_decel (${R% *} m/s to 0 in ${R#* } ms; >= v/decel - 1 period)" \
  '[ "$R" != none ] && le "$(awk -v v="${R% *}" -v d="$lin_decel" -v r="$ctl_rate" "BEGIN { print (v / d - 1 / r) * 1000 - 1 }")" "${R#* }"'
check "c: status shows base_controller WARN 'watchdog: pose stale'" \
  'echo "${STATUS_OUT[c]}" | grep -Eq "^base_controller +WARN +watchdog: pose stale"'
check "c: status counts it (stops_pose_stale $(cnt "${STATUS_OUT[b]}" stops_pose_stale) -> $(cnt "${STATUS_OUT[c]}" stops_pose_stale))" \
  '[ "$(cnt "${STATUS_OUT[c]}" stops_pose_stale)" -gt "$(cnt "${STATUS_OUT[b]}" stops_pose_stale)" ]'
check "c: status shows perception WARN 'ROBOT_POSE stale' counted (frames_stale_pose)" \
  'echo "${STATUS_OUT[c]}" | grep -Eq "^perception +WARN +ROBOT_POSE stale" && echo "${STATUS_OUT[c]}" | grep -Eq "frames_stale_pose=[1-9]"'
check "c: status shows planner ERROR 'no valid pose: stopping' counted (result_stop_no_pose)" \
  'echo "${STATUS_OUT[c]}" | grep -Eq "^planner +ERROR +no valid pose: stopping" && echo "${STATUS_OUT[c]}" | grep -Eq "result_stop_no_pose=[1-9]"'
check "c: status shows the frozen odometry silent" 'echo "${STATUS_OUT[c]}" | grep -Eq "^odometry +- +no status heard"'
check "c: tracking again after kill -CONT" '[ "$(resumed c)" = yes ]'

for c in a b c; do echo "---- deploy/ucon status during case $c"; echo "${STATUS_OUT[$c]}"; done
echo "---- deploy/ucon status at the end"; echo "$status_end"
checks_done "in $(( $(date +%s) - t_begin )) s"
