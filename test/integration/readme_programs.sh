#!/usr/bin/env bash
# The README speaks of the programs a user has: its program table ("## Programs") lists exactly
# the programs in build/bin; every MOOS-IvP / Goby app name it mentions that is not one of them
# is a row of its roles table ("### Roles"), which names the kelp program(s) that take the role
# and names no program as a role; kelp-launch's role map (src/app/launch.c) agrees with it.
. "$(dirname "$0")/lib.sh"
cd "$T"
R=$KELP_ROOT/README.md
for b in "$BIN"/*; do [ -f "$b" ] && [ -x "$b" ] && basename "$b"; done | sort > bin.txt
[ "$(wc -l < bin.txt)" -ge 40 ] || fail "only $(wc -l < bin.txt) programs in $BIN"
# the program table: first column of the rows of the "## Programs" section, before any subsection
awk '/^## Programs/{s=1; next} /^##/{s=0} s' "$R" | sed -n 's/^| `\([^`]*\)` |.*/\1/p' | sort > table.txt
[ -s table.txt ] || fail "no program table under '## Programs' in README.md"
d=$(diff table.txt bin.txt || true)
[ -z "$d" ] || fail "README's program table and build/bin differ ('<' only in the README, '>' only in build/bin):"$'\n'"$d"
# the roles table: "| role[, role] | ... |" rows
awk '/^### Roles/{s=1; next} /^##/{s=0} s' "$R" | grep -E '^\| [A-Za-z]' | grep -v '^| role |' > roles_rows.txt || true
[ -s roles_rows.txt ] || fail "no roles table under '### Roles' in README.md"
: > roles.txt
while IFS= read -r row; do
  names=$(cut -d'|' -f2 <<< "$row" | tr ',' '\n' | sed 's/^ *//; s/ *$//')
  progs=$(cut -d'|' -f3- <<< "$row" | grep -oE '`[^` ]+`' | tr -d '`' | sort -u | comm -12 - bin.txt)
  [ -n "$progs" ] || fail "the role row names no program of build/bin: $row"
  for n in $names; do
    grep -qx "$n" bin.txt && fail "$n is a program, not a role (README roles table)"
    printf '%s %s\n' "$n" "$(tr '\n' ' ' <<< "$progs")" >> roles.txt
  done
done < roles_rows.txt
# every MOOS-IvP / Goby app name in the README (p/i/u + capital) is a program or a role
# (uField is the toolbox's name)
missing=$(grep -oE '\b(p|i|u)[A-Z][A-Za-z0-9]+\b' "$R" | sort -u | grep -vx uField | comm -23 - bin.txt | comm -23 - <(cut -d' ' -f1 roles.txt | sort))
[ -z "$missing" ] || fail "README names these as if programs, yet they are neither in build/bin nor in its roles table: $(echo $missing)"
# kelp-launch's map of roles to programs: each role is in the table with its program
n=0
while read -r role prog; do
  row=$(awk -v r="$role" '$1 == r' roles.txt)
  [ -n "$row" ] || fail "kelp-launch maps $role to $prog; the README's roles table lacks $role"
  grep -qw -- "$prog" <<< "${row#* }" || fail "kelp-launch maps $role to $prog; the README's roles table says: $row"
  n=$((n + 1))
done < <(grep -oE '\{ "[A-Za-z0-9]+", "[A-Za-z0-9-]+" \}' "$KELP_ROOT/src/app/launch.c" | sed -E 's/\{ "([^"]*)", "([^"]*)" \}/\1 \2/')
[ $n -ge 5 ] || fail "read only $n roles of kelp-launch's map (src/app/launch.c)"
ok "README: $(wc -l < table.txt) programs = build/bin; $(wc -l < roles.txt) roles, each with its program ($n as kelp-launch maps them)"
