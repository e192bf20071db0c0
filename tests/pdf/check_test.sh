#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest pdf_check: `qpdf --check` accepts the exports (structure, xref, object streams,
# the Flate data of every stream) of a full-frame and an object image at three levels.
#   check_test.sh FIXTURE WORK_DIR
# Exit 77 (ctest SKIP) only when qpdf (Debian package qpdf) is missing.
set -u
fixture=$1 work=$2
command -v qpdf >/dev/null 2>&1 || { echo "SKIP: qpdf is not installed (Debian package qpdf)"; exit 77; }
rm -rf "$work" && mkdir -p "$work" || exit 1
status=0
for spec in "gradient 96 64" "annulus 80 60"; do
  read -r kind w h <<<"$spec"
  "$fixture" sdvi "$kind" "$w" "$h" "$work/$kind.sdvi" || { echo "FAIL: fixture $kind"; exit 1; }
  for levels in 0 2 4; do
    pdf="$work/${kind}_r$levels.pdf"
    "$fixture" pdf "$work/$kind.sdvi" "$pdf" "$levels" || { echo "FAIL: export $pdf"; status=1; continue; }
    if out=$(qpdf --check "$pdf" 2>&1) && grep -q "No syntax or stream encoding errors" <<<"$out"; then
      echo "ok: qpdf --check $pdf"
    else
      echo "FAIL: qpdf --check $pdf"; echo "$out"; status=1
    fi
  done
done
exit $status
