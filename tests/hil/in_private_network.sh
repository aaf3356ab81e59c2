#!/usr/bin/env bash
# Runs a command in a private user and network namespace whose loopback
# carries multicast, so LCM (ttl=0) never reaches a real interface. Exits 77
# (ctest's skip code) when the machine does not allow such namespaces.
set -euo pipefail
if ! command -v unshare >/dev/null || ! command -v ip >/dev/null; then
  echo "SKIP: unshare or ip (iproute2) is missing" >&2
  exit 77
fi
if ! unshare -rn true 2>/dev/null; then
  echo "SKIP: unprivileged user and network namespaces are not permitted here (unshare -rn failed)" >&2
  exit 77
fi
exec unshare -rn bash -c 'ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec "$@"' bash "$@"
