#!/usr/bin/env bash
# make bench: run each benchmark and print its figures.
set -uo pipefail
cd "$(dirname "$0")/.."
B=${1:-build}
export BUILD=$(cd "$B" && pwd) KELP_ROOT=$PWD
for s in bench/*.sh; do
  [ -e "$s" ] || continue
  echo "== $(basename "$s" .sh)"
  bash "$s" || echo "bench $(basename "$s") failed"
done
