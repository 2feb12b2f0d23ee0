#!/usr/bin/env bash
# Installs the Debian packages of deploy/packages.txt, without recommends.
#   install-deps.sh              every package (build, run, lcm-spy, tests)
#   install-deps.sh base [GROUP...]  the packages without a group, plus those of each GROUP
#                                (spy, test); deploy/ucon asks for what its command needs
# Idempotent: safe to run again; it refreshes the package lists and installs what is missing.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

# Package names of the wanted groups ("base" = lines without a group; no argument = all).
groups=" ${*:-all} "
mapfile -t pkgs < <(grep -v '^\s*#' "$here/packages.txt" |
  awk -v want="$groups" 'NF { g = (NF > 1 ? $2 : "base");
                              if (index(want, " all ") || index(want, " " g " ")) print $1 }')
[ ${#pkgs[@]} -gt 0 ] || { echo "install-deps: no packages in group(s):$groups" >&2; exit 2; }

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null; then SUDO="sudo"; else
    echo "install-deps: need root (or sudo) to install: ${pkgs[*]}" >&2; exit 1; fi
fi

export DEBIAN_FRONTEND=noninteractive
echo "install-deps: apt-get update"
$SUDO apt-get update -qq
echo "install-deps: installing ${#pkgs[@]} packages (already installed ones are kept)"
$SUDO apt-get install -y -qq --no-install-recommends "${pkgs[@]}"

# LCM over UDP multicast: big point clouds need a large socket receive buffer.
rmem=$(cat /proc/sys/net/core/rmem_max 2>/dev/null || echo 0)
if [ "$rmem" -lt 8388608 ]; then
  if $SUDO sysctl -q -w net.core.rmem_max=16777216 >/dev/null 2>&1; then
    echo "install-deps: raised net.core.rmem_max to 16 MiB"
  else
    echo "install-deps: warning: net.core.rmem_max is $rmem bytes and cannot be raised here;" \
         "large LCM messages may be dropped under load" >&2
  fi
fi
echo "install-deps: done"
