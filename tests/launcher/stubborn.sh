#!/usr/bin/env bash
# A process that ignores SIGINT and SIGTERM and has a child: the launcher must SIGKILL the
# whole group after the grace period. $1 is a marker the test greps for.
trap '' INT TERM
bash -c 'sleep 300; true' "$1" &
while true; do sleep 0.2; done
