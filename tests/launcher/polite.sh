#!/usr/bin/env bash
# Exits at once on SIGINT. $1 is a marker; exits with status $2 after $3 seconds if given.
trap 'exit 0' INT TERM
if [ -n "${3:-}" ]; then sleep "$3"; exit "${2:-0}"; fi
while true; do sleep 0.1; done
