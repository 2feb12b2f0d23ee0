# Test profile: a process that crashes after 0.3 s and is respawned with back-off.
10  crasher    test   yes  -      $UCON_ROOT/tests/launcher/polite.sh $UCON_TEST_MARKER 3 0.3
