#!/usr/bin/env bash
# A user program links against the installed kelp through pkg-config: shared libraries from C
# and from C++, and the static archives with `pkg-config --static`; each runs and exchanges a
# message over an LCM community (this test's private network namespace).
. "$(dirname "$0")/lib.sh"
cd "$KELP_ROOT"
version=$(sed -n 's/^VERSION *:= *//p' Makefile)
P=$T/prefix
PREFIX=$P VERSION=$version scripts/install.sh "$BUILD" >/dev/null
export PKG_CONFIG_PATH=$P/lib/pkgconfig
for f in libkelp.so.0 libkelp_core.so.0 libkelp.a libkelp_core.a pkgconfig/kelp.pc pkgconfig/kelp-core.pc; do
  [ -e "$P/lib/$f" ] || fail "not installed: lib/$f"
done
[ "$(readelf -d "$P/lib/libkelp.so.0" | sed -n 's/.*SONAME.*\[\(.*\)\]/\1/p')" = libkelp.so.0 ] || fail "libkelp soname"
pkg-config --exists kelp || fail "pkg-config does not find kelp"
# kelp-spy and the types it shows lcm-spy (share/java, where kelp-spy looks first)
[ -x "$P/bin/kelp-spy" ] || fail "not installed: bin/kelp-spy"
[ "$("$P/bin/kelp-spy" --version)" = "kelp-spy (kelp) $version" ] || fail "installed kelp-spy --version"
if [ -f "$BUILD/kelp_types.jar" ]; then   # make spy-jar (make test builds it; make asan does not)
  cmp -s "$BUILD/kelp_types.jar" "$P/share/java/kelp_types.jar" || fail "not installed: share/java/kelp_types.jar"
  classes=$(jar tf "$P/share/java/kelp_types.jar")
  for t in "$KELP_ROOT"/lcmtypes/*.lcm; do
    c=kelp/$(basename "$t" .lcm).class
    grep -qx "$c" <<< "$classes" || fail "kelp_types.jar lacks $c"
  done
  out=$(env -u DISPLAY "$P/bin/kelp-spy" 2>&1) && fail "kelp-spy ran without a display"
  grep -qF "types from $P/share/java/kelp_types.jar" <<< "$out" || fail "installed kelp-spy does not find the installed jar: $out"
  ok "kelp-spy and kelp_types.jar ($(ls "$KELP_ROOT"/lcmtypes/*.lcm | wc -l) types) installed"
fi
grep -q sqlite "$P/lib/pkgconfig/kelp.pc" && fail "kelp.pc lists sqlite3, which no code uses"
# every public header compiles on its own as C11 and as C++17
for h in "$P"/include/kelp/*.h "$P"/include/kelp/edge/*.h; do
  rel=${h#$P/include/}
  case "$rel" in kelp/kelp_*) continue ;; esac   # lcm-gen output
  echo "#include <$rel>" > "$T/h.c"
  gcc -std=c11 -Wall -Wextra -pedantic -Werror -fsyntax-only $(pkg-config --cflags kelp) "$T/h.c" || fail "$rel as C11"
  g++ -std=c++17 -Wall -Wextra -pedantic -Werror -fsyntax-only $(pkg-config --cflags kelp) -x c++ "$T/h.c" || fail "$rel as C++17"
done
ok "every public header compiles as C11 and C++17"
# a sanitizer build of the libraries (make asan) needs the sanitizer runtime in the program too
SAN=
readelf -d "$P/lib/libkelp.so.0" | grep -q 'NEEDED.*libasan' && SAN="-fsanitize=address,undefined"
# shared, C and C++
gcc -std=c11 -Wall -Werror $SAN test/link/user.c $(pkg-config --cflags --libs kelp) -o "$T/user_c" || fail "C link (shared)"
g++ -std=c++17 -Wall -Werror $SAN -x c++ test/link/user.c -x none $(pkg-config --cflags --libs kelp) -o "$T/user_cpp" ||
  fail "C++ link (shared)"
readelf -d "$T/user_c" | grep -q 'NEEDED.*libkelp.so.0' || fail "C program does not use libkelp.so.0"
readelf -d "$T/user_cpp" | grep -q 'NEEDED.*libkelp.so.0' || fail "C++ program does not use libkelp.so.0"
LD_LIBRARY_PATH=$P/lib "$T/user_c" "$KELP_LCM_URL" || fail "C program (shared) did not receive"
LD_LIBRARY_PATH=$P/lib "$T/user_cpp" "$KELP_LCM_URL" || fail "C++ program (shared) did not receive"
# static: kelp's archives, their private dependencies from pkg-config --static
static_libs=$(pkg-config --static --libs kelp | sed -e 's/-lkelp_core/-Wl,-Bstatic -lkelp_core -Wl,-Bdynamic/' \
                                                     -e 's/-lkelp\( \|$\)/-Wl,-Bstatic -lkelp -Wl,-Bdynamic\1/')
gcc -std=c11 $SAN test/link/user.c $(pkg-config --cflags kelp) $static_libs -o "$T/user_static" || fail "static link"
readelf -d "$T/user_static" | grep -q 'libkelp' && fail "static program still needs a kelp shared library"
"$T/user_static" "$KELP_LCM_URL" || fail "static program did not receive"
ok "C and C++ programs link via pkg-config (shared: $(stat -c %s "$P/lib/libkelp.so.$version") + $(stat -c %s "$P/lib/libkelp_core.so.$version") bytes; static) and run"
