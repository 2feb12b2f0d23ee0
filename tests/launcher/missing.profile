# Test profile: the second process does not exist, so nothing may start.
10  polite     test   no   -      $UCON_ROOT/tests/launcher/polite.sh $UCON_TEST_MARKER
20  ghost      test   no   -      $UCON_BIN/ucon-no-such-process
