#!/usr/bin/env python3
"""The public header rules (docs/ARCHITECTURE.md), checked over include/kelp/*.h and
include/kelp/edge/*.h; one "file:line: message" per violation, exit 1 if any.

1. Prefix: every function declared in include/kelp/X.h (or include/kelp/edge/X.h) is named
   kelp_X_... or exactly kelp_X. (Types and macros are not in the rule.)
2. KELP_MUST_CHECK: a prototype returning int, long or ssize_t whose comment says it can
   return a negative kelp_err (mentions KELP_ERR_, "<0", "< 0" or "negative") carries
   KELP_MUST_CHECK. The few that return a code without being a status are listed in
   NOT_STATUS with the reason.

    scripts/lint_api.py [ROOT]
"""
import glob
import os
import re
import sys

NOT_STATUS = {
    # its comment speaks of kelp_viewer_mail's refusal; it returns whether the model changed
    "kelp_viewer_tick",
}

PROTO = re.compile(r"^([A-Za-z_][\w \*]*?)\b(kelp_\w+)\s*\(", re.M)
STATUS_WORDS = re.compile(r"KELP_ERR_|<\s*0|\bnegative\b")


def blank_comments(src):
    """Comments replaced by spaces (newlines kept, so offsets and lines stay)."""
    return re.sub(r"/\*.*?\*/|//[^\n]*", lambda m: re.sub(r"[^\n]", " ", m.group(0)), src, flags=re.S)


def doc_before(src, start):
    """The comment block just before offset start (only blank lines between), or ""."""
    head = src[:start].rstrip()
    if not head.endswith("*/"):
        return ""
    i = head.rfind("/*")
    return head[i:] if i >= 0 else ""


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    bad = 0
    heads = sorted(glob.glob(os.path.join(root, "include/kelp/*.h")) + glob.glob(os.path.join(root, "include/kelp/edge/*.h")))
    for h in heads:
        rel = os.path.relpath(h, root)
        mod = os.path.basename(h)[:-2]
        src = open(h, encoding="utf-8").read()
        code = blank_comments(src)
        for m in PROTO.finditer(code):
            ret, name = m.group(1).strip(), m.group(2)
            line = code.count("\n", 0, m.start()) + 1
            if name != "kelp_" + mod and not name.startswith("kelp_" + mod + "_"):
                print(f"{rel}:{line}: {name} is declared in {mod}.h but is not named kelp_{mod}_* "
                      f"(rename it, or declare it in the header of its own family)")
                bad += 1
            words = ret.split()
            if "KELP_MUST_CHECK" in words or name in NOT_STATUS:
                continue
            base = [w for w in words if w not in ("static", "inline", "extern", "const")]
            if base not in (["int"], ["long"], ["ssize_t"]):
                continue
            # the prototype's own text (to its ';') with its trailing comment, and the comment before it
            end = code.find(";", m.end())
            tail = src[m.start():src.find("\n", end) if end >= 0 else len(src)]
            if STATUS_WORDS.search(doc_before(src, m.start()) + tail):
                print(f"{rel}:{line}: {name} returns a status (its comment says it can be a negative "
                      f"kelp_err) but lacks KELP_MUST_CHECK")
                bad += 1
    if bad:
        print(f"lint_api: {bad} violation(s) of the header rules in {len(heads)} headers")
        return 1
    print(f"lint_api: clean ({len(heads)} headers: prefix rule, KELP_MUST_CHECK on status returns)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
