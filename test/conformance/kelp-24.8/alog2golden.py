#!/usr/bin/env python3
"""alog2golden.py: a pLogger .alog of a run of the real MOOS-IvP 24.8 apps -> a golden transcript
in the recordings' format (test/conformance/moos-ivp-24.8/README.md).

  alog2golden.py RUN.alog SCENARIO.scn OUT.jsonl OUT.meta.json [--driver=APP]

The log must be written with MarkDataType = true (D:/S: before each value) and LogAuxSrc = true.
The scripted client that played the .scn (uPokeDB, or any client named by --driver) is renamed
"driver", as the driver's own posts are in the recordings. t0 is the time of the driver's
first post minus the script time of that post (the first `at` line), so script times line up.
Rows of the MOOSDB (DB_*), of pLogger and the poking client's own (its status) are left out (kelp has neither); a notification that
pLogger wrote twice (same time, variable, source and value) is kept once. trx is not known from a
log: it is set to t.
"""
import json
import re
import sys


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    opts = dict(a[2:].split("=", 1) for a in sys.argv[1:] if a.startswith("--") and "=" in a)
    alog, scn, out, meta = args
    driver = opts.get("driver", "uPokeDB")
    warp = duration = None
    first_at = None
    posted = set()  # the variables the script posts
    for line in open(scn):
        w = line.split("#")[0].split()
        if not w:
            continue
        if w[0] == "warp":
            warp = float(w[1])
        elif w[0] == "duration":
            duration = float(w[1])
        elif w[0] == "at":
            posted.add(w[3])
            if first_at is None:
                first_at = float(w[1])
    logstart, community = None, ""
    rows, seen = [], set()
    for line in open(alog, errors="replace"):
        if line.startswith("%%"):
            m = re.match(r"%%\s+LOGSTART\s+(\S+)", line)
            if m:
                logstart = float(m.group(1))
            continue
        p = line.rstrip("\n").split(None, 3)
        if len(p) < 4:
            continue
        try:
            t = float(p[0])
        except ValueError:
            continue
        var, srcaux, val = p[1], p[2], p[3].rstrip(" ")
        if var.startswith("DB_") or srcaux.startswith("MOOSDB") or srcaux.startswith("pLogger"):
            continue
        if val.startswith("D:"):
            typ, v = "double", float(val[2:])
        elif val.startswith("S:"):
            typ, v = "string", val[2:]
        else:
            continue  # a continuation line of a multi-line value
        src, _, aux = srcaux.partition(":")
        if src == driver:
            if var not in posted:
                continue  # the poking client's own status, not the script's
            src = "driver"
        key = (p[0], var, srcaux, val)
        if key in seen:
            continue
        seen.add(key)
        rows.append(dict(t=t, var=var, type=typ, val=v, src=src, aux=aux))
    drv = [r["t"] for r in rows if r["src"] == "driver"]
    t0rel = (min(drv) - (first_at or 0.0)) if drv else 0.0
    rows.sort(key=lambda r: r["t"])
    counts = {}
    with open(out, "w") as f:
        for r in rows:
            t = round(r["t"] - t0rel, 4)
            o = dict(t=t, trx=t, var=r["var"], type=r["type"], val=r["val"], src=r["src"], aux=r["aux"],
                     community=community or "alpha")
            f.write(json.dumps(o, separators=(",", ":")) + "\n")
            counts[r["var"]] = counts.get(r["var"], 0) + 1
    m = dict(scenario="missions/" + scn.split("/")[-1], t0_moostime=round(logstart + t0rel, 4), warp=warp,
             duration=duration, rows=len(rows), driver_posts=len(drv), counts=counts,
             source="pLogger alog of the real MOOS-IvP 24.8 apps, converted by alog2golden.py")
    json.dump(m, open(meta, "w"), indent=None)
    print("%d rows, t0 = LOGSTART + %.3f, %d driver posts" % (len(rows), t0rel, len(drv)))


main()
