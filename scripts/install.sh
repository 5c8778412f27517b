#!/usr/bin/env bash
set -euo pipefail
cd "$(dirname "$0")/.."
B=${1:-build}
P=${PREFIX:-/usr/local}; D=${DESTDIR:-}
install -d "$D$P/lib/pkgconfig" "$D$P/include/kelp" "$D$P/bin" "$D$P/share/kelp/lcmtypes"
install -m 644 "$B/libkelp_core.a" "$B/libkelp.a" "$D$P/lib/"
install -m 644 include/kelp/*.h "$D$P/include/kelp/"
for h in "$B"/gen/kelp_*.h; do [ -e "$h" ] && install -m 644 "$h" "$D$P/include/kelp/"; done
install -m 644 lcmtypes/*.lcm "$D$P/share/kelp/lcmtypes/"
for b in "$B"/bin/*; do install -m 755 "$b" "$D$P/bin/"; done
[ -f "$B/kelp_types.jar" ] && install -m 644 "$B/kelp_types.jar" "$D$P/share/kelp/"
cat > "$D$P/lib/pkgconfig/kelp.pc" <<PC
prefix=$P
exec_prefix=\${prefix}
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: kelp
Description: autonomy and acoustic-communications library for marine vehicle computers (LCM transport)
Version: ${VERSION:-0.1.0}
Requires.private: lcm expat sqlite3 cairo
Libs: -L\${libdir} -lkelp -lkelp_core -lm
Libs.private: -lmbedtls -lmbedx509 -lmbedcrypto -lserialport
Cflags: -I\${includedir}
PC
echo "installed into $D$P"
