#!/usr/bin/env bash
# Installs the UCON systemd unit for this checkout: deploy/systemd/install.sh [--user NAME] [--no-enable]
# Fills in the checkout path and user, copies the unit to /etc/systemd/system and the sysctl
# drop-in to /etc/sysctl.d, reloads systemd and enables the unit (it starts at the next boot;
# `systemctl start ucon-robot` starts it now). Needs root; build first (deploy/ucon build).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
USER_NAME=${SUDO_USER:-$(id -un)}
ENABLE=1
while [ $# -gt 0 ]; do
  case "$1" in
    --user) USER_NAME=$2; shift ;;
    --no-enable) ENABLE=0 ;;
    *) echo "install.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
[ "$(id -u)" -eq 0 ] || { echo "install.sh: run as root (sudo)" >&2; exit 1; }
id "$USER_NAME" >/dev/null 2>&1 || { echo "install.sh: no user '$USER_NAME'" >&2; exit 1; }
[ -x "$ROOT/build/bin/ucon-logger" ] || echo "install.sh: warning: $ROOT/build is not built yet (deploy/ucon build)" >&2
sed -e "s|@UCON_ROOT@|$ROOT|g" -e "s|@UCON_USER@|$USER_NAME|g" "$ROOT/deploy/systemd/ucon-robot.service" \
  >/etc/systemd/system/ucon-robot.service
install -m 0644 "$ROOT/deploy/systemd/90-ucon-net.conf" /etc/sysctl.d/90-ucon-net.conf
sysctl -q --system >/dev/null || true
systemctl daemon-reload
[ $ENABLE -eq 1 ] && systemctl enable ucon-robot.service
echo "installed ucon-robot.service (root $ROOT, user $USER_NAME); start: systemctl start ucon-robot"
