#!/usr/bin/env bash
# make install: libraries (static and shared, with sonames), headers, apps, lcmtypes, the
# pkg-config files kelp-core.pc (the allocation-free core alone), kelp.pc (core + edge),
# kelp-plot.pc (include/kelp/edge/plot.h: scenes and cairo pictures) and kelp-viewer.pc
# (include/kelp/edge/viewer.h: the web server and replay, libmicrohttpd), and kelp_types.jar (lcm-spy's view of kelp's types, for bin/kelp-spy) when the build has it.
set -euo pipefail
cd "$(dirname "$0")/.."
B=${1:-build}
P=${PREFIX:-/usr/local}; D=${DESTDIR:-}
V=${VERSION:-0.1.0}; M=${V%%.*}
L="$D$P/lib"
install -d "$L/pkgconfig" "$D$P/include/kelp/edge" "$D$P/bin" "$D$P/share/kelp/lcmtypes" "$D$P/share/java" "$D$P/share/kelp/viewer"
install -m 644 "$B/libkelp_core.a" "$B/libkelp.a" "$B/libkelp_plot.a" "$B/libkelp_viewer.a" "$L/"
# kelp-viewer's page (found as <bin>/../share/kelp/viewer)
install -m 644 share/viewer/index.html share/viewer/viewer.js share/viewer/viewer.css "$D$P/share/kelp/viewer/"
for lib in libkelp_core libkelp libkelp_plot libkelp_viewer; do
  install -m 755 "$B/$lib.so.$V" "$L/"
  ln -sf "$lib.so.$V" "$L/$lib.so.$M"
  ln -sf "$lib.so.$M" "$L/$lib.so"
done
install -m 644 include/kelp/*.h "$D$P/include/kelp/"
install -m 644 include/kelp/edge/*.h "$D$P/include/kelp/edge/"
for h in "$B"/gen/kelp_*.h; do [ -e "$h" ] && install -m 644 "$h" "$D$P/include/kelp/"; done
install -m 644 lcmtypes/*.lcm "$D$P/share/kelp/lcmtypes/"
for b in "$B"/bin/*; do install -m 755 "$b" "$D$P/bin/"; done
# bin/kelp-spy looks for it in ../share/java
if [ -f "$B/kelp_types.jar" ]; then
  install -m 644 "$B/kelp_types.jar" "$D$P/share/java/"
else
  echo "install.sh: $B/kelp_types.jar not built (make spy-jar: needs javac and liblcm-java): kelp-spy will not find kelp's types" >&2
fi
# pc NAME DESCRIPTION LIB REQUIRES REQUIRES_PRIVATE LIBS_PRIVATE: one pkg-config file
pc() {
  cat > "$L/pkgconfig/$1.pc" <<PC
prefix=$P
exec_prefix=\${prefix}
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: $1
Description: $2
Version: $V
${4:+Requires: $4
}${5:+Requires.private: $5
}Libs: -L\${libdir} -l$3
Libs.private: $6
Cflags: -I\${includedir}
PC
}
pc kelp-core "kelp's allocation-free core: IvP solver, DCCL, priority queue, TDMA MAC, Micro-Modem protocol" \
  kelp_core "" "" "-lm"
pc kelp "autonomy and acoustic-communications library for marine vehicle computers (LCM transport)" \
  kelp "kelp-core = $V" "lcm expat ncurses" "-lmbedtls -lmbedx509 -lmbedcrypto -lserialport -lm -lpthread -lutil"
pc kelp-plot "kelp's mission pictures: scenes from LCM logs, PNG/SVG through cairo (kelp/edge/plot.h)" \
  kelp_plot "kelp = $V" "cairo" "-lm"
# (libmicrohttpd by name: its own .pc's static closure wants gnutls' private -dev packages, and
# no libmicrohttpd type is in kelp's header)
pc kelp-viewer "kelp's pMarineViewer role: the web server and log replay (kelp/edge/viewer.h)" \
  kelp_viewer "kelp = $V" "" "-lmicrohttpd -lpthread"
echo "installed into $D$P"
