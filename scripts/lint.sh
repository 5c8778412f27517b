#!/usr/bin/env bash
# Static analysis, clean at this level (the build fails on any finding):
#  - the public header rules (scripts/lint_api.py, a second): every function of
#    include/kelp/X.h is kelp_X_*, every prototype returning a status is KELP_MUST_CHECK
#  - cppcheck: warning, style, performance, portability over src/ (core and edge) and apps/
#  - clang-tidy: clang-analyzer-*, bugprone-* (minus the purely stylistic
#    easily-swappable-parameters and reserved-identifier, which the lcm-gen headers trip),
#    cert-err34-c, over every source in src/ and apps/.
# LINT_ANALYZER=shallow runs the path-sensitive analyzer in its shallow mode (less inlining, a
# smaller path budget): a third of the CPU (measured: 265 CPU-s against 907 for the 172 files).
# CI uses it to fit its thirty minutes; `make lint` (deep) is the check before a commit.
set -euo pipefail
cd "$(dirname "$0")/.."
inc="-Iinclude -Ibuild/gen $(pkg-config --cflags-only-I lcm)"
echo "== header rules"
python3 scripts/lint_api.py
make --no-print-directory all >/dev/null
echo "== cppcheck"
cppcheck -j "$(nproc)" --enable=warning,style,performance,portability --std=c11 --inline-suppr --error-exitcode=1 -q \
  --suppress=missingIncludeSystem --suppress=unusedFunction --suppress=constParameterCallback \
  --suppress='*:build/gen/*' --suppress='*:/usr/include/*' -Iinclude -D__GNUC__ src apps
echo "cppcheck: clean"
echo "== clang-tidy"
mode=()
[ "${LINT_ANALYZER:-deep}" = shallow ] && mode=(--extra-arg=-Xclang --extra-arg=-analyzer-config --extra-arg=-Xclang --extra-arg=mode=shallow)
checks='-*,clang-analyzer-*,-clang-analyzer-security.insecureAPI.DeprecatedOrUnsafeBufferHandling,bugprone-*,-bugprone-easily-swappable-parameters,-bugprone-reserved-identifier,-bugprone-narrowing-conversions,-bugprone-implicit-widening-of-multiplication-result,cert-err34-c'
shopt -s nullglob
files=$(echo src/*/*.c src/*/edge/*.c apps/*/*.c)
# one file per process, one process per core: with two translation units in one process the
# analyzer's va_list state leaks from the first into the second (false "uninitialized va_list"
# in src/app/app.c after src/helm/util.c, in src/app/cli.c after src/app/app.c)
if ! out=$(printf '%s\n' $files | xargs -P "$(nproc)" -n 1 clang-tidy --quiet --checks="$checks" --warnings-as-errors='*' \
      --extra-arg=-std=c11 --extra-arg=-D_DEFAULT_SOURCE --extra-arg=-D_GNU_SOURCE --extra-arg=-DKELP_VERSION=\"lint\" \
      "${mode[@]}" $(for f in $inc; do printf -- '--extra-arg=%s ' "$f"; done) 2>&1); then
  echo "$out" | grep -v 'warnings generated'
  exit 1
fi
echo "clang-tidy: clean ($(echo $files | wc -w) files, analyzer ${LINT_ANALYZER:-deep})"
