#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest gltf_link_order: DEPENDENCIES.md trap 1. libdraco.so carries an older tinygltf with
# the same symbol names; in a binary that uses both, libtinygltf.so must be loaded first
# (earlier DT_NEEDED entry) so that tinygltf's symbols bind to tinygltf.
#   link_order_test.sh BINARY...
set -u
command -v readelf >/dev/null 2>&1 || { echo "SKIP: readelf (binutils) is not installed"; exit 77; }
status=0
for bin in "$@"; do
  needed=$(readelf -d "$bin" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
  t=$(echo "$needed" | grep -n '^libtinygltf' | cut -d: -f1 | head -1)
  d=$(echo "$needed" | grep -n '^libdraco' | cut -d: -f1 | head -1)
  if [ -z "$t" ] || [ -z "$d" ]; then
    echo "FAIL: $bin does not load both libtinygltf (${t:-no}) and libdraco (${d:-no})"; status=1
  elif [ "$t" -gt "$d" ]; then
    echo "FAIL: $bin loads libdraco (DT_NEEDED #$d) before libtinygltf (#$t)"; status=1
  else
    echo "ok: $bin loads libtinygltf (#$t) before libdraco (#$d)"
  fi
done
exit $status
