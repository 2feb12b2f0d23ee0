# The real robot: Mid-360 driver, perception, planner, base controller on the serial motor
# board, logger. ROBOT_POSE comes from the LiDAR-inertial odometry (not started here).
# order  name             group   respawn  config                               command
20  lidar_driver     sensor  yes  $UCON_CONFIG_DIR/lidar_driver.yaml     $UCON_BIN/ucon-lidar-driver --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
30  perception       nav     yes  $UCON_CONFIG_DIR/perception.yaml       $UCON_BIN/ucon-perception --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
40  planner          nav     yes  $UCON_CONFIG_DIR/planner.yaml          $UCON_BIN/ucon-planner --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
50  base_controller  base    yes  $UCON_CONFIG_DIR/base_controller.yaml  $UCON_BIN/ucon-base-controller --config $UCON_CONFIG --backend serial --lcm-url "$UCON_LCM_URL"
60  logger           log     yes  $UCON_CONFIG_DIR/logger.yaml           $UCON_BIN/ucon-logger --config $UCON_CONFIG --log-dir "$UCON_LOG_DIR" --lcm-url "$UCON_LCM_URL"
# Optional (@foxglove: on with `deploy/ucon robot --foxglove`): live view in Foxglove, read-only,
# on 127.0.0.1 unless --foxglove-bind says otherwise (e.g. the robot's address on its network).
@foxglove 65  foxglove  viz  yes  $UCON_CONFIG_DIR/planner.yaml          $UCON_BIN/ucon-foxglove-bridge --port $UCON_FOXGLOVE_PORT --bind $UCON_FOXGLOVE_BIND --planner-config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
