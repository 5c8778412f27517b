#!/usr/bin/env python3
"""The prefix rule's renames (issue 30): every function declared in include/kelp/X.h (or
include/kelp/edge/X.h) is named kelp_X_... (or exactly kelp_X). scripts/lint_api.py checks it.

One table, applied with word-boundary replacement over the project's sources, headers, tests,
docs and scripts, so that it can be run again after merging a branch written against the old
names (it is idempotent: no new name matches an old one).

  PREFIX: every identifier that is OLD or starts with OLD_ becomes NEW / NEW_... (types of
          the family included, so a family keeps one prefix);
  EXACT:  one identifier, whole word.

    scripts/rename_api.py            apply (prints the files changed)
    scripts/rename_api.py --check    list remaining old names, exit 1 if any
"""
import os
import re
import sys

PREFIX = [
    ("kelp_rsense", "kelp_rangesense"),        # include/kelp/rangesense.h
    ("kelp_field_brs", "kelp_beaconrange"),    # include/kelp/beaconrange.h
    ("kelp_field_crs", "kelp_contactrange"),   # include/kelp/contactrange.h
    ("kelp_field_uhz", "kelp_hazardsensor"),   # include/kelp/hazardsensor.h
    ("kelp_field_upc", "kelp_pathcheck"),      # include/kelp/pathcheck.h
    ("kelp_cmdr", "kelp_commander"),           # include/kelp/commander.h
    ("kelp_cmgr", "kelp_contactmgr"),          # include/kelp/contactmgr.h
    ("kelp_m2s", "kelp_moos2sql"),             # include/kelp/moos2sql.h
    ("kelp_ts", "kelp_timerscript"),           # include/kelp/timerscript.h
    ("kelp_postlog", "kelp_alog_postlog"),     # include/kelp/edge/alog.h
    ("kelp_marine_pid", "kelp_pid_marine"),    # include/kelp/pid.h
    ("kelp_broker", "kelp_field_broker"),      # include/kelp/field.h
    ("kelp_glibc_rand", "kelp_rng_glibc"),     # include/kelp/rng.h
]

EXACT = [
    # err.h
    ("kelp_strerror", "kelp_err_str"),
    # bus.h
    ("kelp_name_set", "kelp_bus_name_set"),
    ("kelp_sync_req_encode", "kelp_bus_sync_req_encode"),
    ("kelp_sync_req_decode", "kelp_bus_sync_req_decode"),
    # lcmbus.h
    ("kelp_lcm_url", "kelp_lcmbus_url"),
    ("kelp_lcm_mission_url", "kelp_lcmbus_mission_url"),
    # nodereport.h (VIEW_* artifacts)
    ("kelp_view_kind_of", "kelp_nodereport_view_kind_of"),
    ("kelp_view_parse", "kelp_nodereport_view_parse"),
    ("kelp_view_var", "kelp_nodereport_view_var"),
] + [
    # helm.h: the behaviour implementor's calls (types stay kelp_bhv_*)
    ("kelp_bhv_" + f, "kelp_helm_bhv_" + f) for f in (
        "add_info_vars", "avoid_aof_eval", "avoid_relevance", "buf_delta", "buf_double",
        "buf_ndeltas", "buf_now", "buf_string", "buf_time", "fail", "post_bool", "post_double",
        "post_error", "post_int", "post_string", "post_warning", "set_complete", "set_param",
        "state_name", "swpt_aof_eval")
] + [
    # util.h
    ("kelp_" + f, "kelp_util_" + f) for f in (
        "be_get32", "be_get64", "be_put32", "be_put64", "civil_from_days", "clock_back",
        "clock_step", "days_from_civil", "floor_div", "fmt_fixed", "hex_decode", "hex_digit",
        "json_quote", "parse_bool", "parse_double", "parse_finite", "parse_llong", "parse_long",
        "snprintf", "strieq", "strieq_n", "time_ok", "vsnprintf", "vsnprintf_own")
]

DIRS = ["src", "include", "apps", "test", "fuzz", "bench", "docs", "firmware", "scripts", "tools",
        "share", "missions"]
FILES = ["README.md", "Makefile"]
EXTS = (".c", ".h", ".md", ".sh", ".py", ".txt", ".js", ".html", ".moos", ".bhv", ".cpp", ".in")
SELF = os.path.abspath(__file__)


def pattern():
    alts = [re.escape(o) + r"(?:_\w*)?" for o, _ in PREFIX] + [re.escape(o) for o, _ in EXACT]
    return re.compile(r"\b(?:" + "|".join(alts) + r")\b")


def new_name(old):
    for o, n in EXACT:
        if old == o:
            return n
    for o, n in PREFIX:
        if old == o or old.startswith(o + "_"):
            return n + old[len(o):]
    return old


def files(root):
    for f in FILES:
        p = os.path.join(root, f)
        if os.path.isfile(p):
            yield p
    for d in DIRS:
        for dp, dn, fn in os.walk(os.path.join(root, d)):
            dn[:] = [x for x in dn if x not in ("build", ".git")]
            for f in fn:
                p = os.path.join(dp, f)
                if f.endswith(EXTS) and os.path.abspath(p) != SELF:
                    yield p


def main():
    root = os.path.join(os.path.dirname(SELF), "..")
    check = "--check" in sys.argv[1:]
    pat = pattern()
    left = 0
    for p in sorted(files(root)):
        try:
            s = open(p, encoding="utf-8").read()
        except UnicodeDecodeError:
            continue
        if check:
            for m in pat.finditer(s):
                left += 1
                line = s.count("\n", 0, m.start()) + 1
                print(f"{os.path.relpath(p, root)}:{line}: {m.group(0)} -> {new_name(m.group(0))}")
            continue
        t = pat.sub(lambda m: new_name(m.group(0)), s)
        if t != s:
            open(p, "w", encoding="utf-8").write(t)
            print(os.path.relpath(p, root))
    return 1 if left else 0


if __name__ == "__main__":
    sys.exit(main())
