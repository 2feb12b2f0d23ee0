# The real robot: Mid-360 driver, LiDAR-inertial odometry (ROBOT_POSE; its frame starts where
# the robot is switched on, at init.pose of odometry.yaml, after a standstill of 0.5 s),
# perception, planner, base controller on the serial motor board, logger. The odometry is not
# respawned: a restart would begin a new frame under the old map; without a pose the base stops.
# order  name             group   respawn  config                               command
20  lidar_driver     sensor  yes  $UCON_CONFIG_DIR/lidar_driver.yaml     $UCON_BIN/ucon-lidar-driver --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
25  odometry         nav     no   $UCON_CONFIG_DIR/odometry.yaml         $UCON_BIN/ucon-odometry --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
30  perception       nav     yes  $UCON_CONFIG_DIR/perception.yaml       $UCON_BIN/ucon-perception --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
40  planner          nav     yes  $UCON_CONFIG_DIR/planner.yaml          $UCON_BIN/ucon-planner --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
50  base_controller  base    yes  $UCON_CONFIG_DIR/base_controller.yaml  $UCON_BIN/ucon-base-controller --config $UCON_CONFIG --backend serial --lcm-url "$UCON_LCM_URL"
60  logger           log     yes  $UCON_CONFIG_DIR/logger.yaml           $UCON_BIN/ucon-logger --config $UCON_CONFIG --log-dir "$UCON_LOG_DIR" --lcm-url "$UCON_LCM_URL"
