#!/usr/bin/env bash
# Runs a command in a private network namespace with only loopback, multicast routed onto it:
# DDS discovery (multicast) and UDP test traffic never reach the machine's real interfaces.
#
#   scripts/ros2/netns.sh COMMAND [ARGS...]
set -euo pipefail
if [ "${KEYLO_IN_NETNS:-}" != "1" ]; then
    SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    exec $SUDO env KEYLO_IN_NETNS=1 PATH="$PATH" HOME="${HOME:-/root}" unshare -n -- "$0" "$@"
fi
ip link set lo up
ip link set lo multicast on
ip route add 224.0.0.0/4 dev lo
exec "$@"
