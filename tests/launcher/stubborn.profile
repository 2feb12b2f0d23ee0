# Test profile: one process ignores SIGINT, one stops politely.
# order name      group  respawn config command
10  polite     test   no   -      $UCON_ROOT/tests/launcher/polite.sh $UCON_TEST_MARKER
20  stubborn   test   no   -      $UCON_ROOT/tests/launcher/stubborn.sh $UCON_TEST_MARKER
