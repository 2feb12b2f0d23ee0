# Test profile for host placement (--only / --except): three groups, one process each.
# order name      group   respawn config command
10  sensorproc   sensor  no   -      $UCON_ROOT/tests/launcher/polite.sh $UCON_TEST_MARKER
20  navproc      nav     no   -      $UCON_ROOT/tests/launcher/polite.sh $UCON_TEST_MARKER
30  logproc      log     no   -      $UCON_ROOT/tests/launcher/polite.sh $UCON_TEST_MARKER
