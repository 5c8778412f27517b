#!/usr/bin/env bash
# The installed headers (and lcmtypes) and the README cite only what a user has: public
# documents (docs/REFERENCES.md) and kelp's own docs/. Not the project's working papers:
# "seed 002 section 2.5", "the seed's ...", "uField seed", "acomms.md 7.2" (a .md file that is
# not in kelp), "§3.8", "../shared/...", "spec/". Each pattern is first shown to catch a sample.
. "$(dirname "$0")/lib.sh"
cd "$T"
P=$T/prefix
PREFIX=$P "$KELP_ROOT/scripts/install.sh" "$BUILD" > /dev/null 2>&1 || fail "install.sh"
files=("$KELP_ROOT/README.md" "$P"/include/kelp/*.h "$P"/include/kelp/edge/*.h "$P"/share/kelp/lcmtypes/*.lcm)
[ ${#files[@]} -ge 60 ] || fail "only ${#files[@]} files to read"
# citations of the project's working papers (the seeds and their digests)
bad='\bseeds? +[0-9]{3}\b|\bseed'"'"'s\b|(^|[.;] )Seed \(|\b(the|uField|a|of) seed\b[^.]*\b(section|chapter|ch\.|listing|model|rule|defaults?)|\bseed (ch\.|chapter|section|\(sec)|\bseed: |\(the seed\)|§|\.\./shared|\bshared/(seeds|spec|conformance)|\bspec/[a-z]'
for sample in "Defaults of seed 002 section 2.5" "the seed's model" "uField seed chapter 10" "(seed: \"VAR = value\")" \
              "xrelay (seed 004 §3.8)" "(../shared/conformance/x)" "AUTO_BRIDGE_* (24.8: true; seed: false)" "report range (the seed), not" ". Seed (pmb = true, a mission"; do
  grep -qiE "$bad" <<< "$sample" || fail "the pattern misses: $sample"
done
for fine in "so a run is reproducible from its seed." "kelp_rng seeded by SEED_RANDOM" "As srand(seed); seed 0 acts as 1" \
            "Take a configuration (copied) and a seed. Draws"; do
  ! grep -qiE "$bad" <<< "$fine" || fail "the pattern flags random-number prose: $fine"
done
hits=$(grep -nHiE "$bad" "${files[@]}" | sed "s|$P/||; s|$KELP_ROOT/||" || true)
[ -z "$hits" ] || fail "citations of documents a user does not have:"$'\n'"$hits"
# every .md a file names is one of kelp's (docs/, or the README itself)
n=0
while IFS=: read -r f md; do
  b=$(basename "$md")
  [ -f "$KELP_ROOT/docs/$b" ] || [ -f "$KELP_ROOT/$b" ] || [ -f "$KELP_ROOT/${md#./}" ] ||
    fail "${f#$P/} cites $md, which is not in kelp (docs/)"
  n=$((n + 1))
done < <(grep -oHE '[A-Za-z0-9_./-]+\.md\b' "${files[@]}" | sed "s|^$KELP_ROOT/||")
grep -qE '[A-Za-z0-9_./-]+\.md\b' <<< "Defaults (acomms.md 7.2)" || fail "the .md pattern misses acomms.md"
ok "${#files[@]} files (README, installed headers and lcmtypes) cite no working paper; $n .md citations, each in docs/"
