#!/usr/bin/env bash
# A process that dies 0.2 s after every start (exit status 3): the launcher must back off.
sleep 0.2
exit 3
