# Plays a recorded log (lcm-logplayer) into live perception and planner processes.
# The player is "main": the profile stops when the log ends.
# order  name          group  respawn  config                          command
10  perception    nav    no   $UCON_CONFIG_DIR/perception.yaml  $UCON_BIN/ucon-perception --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
20  planner       nav    no   $UCON_CONFIG_DIR/planner.yaml     $UCON_BIN/ucon-planner --config $UCON_CONFIG --lcm-url "$UCON_LCM_URL"
90  logplayer     main   no   -                                 lcm-logplayer --speed=$UCON_REPLAY_SPEED --lcm-url="$UCON_LCM_URL" --regexp='^(?!PERCEPTION_|PLANNER_).*$' "$UCON_REPLAY_LOG"
