# Stale-input test profile (tests/sim_profile/test_stale_inputs.sh): the processes of
# deploy/profiles/sim.profile with --pose odometry (the odometry publishes ROBOT_POSE, the
# simulator none), on this test's scenario, with configs the test writes into $UCON_TEST_CFG
# (its UDP ports, the odometry started at the scenario's start). Goals come from the test
# (ucon-goal), not from the mission.
# order  name             group   respawn  config                             command
10  simulator        sim     no   $UCON_TEST_CFG/simulator.yaml        $UCON_BIN/ucon-simulator --config $UCON_CONFIG --scenario "$UCON_ROOT/tests/sim_profile/stale_inputs.yaml" --rate 1.0 --duration 0 --lcm-url "$UCON_LCM_URL"
20  lidar_driver     sensor  yes  $UCON_TEST_CFG/lidar_driver.yaml     $UCON_BIN/ucon-lidar-driver --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
25  odometry         nav     no   $UCON_TEST_CFG/odometry.yaml         $UCON_BIN/ucon-odometry --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
30  perception       nav     yes  $UCON_TEST_CFG/perception.yaml       $UCON_BIN/ucon-perception --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
40  planner          nav     yes  $UCON_TEST_CFG/planner.yaml          $UCON_BIN/ucon-planner --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
50  base_controller  base    yes  $UCON_TEST_CFG/base_controller.yaml  $UCON_BIN/ucon-base-controller --config $UCON_CONFIG --backend lcm --lcm-url "$UCON_LCM_URL"
60  logger           log     yes  $UCON_TEST_CFG/logger.yaml           $UCON_BIN/ucon-logger --config $UCON_CONFIG --log-dir "$UCON_LOG_DIR" --lcm-url "$UCON_LCM_URL"
