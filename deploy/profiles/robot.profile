# The real robot: Mid-360 driver, LiDAR-inertial odometry, perception, planner, base controller
# on the serial motor board, logger. The odometry publishes ROBOT_POSE in a frame that starts
# where the robot stands when it starts (odometry.yaml init.pose; it needs 0.5 s of standstill).
# It is not respawned: a restarted odometry would start a new frame under goals and a map given
# in the old one; without a pose the base controller stops (docs/robot.md, "Localization").
# order  name             group   respawn  config                               command
20  lidar_driver     sensor  yes  $UCON_CONFIG_DIR/lidar_driver.yaml     $UCON_BIN/ucon-lidar-driver --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
25  odometry         nav     no   $UCON_CONFIG_DIR/odometry.yaml         $UCON_BIN/ucon-odometry --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
30  perception       nav     yes  $UCON_CONFIG_DIR/perception.yaml       $UCON_BIN/ucon-perception --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
40  planner          nav     yes  $UCON_CONFIG_DIR/planner.yaml          $UCON_BIN/ucon-planner --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
50  base_controller  base    yes  $UCON_CONFIG_DIR/base_controller.yaml  $UCON_BIN/ucon-base-controller --config $UCON_CONFIG --backend serial --lcm-url "$UCON_LCM_URL"
60  logger           log     yes  $UCON_CONFIG_DIR/logger.yaml           $UCON_BIN/ucon-logger --config $UCON_CONFIG --log-dir "$UCON_LOG_DIR" --lcm-url "$UCON_LCM_URL"
# Optional (@foxglove: on with `deploy/ucon robot --foxglove`): live view in Foxglove, read-only,
# on 127.0.0.1 unless --foxglove-bind says otherwise (e.g. the robot's address on its network).
@foxglove 65  foxglove  viz  yes  $UCON_CONFIG_DIR/planner.yaml          $UCON_BIN/ucon-foxglove-bridge --port $UCON_FOXGLOVE_PORT --bind $UCON_FOXGLOVE_BIND --planner-config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
