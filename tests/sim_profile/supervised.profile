# Supervision test profile (tests/sim_profile/test_supervision.sh): the real simulator, lidar
# driver, base controller and logger as in deploy/profiles/sim.profile (configs with this test's
# UDP ports, written by the test into $UCON_TEST_CFG), plus a process that always crashes.
# order  name             group   respawn  config                             command
10  simulator        main    no   $UCON_TEST_CFG/simulator.yaml        $UCON_BIN/ucon-simulator --config $UCON_CONFIG --scenario crossing --rate 1.0 --duration 0 --lcm-url "$UCON_LCM_URL"
20  lidar_driver     sensor  yes  $UCON_TEST_CFG/lidar_driver.yaml     $UCON_BIN/ucon-lidar-driver --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
50  base_controller  base    yes  $UCON_TEST_CFG/base_controller.yaml  $UCON_BIN/ucon-base-controller --config $UCON_CONFIG --backend lcm --lcm-url "$UCON_LCM_URL"
60  logger           log     yes  $UCON_TEST_CFG/logger.yaml           $UCON_BIN/ucon-logger --config $UCON_CONFIG --log-dir "$UCON_LOG_DIR" --lcm-url "$UCON_LCM_URL"
70  crasher          test    yes  -                                    $UCON_ROOT/tests/sim_profile/crash_loop.sh
