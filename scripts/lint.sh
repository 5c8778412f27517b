#!/usr/bin/env bash
# Static analysis, clean at this level (the build fails on any finding):
#  - cppcheck: warning, style, performance, portability over src/ (core and edge) and apps/
#  - clang-tidy: clang-analyzer-*, bugprone-* (minus the purely stylistic
#    easily-swappable-parameters and reserved-identifier, which the lcm-gen headers trip),
#    cert-err34-c, over every source in src/.
set -euo pipefail
cd "$(dirname "$0")/.."
inc="-Iinclude -Ibuild/gen $(pkg-config --cflags-only-I lcm)"
make --no-print-directory all >/dev/null
echo "== cppcheck"
cppcheck --enable=warning,style,performance,portability --std=c11 --inline-suppr --error-exitcode=1 -q \
  --suppress=missingIncludeSystem --suppress=unusedFunction --suppress=constParameterCallback \
  --suppress='*:build/gen/*' --suppress='*:/usr/include/*' -Iinclude -D__GNUC__ src apps
echo "cppcheck: clean"
echo "== clang-tidy"
checks='-*,clang-analyzer-*,-clang-analyzer-security.insecureAPI.DeprecatedOrUnsafeBufferHandling,bugprone-*,-bugprone-easily-swappable-parameters,-bugprone-reserved-identifier,-bugprone-narrowing-conversions,-bugprone-implicit-widening-of-multiplication-result,cert-err34-c'
shopt -s nullglob
files=$(echo src/*/*.c src/*/edge/*.c apps/*/*.c)
out=$(clang-tidy --quiet --checks="$checks" --warnings-as-errors='*' $files -- -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -DKELP_VERSION=\"lint\" $inc 2>&1) || { echo "$out" | grep -v 'warnings generated' ; exit 1; }
echo "clang-tidy: clean ($(echo $files | wc -w) files)"
