#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest gltf_validator: every kind of file sdvi exports (plain, Draco, control mesh, both;
# .glb and .gltf; a full-frame image with a crease pair and an object image) passes the
# Khronos glTF-Validator with zero errors and zero warnings (infos are allowed).
#   validator_test.sh FIXTURE REPO_ROOT WORK_DIR
# Exit 77 (ctest SKIP) when node or the npm packages are missing.
set -u
fixture=$1 root=$2 work=$3
command -v node >/dev/null 2>&1 || { echo "SKIP: node is not installed"; exit 77; }
[ -f "$root/scripts/npm/node_modules/gltf-validator/package.json" ] ||
  { echo "SKIP: gltf-validator missing: run npm install in scripts/npm (scripts/setup.sh does)"; exit 77; }
rm -rf "$work" && mkdir -p "$work" || exit 1
files=()
for kind in gradient object; do
  mapfile -t -O "${#files[@]}" files < <("$fixture" gltf-variants "$kind" 96 64 "$work") ||
    { echo "FAIL: export of the $kind variants"; exit 1; }
done
[ "${#files[@]}" -eq 16 ] || { echo "FAIL: expected 16 files, got ${#files[@]}"; exit 1; }
node "$root/scripts/gltf_validate.mjs" "${files[@]}" --json "$work/report.json"
