#!/usr/bin/env bash
# A user program links against the installed kelp through pkg-config: shared libraries from C
# and from C++, and the static archives with `pkg-config --static`; each runs and exchanges a
# message over an LCM community (this test's private network namespace). Then every function
# of every installed header links through that header's pkg-config file (kelp, kelp-plot,
# kelp-viewer), from C, C++ and statically.
. "$(dirname "$0")/lib.sh"
cd "$KELP_ROOT"
version=$(sed -n 's/^VERSION *:= *//p' Makefile)
P=$T/prefix
PREFIX=$P VERSION=$version scripts/install.sh "$BUILD" >/dev/null
export PKG_CONFIG_PATH=$P/lib/pkgconfig
for f in libkelp.so.0 libkelp_core.so.0 libkelp_plot.so.0 libkelp_viewer.so.0 libkelp.a libkelp_core.a libkelp_plot.a \
         libkelp_viewer.a pkgconfig/kelp.pc pkgconfig/kelp-core.pc pkgconfig/kelp-plot.pc pkgconfig/kelp-viewer.pc; do
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
# (kelp's archives static, the libraries they need shared)
static_libs() { pkg-config --static --libs "$@" | sed -E 's/-l(kelp[a-z_]*)( |$)/-Wl,-Bstatic -l\1 -Wl,-Bdynamic\2/g'; }
gcc -std=c11 $SAN test/link/user.c $(pkg-config --cflags kelp) $(static_libs kelp) -o "$T/user_static" || fail "static link"
readelf -d "$T/user_static" | grep -q 'libkelp' && fail "static program still needs a kelp shared library"
"$T/user_static" "$KELP_LCM_URL" || fail "static program did not receive"
ok "C and C++ programs link via pkg-config (shared: $(stat -c %s "$P/lib/libkelp.so.$version") + $(stat -c %s "$P/lib/libkelp_core.so.$version") bytes; static) and run"

# every function of every installed header: a program takes the address of each (gcc -aux-info
# lists the functions a header declares) and links through that header's .pc alone, shared
# from C and C++ and static from C: edge/plot.h through kelp-plot, edge/viewer.h through
# kelp-viewer, the others through kelp (which requires kelp-core)
pc_of() { case "$1" in kelp/edge/plot.h) echo kelp-plot ;; kelp/edge/viewer.h) echo kelp-viewer ;; *) echo kelp ;; esac; }
total=0
for pc in kelp kelp-plot kelp-viewer; do
  src=$T/addr_$pc.c; : > "$src"; hdrs=()
  for h in "$P"/include/kelp/*.h "$P"/include/kelp/edge/*.h; do
    rel=${h#$P/include/}
    [ "$(pc_of "$rel")" = "$pc" ] || continue
    echo "#include <$rel>" >> "$src"; hdrs+=("$h")
  done
  gcc -std=c11 -fsyntax-only -aux-info "$T/aux_$pc.txt" $(pkg-config --cflags "$pc") "$src" || fail "$pc: headers do not compile"
  # the functions declared in this .pc's own headers (not in the libc headers they include)
  fns=$(for h in "${hdrs[@]}"; do grep -F "/* $h:" "$T/aux_$pc.txt" || true; done |
        sed -E 's|^/\* [^*]* \*/ ||; s/^[^(]*[ *]([A-Za-z_][A-Za-z0-9_]*) \(.*/\1/' | sort -u)
  n=$(wc -w <<< "$fns")
  [ "$n" -ge 1 ] || fail "$pc: no function found in its headers"
  { echo "#include <stdio.h>"
    echo "static void (*volatile fns[])(void) = {"
    for f in $fns; do echo "    (void (*)(void))$f,"; done
    echo "};"
    echo "int main(void) { unsigned n = 0; for (unsigned i = 0; i < sizeof fns / sizeof fns[0]; i++) n += fns[i] != 0;"
    echo "    printf(\"%u\\n\", n); return n != $n; }"; } >> "$src"
  gcc -std=c11 -Wall -Werror $SAN "$src" $(pkg-config --cflags --libs "$pc") -o "$T/addr_c" ||
    fail "$pc: a C program using every function of its headers does not link with pkg-config --libs $pc"
  g++ -std=c++17 -Wall -Werror $SAN -x c++ "$src" -x none $(pkg-config --cflags --libs "$pc") -o "$T/addr_cpp" ||
    fail "$pc: a C++ program using every function of its headers does not link with pkg-config --libs $pc"
  gcc -std=c11 $SAN "$src" $(pkg-config --cflags "$pc") $(static_libs "$pc") -o "$T/addr_static" ||
    fail "$pc: static link with pkg-config --static --libs $pc"
  for x in addr_c addr_cpp addr_static; do
    [ "$(LD_LIBRARY_PATH=$P/lib "$T/$x")" = "$n" ] || fail "$pc: $x does not run"
  done
  total=$((total + n))
  echo "$pc: the $n functions of ${#hdrs[@]} headers link (C, C++, static)"
done
ok "every function of every installed header ($total) links through its pkg-config file"
