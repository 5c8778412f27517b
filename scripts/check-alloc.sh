#!/usr/bin/env bash
# Fail if any object of the core archive references the heap.
set -euo pipefail
lib=$1
bad=$(nm -A -u "$lib" 2>/dev/null | grep -wE 'malloc|calloc|realloc|free|aligned_alloc|posix_memalign|strdup|strndup' || true)
# I/O and clocks are forbidden in the core too.
io=$(nm -A -u "$lib" 2>/dev/null | grep -wE 'printf|fprintf|puts|fopen|fwrite|fread|read|write|open|close|time|clock_gettime|gettimeofday|exit|abort|getenv|rand|srand' || true)
n=$(ar t "$lib" | wc -l)
if [ -n "$bad" ]; then echo "check-alloc: heap references in core:"; echo "$bad"; exit 1; fi
if [ -n "$io" ]; then echo "check-alloc: I/O, clock or exit references in core:"; echo "$io"; exit 1; fi
echo "check-alloc: $n core objects, no malloc/calloc/realloc/free, no I/O or clock calls"
