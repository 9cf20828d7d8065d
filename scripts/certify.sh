#!/usr/bin/env bash
# The full equivalence certification (tests/support/equivalence.h, tier "full"): every ReSTIR PT shift x MIS
# x Russian roulette on the stripes and mirror-glass scenes, ReSTIR DI without visibility reuse and
# ReSTIR GI, at margins of 0.5% (image mean) and 2% (8x8 blocks), alpha 0.01. ~40 minutes on two
# cores; prints one line per configuration and exits non-zero if any fails.
#   bash scripts/certify.sh [--jobs N]
source "$(dirname "$0")/common.sh"
jobs="$(nproc)"
while [ $# -gt 0 ]; do
  case "$1" in
    --jobs) jobs="$2"; shift 2 ;;
    *) echo "usage: scripts/certify.sh [--jobs N]" >&2; exit 2 ;;
  esac
done
install_missing_packages
build "$ROOT/build"
cd "$ROOT/build"
RESTIR_EQUIVALENCE=full ctest -j "$jobs" -R '^slow_equivalence_' --output-on-failure --timeout 14400 -V |
  grep -E 'MESSAGE|tests passed|tests failed|Failed' | sed 's/.*MESSAGE: //'
exit "${PIPESTATUS[0]}"
