# The whole stack in simulation. `deploy/ucon sim` runs it with a config folder of its own
# (run/config): the odometry starts at the scenario's start, and with --pose odometry the
# simulator publishes no ROBOT_POSE (the odometry does); with --pose ground_truth the odometry
# runs beside it on ODOMETRY_POSE, for comparison. The odometry is not respawned: a restarted
# odometry would start a new frame under a map built in the old one (no pose = the base stops).
# Columns:
# order  name             group   respawn  config                               command
# Group "main": when it exits the profile stops (the mission ends when the goals are reached
# or after --duration simulated seconds, and prints the summary).
10  simulator        sim     no   $UCON_CONFIG_DIR/simulator.yaml        $UCON_BIN/ucon-simulator --config $UCON_CONFIG --scenario "$UCON_SCENARIO" --rate $UCON_RATE --lcm-url "$UCON_LCM_URL"
20  lidar_driver     sensor  yes  $UCON_CONFIG_DIR/lidar_driver.yaml     $UCON_BIN/ucon-lidar-driver --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
25  odometry         nav     no   $UCON_CONFIG_DIR/odometry.yaml         $UCON_BIN/ucon-odometry --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
30  perception       nav     yes  $UCON_CONFIG_DIR/perception.yaml       $UCON_BIN/ucon-perception --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
40  planner          nav     yes  $UCON_CONFIG_DIR/planner.yaml          $UCON_BIN/ucon-planner --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
50  base_controller  base    yes  $UCON_CONFIG_DIR/base_controller.yaml  $UCON_BIN/ucon-base-controller --config $UCON_CONFIG --backend lcm --lcm-url "$UCON_LCM_URL"
60  logger           log     yes  $UCON_CONFIG_DIR/logger.yaml           $UCON_BIN/ucon-logger --config $UCON_CONFIG --log-dir "$UCON_LOG_DIR" --lcm-url "$UCON_LCM_URL"
70  mission          main    no   $UCON_CONFIG_DIR/mission.yaml          $UCON_BIN/ucon-mission --config $UCON_CONFIG --scenario "$UCON_SCENARIO" --duration $UCON_DURATION $UCON_MISSION_OPTS --summary-json "$UCON_LOG_DIR/summary.json" --lcm-url "$UCON_LCM_URL"
# Optional (@foxglove: on with `deploy/ucon sim --foxglove`): live view in Foxglove, read-only,
# on 127.0.0.1 unless --foxglove-bind says otherwise.
@foxglove 65  foxglove  viz  yes  $UCON_CONFIG_DIR/planner.yaml          $UCON_BIN/ucon-foxglove-bridge --port $UCON_FOXGLOVE_PORT --bind $UCON_FOXGLOVE_BIND --planner-config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
