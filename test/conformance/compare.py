#!/usr/bin/env python3
"""Compare kelp's transcript of a conformance scenario with the recording of MOOS-IvP 24.8.

  compare.py --golden DIR --kelp DIR [--allow docs/CONFORMANCE.md] [SCENARIO ...]
  compare.py --self-test --golden DIR

Each scenario is compared figure by figure; a figure is one thing a MOOS-IvP user would check
(the set of variables an app publishes, one variable's count, its value format, the values it
carries and when, a message reaching a vehicle, the APPCAST's counters and lines, the status
string's keys and cadence). The last table gives, per scenario, the figures that agree.

Timing tolerance (MOOS seconds): an app iterates every P = 1/AppTick MOOS seconds, and a
posting made in reply to an input lands in the app's next iteration, so two runs of the same
app may place it up to one period apart each way: tol = 2 P, plus 0.1 s x warp of scheduling
noise (the recordings' README).
Counts are taken over the scenario window 0 <= t <= duration of each transcript (never from
the meta files: the recordings' meta counts include start-up rows their transcripts lack).
Each end of the window may gain or lose what the app posts within tol, so a count may differ
by rate x tol at each end: 2 x rate x tol, rounded up, + 1.
A cadence (<APP>_STATUS) is the mean interval over the window, (last - first) / (n - 1): only
its two ends carry jitter, so it may differ by 2 tol / (n - 1).
Start-up (t < 0): each side's apps start a few seconds before t0 at a time that is not
behaviour, and the recordings' driver dropped some start-up rows (first APPCASTs, <APP>_PID,
iteration-1 postings). So start-up rows are compared by value, not time; a row 24.8 posted
before t0 must be in kelp's transcript, a kelp row before t0 that the recording lacks is not a
difference, nor is a variable that kelp posts only before t0 and the recording never shows.
The driver's own posts must agree one to one with the recording's (count per variable and
vehicle, script time within tol, @MOOSTIME within tol, vehicle positions within the fastest
vehicle's speed x the two posts' time difference + 0.01 of two-decimal rounding).
Nothing else is tuned.

A scenario is gated when its name matches GATED; its disagreeing figures make the exit status
non-zero unless a row of the allow file (a markdown table: | scenario | figure | app | 24.8 does
| kelp does | why |, scenario and figure as fnmatch globs) lists them.
"""
import argparse
import bisect
import collections
import fnmatch
import json
import math
import os
import re
import sys

GATED = ["nodecomms_*", "msghandler_*", "pathcheck_g1", "crs_e1_nonoise", "vehicle_*", "cmgr_c*", "brs_d1_nonoise",
         "hazard_f1_fixedseed"]
# values that are measured timings (uFldNodeComms's RTE: real seconds between two of its
# iterations that saw a vehicle's report) are compared by count and format only
PERIODIC_SKIP_VALUES = re.compile(r".*_STATUS$|^APPCAST$|.*_ITER_(GAP|LEN)$|.*_PID$|^RTE$")


def load_rows(path):
    rows = []
    if not os.path.exists(path) and os.path.exists(path + ".gz"):
        import gzip
        opener = lambda: gzip.open(path + ".gz", "rt")
    else:
        opener = lambda: open(path)
    with opener() as f:
        for line in f:
            line = line.strip()
            if line:
                rows.append(json.loads(line))
    return rows


def mission_info(path):
    """AppTick per ProcessConfig block and the global MOOSTimeWarp."""
    ticks, warp, cur = {}, 1.0, None
    for line in open(path):
        line = line.split("//")[0].strip()
        m = re.match(r"ProcessConfig\s*=\s*(\S+)", line, re.I)
        if m:
            cur = m.group(1)
            ticks[cur] = 4.0
            continue
        m = re.match(r"(\w+)\s*=\s*(\S+)", line)
        if not m:
            continue
        k, v = m.group(1).lower(), m.group(2)
        try:
            if cur and k == "apptick":
                ticks[cur] = float(v)
            elif not cur and k == "moostimewarp":
                warp = float(v)
        except ValueError:
            pass
    return ticks, warp


class Figure:
    def __init__(self, fid, ok, detail=""):
        self.fid, self.ok, self.detail = fid, ok, detail


def is_num(s):
    try:
        float(s)
        return s.strip() != "" and s.strip().lower() not in ("nan", "inf", "-inf", "infinity")
    except ValueError:
        return False


def num_class(s):
    if not is_num(s):
        return "text"
    if "e" in s.lower():
        return "exp"
    if "." not in s:
        return "int"
    return "d%d" % len(s.split(".", 1)[1])


def kv_pairs(val):
    """A MOOS key=value list, or None when the string is not one."""
    if "=" not in val:
        return None
    out = []
    for part in val.split(","):
        if "=" not in part:
            if out:  # a comma inside a value: glue it back
                out[-1] = (out[-1][0], out[-1][1] + "," + part)
                continue
            return None
        k, v = part.split("=", 1)
        out.append((k, v))
    return out


class Norm:
    """Values made comparable: absolute MOOS times inside strings become scenario times."""

    def __init__(self, t0, tol, ntol=0.05):
        self.t0, self.tol, self.ntol = t0, tol, ntol

    def tokens(self, val):
        if not isinstance(val, str):
            x = float(val)  # a double may be a MOOS time too (CONTACT_CLOSEST_TIME)
            return [("t", x - self.t0)] if abs(x - self.t0) < 1e6 else [("n", x)]
        toks = []
        for m in re.finditer(r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?|[^-\d]+|-", val):
            s = m.group(0)
            if is_num(s):
                x = float(s)
                if abs(x - self.t0) < 1e6:
                    toks.append(("t", x - self.t0))
                else:
                    toks.append(("n", x))
            else:
                toks.append(("s", s))
        return toks

    def same(self, a, b, times=True):
        ta, tb = self.tokens(a), self.tokens(b)
        if len(ta) != len(tb):
            return False
        for (ka, va), (kb, vb) in zip(ta, tb):
            if ka != kb:
                return False
            if ka == "s" and va != vb:
                return False
            if ka == "t" and times and abs(va - vb) > self.tol:
                return False
            # positions and speeds computed at a post time that jitters by milliseconds
            if ka == "n" and abs(va - vb) > self.ntol + 1e-6 * abs(va):
                return False
        return True


def match_rows(g, k, norm, tol):
    """Greedy time-ordered matching of rows with the same value within tol. Returns the
    unmatched rows of each side."""
    used = [False] * len(k)
    miss = []
    j0 = 0
    for r in g:
        found = False
        while j0 < len(k) and k[j0]["t"] < r["t"] - tol:
            j0 += 1
        j = j0
        while j < len(k) and k[j]["t"] <= r["t"] + tol:
            if not used[j] and k[j]["type"] == r["type"] and norm.same(r["val"], k[j]["val"]):
                used[j] = True
                found = True
                break
            j += 1
        if not found:
            miss.append(r)
    extra = [k[j] for j in range(len(k)) if not used[j]]
    return miss, extra


def short(v, n=110):
    s = str(v)
    return s if len(s) <= n else s[:n] + "..."


def appcast_fields(val):
    f = val.split("!@#")
    out = collections.OrderedDict()
    for x in f:
        if "=" in x:
            k, v = x.split("=", 1)
            out.setdefault(k, v)
    return out


def mask(s):
    return re.sub(r"\d+(\.\d+)?", "#", s)


def compare(scn, golden_dir, kelp_dir):
    figs = []
    mission = os.path.join(golden_dir, "missions", scn + ".moos")
    ticks, warp = mission_info(mission)
    gmeta = json.load(open(os.path.join(golden_dir, "golden", scn + ".meta.json")))
    G = load_rows(os.path.join(golden_dir, "golden", scn + ".jsonl"))
    kpath = os.path.join(kelp_dir, scn + ".jsonl")
    if not os.path.exists(kpath):
        return [Figure("run", False, "no kelp transcript (%s)" % kpath)]
    kmeta = json.load(open(os.path.join(kelp_dir, scn + ".meta.json")))
    K = load_rows(kpath)
    dur = float(gmeta["duration"])
    period = max(1.0 / t for t in ticks.values()) if ticks else 0.25
    tol = 2 * period + 0.1 * warp
    G = [r for r in G if not r["var"].startswith("DB_") and r["t"] <= dur]
    K = [r for r in K if not r["var"].startswith("DB_") and r["t"] <= dur]
    Gw = [r for r in G if r["t"] >= 0]  # the scenario window
    Kw = [r for r in K if r["t"] >= 0]
    gn = Norm(gmeta["t0_moostime"], tol)
    kn = Norm(kmeta["t0_moostime"], tol)

    def rel(rows, side):
        n = gn if side == "g" else kn
        out = []
        for r in rows:
            r2 = dict(r)
            if r["type"] == "string":
                r2["val"] = "".join(
                    ("%.6f" % (v + 1e12)) if k == "t" else ("%.17g" % v if k == "n" else v) for k, v in n.tokens(r["val"]))
            elif r["type"] == "double":
                k, v = n.tokens(r["val"])[0]
                r2["val"] = v + 1e12 if k == "t" else v
            out.append(r2)
        return out

    norm = Norm(1e12, tol)  # after rel(), times sit at 1e12 + scenario time on both sides
    Gr, Kr = rel(G, "g"), rel(K, "k")

    # driver posts: the script was played the same way (a check on the suite itself)
    figs.extend(driver_figures(G, K, gmeta, kmeta, tol, scenario_speed(
        os.path.join(golden_dir, "missions", scn + ".scn"))))

    # half the shortest interval between one vehicle's reports in the script: two relays carry
    # the same report when their TIME= differ by less
    report_half = 0.5 / max([scenario_rate(os.path.join(golden_dir, "missions", scn + ".scn"))] + [1e-9])

    vehicle = is_vehicle(G)
    apps = sorted(ticks)
    by = collections.defaultdict(list)  # the window's rows per (side, app, var)
    pre = collections.defaultdict(list)  # start-up rows (t < 0)
    raw = collections.defaultdict(list)  # every row as posted (number formats)
    for side, rows, rrows in (("g", Gr, G), ("k", Kr, K)):
        for r, r0 in zip(rows, rrows):
            if r["src"] != "driver":
                (by if r["t"] >= 0 else pre)[(side, r["src"], r["var"])].append(r)
                raw[(side, r["src"], r["var"])].append(r0)
    for app in apps:
        gv = {v for (s, a, v) in list(by) + list(pre) if s == "g" and a == app}
        kv = {v for (s, a, v) in by if s == "k" and a == app}
        # a variable kelp posts only at start-up is a difference only if the recording shows it
        kv |= {v for (s, a, v) in pre if s == "k" and a == app and v in gv}
        ok = gv == kv
        figs.append(Figure("vars/%s" % app, ok, "" if ok else "only 24.8: %s; only kelp: %s" % (
            sorted(gv - kv), sorted(kv - gv))))
        # the source aux of an app's postings (the helm's "<iteration>:<behaviour>"): per variable
        # the aux texts with their digits masked, where the recording has any; each of the
        # recording's must be among kelp's (not the other way: the recordings miss the first
        # posting of a variable new to the MOOSDB, and with it a behaviour's aux at times)
        gaux, kaux = collections.defaultdict(set), collections.defaultdict(set)
        for (s_, a_, v_), rr in by.items():
            if a_ == app:
                for r in rr:
                    (gaux if s_ == "g" else kaux)[v_].add(re.sub(r"\d+", "#", r.get("aux") or ""))
        bad = sorted(v for v in gaux if v in kaux and any(gaux[v]) and not gaux[v] <= kaux[v])
        if any(any(x) for x in gaux.values()):
            figs.append(Figure("aux/%s" % app, not bad, "" if not bad else "; ".join(
                "%s: 24.8 %s, kelp %s" % (v, sorted(gaux[v]), sorted(kaux[v])) for v in bad[:4])))
        for var in sorted(gv | kv):
            g = by.get(("g", app, var), [])
            k = by.get(("k", app, var), [])
            gp = pre.get(("g", app, var), [])
            kp = pre.get(("k", app, var), [])
            if not (g or gp) or not (k or kp):
                continue
            # count over the window
            rate = len(g) / dur
            ctol = int(math.ceil(rate * 2 * tol)) + 1
            ok = abs(len(g) - len(k)) <= ctol
            figs.append(Figure("count/%s" % var, ok, "" if ok else "24.8 %d, kelp %d (tolerance %d)" % (len(g), len(k), ctol)))
            if var.endswith("_STATUS"):
                figs.extend(status_figures(app, var, g, k, tol))
                continue
            if var == "APPCAST":
                figs.extend(appcast_figures(app, G, K))
                continue
            figs.append(format_figure(var, raw[("g", app, var)], raw[("k", app, var)]))
            if PERIODIC_SKIP_VALUES.match(var) or vehicle:
                continue  # a vehicle's values: vehicle_figures judges what it does
            # uFldPathCheck's odometry: per vehicle in pathcheck_figures, where a value the other
            # side skipped (two of a vehicle's reports in one of its iterations) is told apart
            if scn.startswith("pathcheck_") and var == "UPC_ODOMETRY_REPORT":
                continue
            # uFldHazardSensor's classify answers and options summary: hazard_figures
            if scn.startswith("hazard_") and app == "uFldHazardSensor" and HAZARD_OWN_VALUES.match(var):
                g = [r for r in g if not hazard_classify_circle(r)]
                k = [r for r in k if not hazard_classify_circle(r)]
                gp = [r for r in gp if not hazard_classify_circle(r)]
                kp = [r for r in kp if not hazard_classify_circle(r)]
                if var != "VIEW_CIRCLE":
                    continue
            # uFldNodeComms relays, on each iteration, the latest report of each vehicle: when two
            # of a vehicle's reports arrive within one iteration (the iteration's phase against
            # the reports', not behaviour) the older is relayed to no one. A relay one side made
            # of a report the other side relayed to no one at all is that, not a difference.
            vnorm = norm
            if scn.startswith("pathcheck_") and var == "UPC_ODOMETRY_REPORT":
                # sums of positions the driver rounds to 0.01 at its own post times, printed to
                # one decimal: two runs may print one unit (0.1) apart
                vnorm = Norm(1e12, tol, ntol=0.1)
            if scn.startswith("nodecomms_") and var.startswith("NODE_REPORT_") and app == "uFldNodeComms":
                g = [r for r in g if relayed_anywhere(Kr, r, report_half)]
                k = [r for r in k if relayed_anywhere(Gr, r, report_half)]
                # a relay names its report by TIME=: within half a report interval, so that a
                # report relayed to someone on one side only is found, not paired with the next
                vnorm = Norm(1e12, report_half)
            # uFldMessageHandler posts its summary on each iteration with mail and on every 100th
            # iteration: the 100th-iteration repeat of the last value falls where the app's start
            # put it, and a value superseded within one iteration period (a burst split across
            # two iterations) is the iteration's phase; both are left to summary/sequence
            if scn.startswith("msghandler_") and var == "UMH_SUMMARY_MSGS":
                g, k = summary_phase(g, tol), summary_phase(k, tol)
            # values in time over the window; what is left near t0 may pair with the other
            # side's start-up rows (by value: start-up timing is not behaviour)
            miss, extra = match_rows(g, k, vnorm, tol)
            pmiss, pextra = match_values(gp + [r for r in miss if r["t"] < tol], kp + [r for r in extra if r["t"] < tol], norm)
            miss = [r for r in miss if r["t"] >= tol] + [r for r in pmiss]
            extra = [r for r in extra if r["t"] >= tol] + [r for r in pextra if r["t"] >= 0]
            # a comms pulse's far end is the target's latest position when the relay is made: the
            # same pulse one report of the target earlier or later is the iteration's phase
            if scn.startswith("nodecomms_") and var == "VIEW_COMMS_PULSE":
                gi, ki = report_index(G), report_index(K)
                miss, extra = pair_pulses(miss, extra, gi, ki, tol)
                # a pulse goes with a relay: a pulse of a report the other side relayed to no one
                # (two of its reports in one iteration) is the same phase as above
                gt, kt = report_times(Gr), report_times(Kr)
                miss = [r for r in miss if not pulse_unrelayed(r, gi, kt, Kr, report_half)]
                extra = [r for r in extra if not pulse_unrelayed(r, ki, gt, Gr, report_half)]
            # the window's end: a posting within tol of it may fall either side
            miss = [r for r in miss if r["t"] <= dur - tol]
            extra = [r for r in extra if r["t"] <= dur - tol]
            g, k = gp + g, kp + k
            ok = not miss and not extra
            d = ""
            if not ok:
                d = "%d of 24.8's %d not in kelp's, %d of kelp's %d not in 24.8's" % (len(miss), len(g), len(extra), len(k))
                if miss:
                    d += "; 24.8 t=%.2f %s" % (miss[0]["t"], short(raw_of(G, miss[0])))
                if extra:
                    d += "; kelp t=%.2f %s" % (extra[0]["t"], short(raw_of(K, extra[0])))
            figs.append(Figure("values/%s" % var, ok, d))
            # source-aux
            ga = sorted({r.get("aux", "") for r in g})
            ka = sorted({r.get("aux", "") for r in k})
            if ga != ka or any(ga):
                figs.append(Figure("aux/%s" % var, ga == ka, "" if ga == ka else "24.8 %s, kelp %s" % (ga, ka)))
    Gwr, Kwr = [r for r in Gr if r["t"] >= 0], [r for r in Kr if r["t"] >= 0]
    if scn.startswith("nodecomms_"):
        figs.extend(nodecomms_figures(Gwr, Kwr, tol, dur))
    if scn.startswith("msghandler_"):
        figs.extend(msghandler_figures(Gwr, Kwr, tol))
    if scn.startswith("cmgr_"):
        figs.extend(cmgr_figures(Gwr, Kwr, tol, dur))
    if scn.startswith("hazard_"):
        figs.extend(hazard_figures(Gwr, Kwr, tol, 1.0 / ticks.get("uFldHazardSensor", 4) * warp, G, K))
    if vehicle:
        figs.extend(vehicle_figures(G, K))
    vmax = scenario_speed(os.path.join(golden_dir, "missions", scn + ".scn"))
    if scn.startswith("pathcheck_"):
        figs.extend(pathcheck_figures(G, K, Gwr, Kwr, tol, dur, vmax, 1.0 / ticks.get("uFldPathCheck", 4) * warp))
    if scn.startswith("brs_") or scn.startswith("crs_"):
        figs.extend(rangesensor_figures(G, K, Gwr, Kwr, tol, vmax, "BRS" if scn.startswith("brs_") else "CRS"))
    return figs


def report_index(rows):
    """(X, Y) rounded to 0.01 -> (vehicle, index of its report) over the driver's node reports."""
    out, n = {}, collections.Counter()
    for r in rows:
        if r["src"] == "driver" and r["var"] == "NODE_REPORT" and r["type"] == "string":
            f = dict(kv_pairs(r["val"]) or [])
            if "NAME" in f and "X" in f and "Y" in f:
                out.setdefault((round(float(f["X"]), 2), round(float(f["Y"]), 2)), (f["NAME"], n[f["NAME"]]))
                n[f["NAME"]] += 1
    return out


def report_times(rows):
    """(vehicle, index of its report) -> the report's TIME (after rel()), over the driver's node
    reports, counted as report_index counts them."""
    out, n = {}, collections.Counter()
    for r in rows:
        if r["src"] == "driver" and r["var"] == "NODE_REPORT" and r["type"] == "string":
            rid = report_id(r["val"])
            if rid:
                out[(rid[0], n[rid[0]])] = rid[1]
                n[rid[0]] += 1
    return out


def pulse_unrelayed(r, idx, other_times, other_rows, half):
    """Whether the report a pulse starts from was relayed to no one on the other side."""
    d = dict(kv_pairs(r["val"]) or [])
    try:
        src = idx.get((round(float(d.get("sx", "nan")), 2), round(float(d.get("sy", "nan")), 2)))
    except ValueError:
        return False
    t = other_times.get(src) if src else None
    if t is None:
        return False
    return not relayed_anywhere(other_rows, {"type": "string", "val": "NAME=%s,TIME=%.6f" % (src[0], t)}, half)


def pair_pulses(miss, extra, gidx, kidx, tol):
    """Pairs left-over pulses that agree but for the far end (tx, ty and the beam width it sets),
    one report of the same target apart. Both ends are named by the driver's report they come
    from on each side (vehicle, index): the two runs' positions differ in the last decimal with
    the driver's timing. Returns what stays unpaired."""
    def at(idx, d, kx, ky):
        try:
            return idx.get((round(float(d.get(kx, "nan")), 2), round(float(d.get(ky, "nan")), 2)))
        except ValueError:
            return None

    def parts(r, idx):
        f = kv_pairs(r["val"]) or []
        d = dict(f)
        rest = tuple((k, v) for k, v in f if k not in ("sx", "sy", "tx", "ty", "beam_width", "time", "duration"))
        return rest, at(idx, d, "sx", "sy"), at(idx, d, "tx", "ty")

    used = [False] * len(extra)
    left = []
    for r in miss:
        rest, src, tgt = parts(r, gidx)
        for j, x in enumerate(extra):
            if used[j] or src is None or tgt is None:
                continue
            xrest, xsrc, xtgt = parts(x, kidx)
            if (xrest == rest and xsrc == src and xtgt and xtgt[0] == tgt[0] and abs(xtgt[1] - tgt[1]) <= 1 and
                    abs(x["t"] - r["t"]) <= tol):
                used[j] = True
                break
        else:
            left.append(r)
    return left, [extra[j] for j in range(len(extra)) if not used[j]]


def report_id(val):
    """(NAME, TIME) of a relayed node report after rel() (TIME relative), or None."""
    m = re.search(r"(?:^|,)NAME=([^,]*)", val)
    t = re.search(r"(?:^|,)TIME=([-\d.]+)", val)
    return (m.group(1), float(t.group(1))) if m and t else None


_relay_cache = {}


def relayed_anywhere(rows, r, half):
    """Whether any uFldNodeComms relay (NODE_REPORT_*) in rows carries the report r carries."""
    rid = report_id(r["val"]) if r["type"] == "string" else None
    if rid is None:
        return True
    key = id(rows)
    if key not in _relay_cache or _relay_cache[key][0] is not rows:
        idx = collections.defaultdict(list)
        for x in rows:
            if x["src"] == "uFldNodeComms" and x["var"].startswith("NODE_REPORT_") and x["type"] == "string":
                xid = report_id(x["val"])
                if xid:
                    idx[xid[0]].append(xid[1])
        for v in idx.values():
            v.sort()
        _relay_cache[key] = (rows, idx)
    times = _relay_cache[key][1].get(rid[0], [])
    i = bisect.bisect_left(times, rid[1] - half)
    return i < len(times) and times[i] < rid[1] + half


def scenario_rate(scn_path):
    """The highest report rate of the .scn's vehicles (reports per second; 0 when none)."""
    rate = 0.0
    for line in open(scn_path):
        m = re.match(r"\s*vehicle\s+(.*)", line)
        if m:
            s = re.search(r"(?:^|,)rate=([\d.]+)", m.group(1))
            if s:
                rate = max(rate, float(s.group(1)))
    return rate


def match_values(g, k, norm):
    """Rows paired by value alone (start-up rows). Returns the unpaired rows of each side."""
    used = [False] * len(k)
    miss = []
    for r in g:
        for j, x in enumerate(k):
            if not used[j] and x["type"] == r["type"] and norm.same(r["val"], x["val"], times=False):
                used[j] = True
                break
        else:
            miss.append(r)
    return miss, [k[j] for j in range(len(k)) if not used[j]]


def scenario_speed(scn_path):
    """The fastest vehicle of a .scn (m/s), for the driver's position tolerance."""
    vmax = 0.0
    for line in open(scn_path):
        m = re.match(r"\s*vehicle\s+(.*)", line)
        if m:
            s = re.search(r"(?:^|,)spd=([-\d.]+)", m.group(1))
            if s:
                vmax = max(vmax, abs(float(s.group(1))))
    return vmax


def driver_figures(G, K, gmeta, kmeta, tol, vmax):
    """The driver's own posts, echoed: one to one with the recording's, per variable (and per
    vehicle for reports), in order: count, script time, value (@MOOSTIME and TIME= relative to
    t0, positions within vmax x the time difference + 0.01)."""
    figs = []

    def key(r):
        m = re.match(r"NAME=([^,]*)", r["val"]) if r["type"] == "string" else None
        return r["var"] + ("[%s]" % m.group(1) if m else "")

    def groups(rows):
        out = collections.defaultdict(list)
        for r in rows:
            if r["src"] == "driver":
                out[key(r)].append(r)
        return out

    gd, kd = groups(G), groups(K)
    gc = {k: len(v) for k, v in gd.items()}
    kc = {k: len(v) for k, v in kd.items()}
    ok = gc == kc
    d = "" if ok else "; ".join("%s: 24.8 %d, kelp %d" % (k, gc.get(k, 0), kc.get(k, 0))
                                for k in sorted(set(gc) | set(kc)) if gc.get(k) != kc.get(k))
    figs.append(Figure("driver/posts", ok, short(d, 300)))
    gn, kn = Norm(gmeta["t0_moostime"], tol), Norm(kmeta["t0_moostime"], tol)
    bad = []
    for k in sorted(gd):
        for a, b in zip(gd[k], kd.get(k, [])):
            dt = abs(a["t"] - b["t"])
            same = a["type"] == b["type"] and dt <= tol
            if same and a["type"] == "double":
                same = abs(float(a["val"]) - float(b["val"])) <= 0.011 + vmax * dt
            elif same:
                ta, tb = gn.tokens(a["val"]), kn.tokens(b["val"])
                same = len(ta) == len(tb) and all(
                    ka == kb and (va == vb if ka == "s" else abs(va - vb) <= (tol if ka == "t" else 0.011 + vmax * dt))
                    for (ka, va), (kb, vb) in zip(ta, tb))
            if not same:
                bad.append((a, b))
    d = ""
    if bad:
        a, b = bad[0]
        d = "%d of %d differ; 24.8 t=%.2f %s, kelp t=%.2f %s" % (len(bad), sum(gc.values()), a["t"], short(a["val"], 80),
                                                                b["t"], short(b["val"], 80))
    figs.append(Figure("driver/values", not bad, d))
    return figs


def raw_of(rows, r):
    for x in rows:
        if x["t"] == r["t"] and x["var"] == r["var"] and x["src"] == r["src"]:
            return x["val"]
    return r["val"]


def format_figure(var, g, k):
    def shape(rows):
        keyseqs = collections.Counter()
        classes = collections.defaultdict(set)
        kinds = collections.Counter()
        for r in rows:
            kinds[r["type"]] += 1
            if r["type"] != "string":
                continue
            p = kv_pairs(r["val"])
            if p is None:
                continue
            keyseqs[tuple(x for x, _ in p)] += 1
            for key, v in p:
                classes[key].add(num_class(v))
                if num_class(v).startswith("d") and v.endswith("0"):
                    zeros.add(key)  # a trailing zero kept: a fixed format, not a trimmed one
        return set(kinds), set(keyseqs), {key: describe(c) for key, c in classes.items()}

    def describe(c):
        if c == {"text"} or not c:
            return "text"
        ds = sorted(int(x[1:]) for x in c if x.startswith("d"))
        if "text" in c:
            return "mixed"
        if not ds:
            return "int"
        if "int" in c or len(ds) > 1:
            return "trimmed<=%d" % ds[-1]
        return "fixed %d" % ds[0]

    zeros = set()
    gk, gs, gc = shape(g)
    gz, zeros = zeros, set()
    kk, ks, kc = shape(k)
    kz = zeros
    probs = []
    if gk != kk:
        probs.append("types 24.8 %s, kelp %s" % (sorted(gk), sorted(kk)))
    if var == "IVPHELM_SUMMARY" and gs and ks:
        # 24.8's HelmReport writes a field when it changed (whole the first time): which fields
        # changed together is the run's; the whole report's key order and the keys written at
        # all are the format
        gs = {max(gs, key=len), tuple(sorted({x for q in gs for x in q}))}
        ks = {max(ks, key=len), tuple(sorted({x for q in ks for x in q}))}
    if gs != ks:
        probs.append("keys 24.8 %s, kelp %s" % (",".join(sorted(gs)[0]) if gs else "-", ",".join(sorted(ks)[0]) if ks else "-"))
    for key in sorted(set(gc) & set(kc)):
        a, b = gc[key], kc[key]
        # two trimmed formats that differ in the most decimals seen: which values a run met is
        # chance (kelp's punctual clock times 0.001 s past a tick print as x or x.5; 24.8's late
        # ones as x.02)
        if a.startswith("trimmed") and b.startswith("trimmed"):
            continue
        if a != b and not (a.startswith("trimmed") and b in ("int",) or b.startswith("trimmed") and a == "int"):
            # a trimmed number that happened to be whole in one run is not a format difference
            if not (a.startswith("trimmed") and b.startswith("fixed") and int(b.split()[1]) <= int(a.split("=")[1])) and \
               not (b.startswith("trimmed") and a.startswith("fixed") and int(a.split()[1]) <= int(b.split("=")[1])):
                # two fixed counts, the longer never with a trailing zero: what printed fewer
                # decimals may be the same trimmed format that met a value ending in zero
                if a.startswith("fixed") and b.startswith("fixed"):
                    na, nb = int(a.split()[1]), int(b.split()[1])
                    if (na > nb and key not in gz) or (nb > na and key not in kz):
                        continue
                # a fixed count never seen with a trailing zero beside a trimmed format that met
                # fewer decimals: the same trimmed format (24.8's doubleToStringX(t, 2) TIMEs
                # all end in a non-zero digit in one run, all in zero in another)
                if (a.startswith("fixed") and b.startswith("trimmed") and key not in gz) or \
                   (b.startswith("fixed") and a.startswith("trimmed") and key not in kz):
                    continue
                probs.append("%s: 24.8 %s, kelp %s" % (key, a, b))
    return Figure("format/%s" % var, not probs, "; ".join(probs))


def status_figures(app, var, g, k, tol):
    figs = []
    gkeys = [x for x, _ in kv_pairs(g[-1]["val"])]
    kkeys = [x for x, _ in kv_pairs(k[-1]["val"])]
    figs.append(Figure("status/%s/keys" % app, gkeys == kkeys, "" if gkeys == kkeys else "24.8 %s, kelp %s" % (gkeys, kkeys)))

    def cadence(rows):
        ts = [r["t"] for r in rows]
        if len(ts) < 2:
            return None, ""
        d = sorted(b - a for a, b in zip(ts, ts[1:]))
        return (ts[-1] - ts[0]) / (len(ts) - 1), "%.2f-%.2f" % (d[0], d[-1])

    (gc, gr), (kc, kr) = cadence(g), cadence(k)
    ctol = 2 * tol / (min(len(g), len(k)) - 1) if min(len(g), len(k)) > 1 else 0
    ok = gc is not None and kc is not None and abs(gc - kc) <= ctol
    figs.append(Figure("status/%s/cadence" % app, ok, "" if ok else
                       "24.8 every %s s (intervals %s), kelp every %s s (intervals %s); tolerance %.3f" % (
                           "%.3f" % gc if gc else "-", gr, "%.3f" % kc if kc else "-", kr, ctol)))

    def sets(rows):
        d = dict(kv_pairs(rows[-1]["val"]))
        return d.get("Publishing", ""), d.get("Subscribing", "")

    gp, gsub = sets(g)
    kp, ksub = sets(k)
    figs.append(Figure("status/%s/subscribing" % app, gsub == ksub, "" if gsub == ksub else "24.8 %s, kelp %s" % (gsub, ksub)))
    figs.append(Figure("status/%s/publishing" % app, gp == kp, "" if gp == kp else "24.8 %s, kelp %s" % (gp, kp)))
    return figs


def appcast_figures(app, G, K):
    g = [r for r in G if r["var"] == "APPCAST" and r["src"] == app]
    k = [r for r in K if r["var"] == "APPCAST" and r["src"] == app]
    if not g or not k:
        return []
    gf, kf = appcast_fields(g[-1]["val"]), appcast_fields(k[-1]["val"])
    figs = [Figure("appcast/%s/fields" % app, list(gf) == list(kf), "" if list(gf) == list(kf) else "24.8 %s, kelp %s" % (list(gf), list(kf)))]
    gl = [mask(x) for x in gf.get("messages", "").split("!@")]
    kl = [mask(x) for x in kf.get("messages", "").split("!@")]
    ok = gl == kl
    d = ""
    if not ok:
        for i in range(max(len(gl), len(kl))):
            a = gl[i] if i < len(gl) else "(none)"
            b = kl[i] if i < len(kl) else "(none)"
            if a != b:
                d = "line %d: 24.8 '%s', kelp '%s'" % (i + 1, short(a, 70), short(b, 70))
                break
    figs.append(Figure("appcast/%s/lines" % app, ok, d))
    # counters: the whole numbers of the report, in order; a count that grows with time (reports
    # received) may differ by what the request's timing holds: 2% (at least 1) above 20
    ints = lambda s: [int(x) for x in re.findall(r"(?<![\d.])\d+(?![\d.])", s)]
    gi, ki = ints(gf.get("messages", "")), ints(kf.get("messages", ""))
    ok = len(gi) == len(ki) and all(a == b if a <= 20 else abs(a - b) <= max(1, 0.02 * a) for a, b in zip(gi, ki))
    figs.append(Figure("appcast/%s/counters" % app, ok, "" if ok else "24.8 %s, kelp %s" % (gi[:12], ki[:12])))
    for key in ("run_warning_total", "events_total", "config_warnings", "run_warnings"):
        if key in gf or key in kf:
            a, b = mask(gf.get(key, "")), mask(kf.get(key, ""))
            figs.append(Figure("appcast/%s/%s" % (app, key), a == b, "" if a == b else "24.8 '%s', kelp '%s'" % (short(a, 80), short(b, 80))))
    return figs


def nodecomms_figures(G, K, tol, dur):
    figs = []

    def deliveries(rows):
        out = collections.defaultdict(list)
        for r in rows:
            if r["var"].startswith("NODE_MESSAGE_") and r["src"] != "driver":
                m = re.search(r"var_name=([^,]*)", r["val"])
                if m:
                    out[m.group(1)].append((r["var"][len("NODE_MESSAGE_"):], r["t"]))
        return out

    inputs = []
    for r in G:
        if r["var"] == "NODE_MESSAGE" and r["src"] == "driver":
            m = re.search(r"var_name=([^,]*)", r["val"])
            if m:
                inputs.append(m.group(1))
    gd, kd = deliveries(G), deliveries(K)
    for name in inputs:
        a = sorted(d for d, _ in gd.get(name, []))
        b = sorted(d for d, _ in kd.get(name, []))
        ok = a == b
        if ok and a:
            ok = abs(min(t for _, t in gd[name]) - min(t for _, t in kd[name])) <= tol
        figs.append(Figure("message/%s" % name, ok, "" if ok else "24.8 to %s, kelp to %s" % (a or "nobody", b or "nobody")))

    def relays(rows):
        out = collections.defaultdict(list)
        for r in rows:
            if r["var"].startswith("NODE_REPORT_") and r["src"] != "driver" and r["type"] == "string":
                m = re.search(r"NAME=([^,]*)", r["val"])
                if m:
                    xy = tuple(float(v) if is_num(v) else v for v in (
                        (re.search(r"(?:^|,)%s=([^,]*)" % c, r["val"]) or re.match("()", "")).group(1) for c in ("X", "Y")))
                    out[(r["var"][len("NODE_REPORT_"):], m.group(1))].append((r["t"], xy))
        return out

    def near(p, q):
        return all(abs(a - b) <= 0.05 if isinstance(a, float) and isinstance(b, float) else a == b for a, b in zip(p, q))

    # relay windows per (destination, source): first and last relay time, count, and which
    # report was relayed first (its position: the driver posts the same one at t0 in both runs,
    # so a report relayed by one and refused by the other shows here, e.g. one at exactly
    # comms_range)
    gr, kr = relays(G), relays(K)
    for key in sorted(set(gr) | set(kr)):
        a, b = gr.get(key, []), kr.get(key, [])
        rate = len(a) / dur if a else 0
        ok = bool(a) and bool(b) and abs(len(a) - len(b)) <= math.ceil(rate * 2 * tol) + 1 and \
            abs(a[0][0] - b[0][0]) <= tol and abs(a[-1][0] - b[-1][0]) <= tol and near(a[0][1], b[0][1])
        fmt = lambda x: "%d relays %.2f-%.2f, the first X=%s,Y=%s" % ((len(x), x[0][0], x[-1][0]) + tuple(
            "%g" % v if isinstance(v, float) else v for v in x[0][1])) if x else "no relay"
        d = "" if ok else "24.8 %s; kelp %s" % (fmt(a), fmt(b))
        figs.append(Figure("relay/%s<-%s" % key, ok, d))

    # the comms pulses drawn: their labels (one per source/destination pair and kind)
    def labels(rows):
        out = collections.Counter()
        for r in rows:
            if r["var"] == "VIEW_COMMS_PULSE" and r["type"] == "string":
                m = re.search(r"(?:^|,)label=([^,]*)", r["val"])
                out[m.group(1) if m else "(none)"] += 1
        return out

    gl, kl = labels(G), labels(K)
    if gl or kl:
        ok = set(gl) == set(kl)
        figs.append(Figure("pulse/labels", ok, "" if ok else "24.8 %d labels, e.g. %s; kelp %d labels, e.g. %s" % (
            len(gl), sorted(set(gl) - set(kl))[:4] or sorted(gl)[:4], len(kl), sorted(set(kl) - set(gl))[:4] or sorted(kl)[:4])))
    return figs


def summary_phase(rows, tol):
    """A handler's summaries without the periodic repeats and the values superseded within tol."""
    out = []
    for i, r in enumerate(rows):
        if i and rows[i - 1]["val"] == r["val"]:
            continue
        if i + 1 < len(rows) and rows[i + 1]["t"] - r["t"] < tol and rows[i + 1]["val"] != r["val"]:
            continue
        out.append(r)
    return out


def msghandler_figures(G, K, tol):
    """Per NODE_MESSAGE input: what the handler posted for it (var, type, value, aux)."""
    figs = []

    def var_name(val):
        for part in str(val).split(","):
            if "=" in part:
                k, v = part.split("=", 1)
                if k.strip().lower() == "var_name":
                    return v.strip()
        return None

    def outputs(rows):
        ins = [r for r in rows if r["var"] == "NODE_MESSAGE" and r["src"] == "driver"]
        outs = [r for r in rows if r["src"] == "uFldMessageHandler"]
        res = []
        for r in ins:
            name = var_name(r["val"])
            got = sorted((o["var"], o["type"], str(o["val"]), o.get("aux", "")) for o in outs
                         if name and o["var"] == name and o["t"] >= r["t"] - tol)
            res.append((r["val"], got))
        return res

    g, k = outputs(G), outputs(K)
    for i, (inp, got) in enumerate(g):
        kgot = k[i][1] if i < len(k) else None
        ok = kgot == got
        figs.append(Figure("message/%02d" % (i + 1), ok, "" if ok else "input '%s': 24.8 posted %s, kelp %s" % (short(inp, 60), got or "nothing", kgot if kgot else "nothing")))
    gs = [r["val"] for r in G if r["var"] == "UMH_SUMMARY_MSGS"]
    ks = [r["val"] for r in K if r["var"] == "UMH_SUMMARY_MSGS"]
    gu, ku = sorted(set(gs), key=gs.index), sorted(set(ks), key=ks.index)
    # inputs closer together than one iteration period land in one iteration or in two,
    # depending only on the iteration's phase: each such pair may add (or save) one
    # intermediate summary in either run
    ins = [r["t"] for r in G if r["var"] == "NODE_MESSAGE" and r["src"] == "driver"]
    close = sum(1 for a, b in zip(ins, ins[1:]) if b - a < tol / 2)

    def sub(a, b):  # a is an ordered subsequence of b
        it = iter(b)
        return all(x in it for x in a)

    ok = (sub(gu, ku) and len(ku) - len(gu) <= close) or (sub(ku, gu) and len(gu) - len(ku) <= close)
    figs.append(Figure("summary/sequence", ok, "" if ok else "24.8 %s, kelp %s" % (short(gu, 150), short(ku, 150))))
    return figs


def cmgr_figures(G, K, tol, dur):
    """pContactMgrV20: per alert flag and contact, the windows the flag was posted in (when, in
    order); the retired lists in order; the contacts each recap names (its ages are the
    iteration's phase against the reports', not behaviour)."""
    figs = []
    app = "pContactMgrV20"
    summary = {"CONTACTS_LIST", "CONTACTS_ALERTED", "CONTACTS_RETIRED", "CONTACTS_RECAP", "CONTACTS_COUNT",
               "CONTACT_CLOSEST", "CONTACT_CLOSEST_TIME", "APPCAST", "PCONTACTMGRV20_STATUS", "VIEW_CIRCLE",
               "BHV_ABLE_FILTER", "ALERT_VERBOSE", "CONTACT_RANGES", "CONTACT_CLOSEST_RANGE", "CONTACT_CLOSEST_RELBNG"}

    def flags(rows):
        out = collections.defaultdict(list)
        for r in rows:
            if r["src"] == app and r["type"] == "string" and r["var"] not in summary and not r["var"].endswith("_PID"):
                out[(r["var"], r["val"])].append(r["t"])
        return out

    gf, kf = flags(G), flags(K)
    for key in sorted(set(gf) | set(kf)):
        a, b = gf.get(key, []), kf.get(key, [])
        ok = len(a) == len(b) and all(abs(x - y) <= tol for x, y in zip(a, b) if x <= dur - tol and y <= dur - tol)
        figs.append(Figure("alert/%s=%s" % key, ok, "" if ok else "24.8 at %s, kelp at %s" % (
            ["%.2f" % x for x in a], ["%.2f" % x for x in b])))

    def seq(rows, var):
        out = []
        for r in rows:
            if r["src"] == app and r["var"] == var and (not out or out[-1] != r["val"]):
                out.append(r["val"])
        return out

    a, b = seq(G, "CONTACTS_RETIRED"), seq(K, "CONTACTS_RETIRED")
    figs.append(Figure("retired/sequence", a == b, "" if a == b else "24.8 %s, kelp %s" % (short(a, 150), short(b, 150))))
    names = lambda v: tuple(re.findall(r"vname=([^,]*)", v))
    a = [names(v) for v in seq(G, "CONTACTS_RECAP")]
    b = [names(v) for v in seq(K, "CONTACTS_RECAP")]
    a = [x for i, x in enumerate(a) if i == 0 or a[i - 1] != x]
    b = [x for i, x in enumerate(b) if i == 0 or b[i - 1] != x]
    figs.append(Figure("recap/contacts", a == b, "" if a == b else "24.8 %s, kelp %s" % (short(a, 150), short(b, 150))))
    return figs


HAZARD_OWN_VALUES = re.compile(r"^UHZ_HAZARD_REPORT(_.*)?$|^UHZ_OPTIONS_SUMMARY$|^VIEW_CIRCLE$")


def hazard_classify_circle(r):
    """A classify answer's circle (5 vertices); a detection's has 12."""
    return r["var"] == "VIEW_CIRCLE" and ",vertices=5," in str(r["val"])


def hazard_figures(G, K, tol, period, Gall, Kall):
    """uFldHazardSensor: who detected what in which order, the classifications answered, the
    options summary, and the AppCast's statistics table.

    A classify answer comes min_classify_interval after the previous one, at the first iteration
    that finds the interval over: each answer may come one iteration period later on one side
    than on the other, and the slips add up along the queue. So the answers are compared by
    sequence (vehicle, label, type said), the first within tol, and each interval between two
    answers within tol of the recording's. The options summary is posted at start-up and every
    options_summary_interval after: its phase is the app's start (not behaviour), so it is
    compared by value and interval."""
    figs = []

    def seq(rows, var, keys):
        out = []
        for r in rows:
            if r["var"] == var and r["src"] == "uFldHazardSensor":
                d = dict(kv_pairs(r["val"]))
                out.append((r["t"], tuple(d.get(x, "") for x in keys)))
        return out

    gd, kd = seq(G, "UHZ_DETECTION_REPORT", ("vname", "label")), seq(K, "UHZ_DETECTION_REPORT", ("vname", "label"))
    a, b = [x for _, x in gd], [x for _, x in kd]
    ok = a == b
    figs.append(Figure("hazard/detections", ok, "" if ok else "24.8 %s; kelp %s" % (short(a, 150), short(b, 150))))

    ga, ka = seq(G, "UHZ_HAZARD_REPORT", ("vname", "label", "type")), seq(K, "UHZ_HAZARD_REPORT", ("vname", "label", "type"))
    ok = [x for _, x in ga] == [x for _, x in ka]
    d = "" if ok else "24.8 %s; kelp %s" % (short([x for _, x in ga], 150), short([x for _, x in ka], 150))
    if ok and ga:
        gi = [q[0] - p[0] for p, q in zip(ga, ga[1:])]
        ki = [q[0] - p[0] for p, q in zip(ka, ka[1:])]
        ok = abs(ga[0][0] - ka[0][0]) <= tol and all(abs(x - y) <= tol for x, y in zip(gi, ki))
        d = "" if ok else "first 24.8 %.2f kelp %.2f; intervals 24.8 %s kelp %s" % (
            ga[0][0], ka[0][0], ["%.2f" % x for x in gi], ["%.2f" % x for x in ki])
    figs.append(Figure("hazard/classifications", ok, d))
    gc = sorted(str(r["val"]).split(",time=")[0] for r in G if hazard_classify_circle(r))
    kc = sorted(str(r["val"]).split(",time=")[0] for r in K if hazard_classify_circle(r))
    figs.append(Figure("hazard/classify_circles", gc == kc, "" if gc == kc else "24.8 %s; kelp %s" % (short(gc, 120), short(kc, 120))))

    def summaries(rows):
        rs = [r for r in rows if r["var"] == "UHZ_OPTIONS_SUMMARY" and r["src"] == "uFldHazardSensor"]
        ts = [r["t"] for r in rs]
        return sorted({str(r["val"]) for r in rs}), ((ts[-1] - ts[0]) / (len(ts) - 1) if len(ts) > 1 else None)

    (gv, gcad), (kv, kcad) = summaries(Gall), summaries(Kall)
    ok = gv == kv and gcad is not None and kcad is not None and abs(gcad - kcad) <= period
    figs.append(Figure("hazard/options_summary", ok, "" if ok else "24.8 %s every %s s; kelp %s every %s s" % (
        gv, gcad, kv, kcad)))

    # the AppCast's per-vehicle rows (the settings and the statistics), times masked
    def rows(rows_):
        casts = [r for r in rows_ if r["var"] == "APPCAST" and r["src"] == "uFldHazardSensor"]
        if not casts:
            return None
        lines = appcast_fields(casts[-1]["val"]).get("messages", "").split("!@")
        out, dashes = [], 0
        for ln in lines:
            if ln.startswith("-----"):
                dashes += 1
                continue
            if dashes >= 2 and ln.strip():
                out.append(re.sub(r"\(\d+\)", "(#)", " ".join(ln.split())))
        return out

    gr, kr = rows(Gall), rows(Kall)
    if gr is not None and kr is not None:
        def close(x, y):  # sensor requests grow with time: the counters' tolerance
            xs, ys = x.split(), y.split()
            return len(xs) == len(ys) and all(
                p == q or (p.isdigit() and q.isdigit() and int(p) > 20 and abs(int(p) - int(q)) <= max(1, 0.02 * int(p)))
                for p, q in zip(xs, ys))
        ok = len(gr) == len(kr) and all(close(x, y) for x, y in zip(gr, kr))
        figs.append(Figure("hazard/appcast_stats", ok, "" if ok else "24.8 %s; kelp %s" % (gr, kr)))
    return figs


def series_match(a, b, tol, vtol, lo, hi, skipped=0.0):
    """Rows (t, values) of one side each with a row of the other within tol in time whose values
    are all within vtol; only rows with lo <= t <= hi are checked. With skipped, a row of a rising
    series that the other side stepped over (its rows just below and just above the value more
    than one iteration period (skipped, s) apart, the one above within tol: two inputs in one of
    its iterations) is the iteration's phase. Returns the first unmatched (side, row) or None."""
    def stepped_over(t, v, ys):
        below = [(u, w) for u, w in ys if u <= t + tol and w[0] < v[0] - vtol]
        above = [(u, w) for u, w in ys if w[0] > v[0] + vtol]
        return (bool(below) and bool(above) and abs(above[0][0] - t) <= tol
                and above[0][0] - below[-1][0] > 1.5 * skipped)

    for side, xs, ys in (("24.8", a, b), ("kelp", b, a)):
        for t, v in xs:
            if t < lo or t > hi:
                continue
            if not any(abs(t - u) <= tol and len(v) == len(w) and all(abs(p - q) <= vtol for p, q in zip(v, w))
                       for u, w in ys) and not (skipped and stepped_over(t, v, ys)):
                return side, t, v
    return None


def pathcheck_figures(G, K, Gw, Kw, tol, dur, vmax, period):
    """uFldPathCheck: per vehicle, the speed series (avg_spd, every iteration) and the odometry
    series (total_dist, trip_dist; one printed unit apart at most), and the AppCast's counts and
    its per-vehicle trip and total distances (24.8 writes its rows run together before its
    table: they are read from there)."""
    figs = []

    def series(rows, var, keys):
        out = collections.defaultdict(list)
        for r in rows:
            if r["var"] == var and r["src"] == "uFldPathCheck" and r["type"] == "string":
                d = dict(kv_pairs(r["val"]) or [])
                if "vname" in d and all(is_num(d.get(k, "")) for k in keys):
                    out[d["vname"]].append((r["t"], tuple(float(d[k]) for k in keys)))
        return out

    # avg_spd comes from the reports' TIME stamps, which are the driver's posting times: each
    # driver's (24.8's and kelp's) posts a few ms off their schedule on a loaded host, so two
    # runs' speeds differ by the speed x that jitter / the history's span (3 m/s x 0.005 s /
    # 1 s = 0.015) besides the printed unit
    for var, keys, vtol, name in (("UPC_SPEED_REPORT", ("avg_spd",), 0.031, "speed"),
                                  ("UPC_ODOMETRY_REPORT", ("total_dist", "trip_dist"), 0.1 + 1e-6, "odometry")):
        gs, ks = series(Gw, var, keys), series(Kw, var, keys)
        for v in sorted(set(gs) | set(ks)):
            a, b = gs.get(v, []), ks.get(v, [])
            rate = len(a) / dur if a else 0
            ok = bool(a) and bool(b) and abs(len(a) - len(b)) <= math.ceil(rate * 2 * tol) + 1
            bad = series_match(a, b, tol, vtol, tol, dur - tol, period if name == "odometry" else 0.0) if ok else None
            d = "" if ok and not bad else ("24.8 %d posts, kelp %d" % (len(a), len(b)) if not ok else
                                            "%s t=%.2f %s has no match" % bad)
            figs.append(Figure("%s/%s" % (name, v), ok and not bad, d))
    g = [r for r in G if r["var"] == "APPCAST" and r["src"] == "uFldPathCheck"]
    k = [r for r in K if r["var"] == "APPCAST" and r["src"] == "uFldPathCheck"]
    if g and k:
        gm, km = appcast_fields(g[-1]["val"]).get("messages", ""), appcast_fields(k[-1]["val"]).get("messages", "")
        cnt = lambda m: [int(x) for x in re.findall(r"Recd \((?:good|bad)\):\s+(\d+)", m)]
        a, b = cnt(gm), cnt(km)
        ok = len(a) == 2 and len(b) == 2 and abs(a[0] - b[0]) <= max(1, 0.02 * a[0]) and a[1] == b[1]
        figs.append(Figure("appcast/uFldPathCheck/received", ok, "" if ok else "24.8 %s, kelp %s" % (a, b)))
        names = sorted(set(series(Gw, "UPC_ODOMETRY_REPORT", ())) | set(series(Kw, "UPC_ODOMETRY_REPORT", ())))

        def rows(m):
            """the rows of a table, else 24.8's run-together text"""
            out = {}
            for line in m.split("!@"):
                f = line.split()
                if len(f) == 6 and f[4:] == ["n/a", "n/a"] and all(is_num(x) for x in f[1:4]):
                    out[f[0]] = tuple(float(x) for x in f[1:4])
            if not out:
                for v in names:
                    x = re.search(re.escape(v) + r"(-?\d+\.\d)(-?\d+\.\d)(-?\d+\.\d)n/an/a", m)
                    if x:
                        out[v] = tuple(float(y) for y in x.groups())
            return out

        grows, krows = rows(gm), rows(km)
        # trip and total at the request: what a vehicle moves within the timing tolerance
        dtol = vmax * tol + 0.1
        ok = set(grows) == set(krows) and all(abs(grows[v][i] - krows[v][i]) <= dtol for v in grows for i in (0, 1))
        figs.append(Figure("appcast/uFldPathCheck/table", ok, "" if ok else "24.8 %s, kelp %s" % (grows, krows)))
    return figs


ANSWER_SKEW_S = 0.1


def rangesensor_figures(G, K, Gw, Kw, tol, vmax, pfx):
    """uFldBeaconRangeSensor / uFldContactRangeSensor: per request of the script, who is answered
    by which beacon or contact at what range (ranges within what the vehicles move in tol); the
    noise factors (reported / ground-truth range, in order) when ground truth is posted; the
    AppCast's vehicle table (its counters per vehicle)."""
    figs = []
    app = "uFldBeaconRangeSensor" if pfx == "BRS" else "uFldContactRangeSensor"
    key = "id" if pfx == "BRS" else "target"

    def answers(rows):
        reqs = [r for r in rows if r["var"] == pfx + "_RANGE_REQUEST" and r["src"] == "driver"]
        reps = [r for r in rows if r["var"] == pfx + "_RANGE_REPORT" and r["src"] == app and r["type"] == "string"]
        out = []
        # a recording made over MOOS stamps the app's answers on the app's clock and the
        # driver's requests at their script times: an answer can read up to ~0.05 s before its
        # request (crs_n1_uniform: 4.955 for a request at 5.000); ANSWER_SKEW_S keeps it with its
        # request (no app answers within 0.1 s of a request: they answer at their next iteration)
        sk = ANSWER_SKEW_S
        for i, q in enumerate(reqs):
            end = reqs[i + 1]["t"] - sk if i + 1 < len(reqs) else q["t"] + 2 * tol
            got = []
            for r in reps:
                if q["t"] - sk <= r["t"] < end:
                    d = dict(kv_pairs(r["val"]) or [])
                    got.append((d.get("vname", ""), d.get(key, ""), float(d["range"]) if is_num(d.get("range", "")) else None))
            out.append((q["val"], got))
        return out

    ga, ka = answers(Gw), answers(Kw)
    rtol = 2 * vmax * tol + 0.01
    for i, (req, got) in enumerate(ga):
        kgot = ka[i][1] if i < len(ka) else None
        ok = kgot is not None and len(got) == len(kgot) and all(
            a[0] == b[0] and a[1] == b[1] and (a[2] is None) == (b[2] is None) and (a[2] is None or abs(a[2] - b[2]) <= rtol)
            for a, b in zip(got, kgot))
        fmt = lambda x: ", ".join("%s<-%s %.1f" % (v, w, r if r is not None else float("nan")) for v, w, r in x) or "nothing"
        figs.append(Figure("answer/%02d" % (i + 1), ok, "" if ok else "request '%s' at #%d: 24.8 %s; kelp %s" % (
            req, i + 1, fmt(got), fmt(kgot) if kgot is not None else "no such request")))

    def factors(rows):
        noisy = [r for r in rows if r["var"] == pfx + "_RANGE_REPORT" and r["src"] == app]
        gt = [r for r in rows if r["var"] == pfx + "_RANGE_REPORT_GT" and r["src"] == app]
        out = []
        for a, b in zip(noisy, gt):
            x, y = dict(kv_pairs(a["val"]) or []).get("range"), dict(kv_pairs(b["val"]) or []).get("range")
            if is_num(x or "") and is_num(y or "") and float(y) > 0:
                out.append(float(x) / float(y))
        return out

    gf, kf = factors(Gw), factors(Kw)
    if gf or kf:
        ok = len(gf) == len(kf) and all(abs(a - b) <= 1e-3 for a, b in zip(gf, kf))
        first = next((i for i, (a, b) in enumerate(zip(gf, kf)) if abs(a - b) > 1e-3), min(len(gf), len(kf)))
        figs.append(Figure("noise/factors", ok, "" if ok else "%d and %d factors, the first %d agree" % (len(gf), len(kf), first)))
    g = [r for r in G if r["var"] == "APPCAST" and r["src"] == app]
    k = [r for r in K if r["var"] == "APPCAST" and r["src"] == app]
    if g and k:
        def table(m):
            lines = m.split("!@")
            at = next((i for i, x in enumerate(lines) if x.startswith("Vehicles(")), None)
            rows = {}
            if at is not None:
                for x in lines[at + 4:]:
                    f = x.split()
                    if not f:
                        break
                    rows[f[0]] = [c for c in f[1:] if re.fullmatch(r"\d+", c)]
            return rows
        a, b = table(appcast_fields(g[-1]["val"]).get("messages", "")), table(appcast_fields(k[-1]["val"]).get("messages", ""))
        ok = a == b and bool(a)
        figs.append(Figure("appcast/%s/vehicles" % app, ok, "" if ok else "24.8 %s, kelp %s" % (a, b)))
    return figs


# the vehicle comparator's tolerances (issue 27's "done when"): the track within 3 m of 24.8's
# at matched times from DEPLOY, each waypoint arrival and completion within 1.5 s, the rudder's
# peak in each turn within 10 %, cruise thrust and speed within 10 %
VEH_TRACK_M = 3.0
VEH_EVENT_S = 1.5
VEH_PEAK_PCT = 10.0
VEH_CRUISE_PCT = 10.0
VEH_TURN_RUDDER = 20.0  # a leg is a turn when the recording's rudder peaks at this or more


def is_vehicle(G):
    """A simulated vehicle: NAV_X and NAV_Y posted by an app of the mission (not by the driver's
    synthesised vehicles)."""
    names = {r["var"] for r in G if r["src"] != "driver"}
    return "NAV_X" in names and "NAV_Y" in names


def vehicle_figures(G, K):
    """A simulated vehicle (uSimMarineV22 + pMarinePIDV22 + pHelmIvP) judged by what it does, each
    side's times taken from its first DEPLOY = true (its start, whoever posted it): the track at
    the recording's NAV_X/NAV_Y times (interpolated on kelp's), the helm's events (each
    WPT_INDEX change: a waypoint arrival; each IVPHELM_ALLSTOP change: a start, a completion, a
    mode change) paired in order, the peak |DESIRED_RUDDER| between
    consecutive events (one turn per leg), and the median DESIRED_THRUST and NAV_SPEED while
    driving."""
    def side(rows):
        rows = sorted(rows, key=lambda r: r["t"])
        dep = [r["t"] for r in rows if r["var"] == "DEPLOY" and str(r["val"]).lower() == "true"]
        t0 = dep[0] if dep else 0.0
        track, x = [], None
        for r in rows:
            if r["var"] == "NAV_X" and r["type"] == "double":
                x = float(r["val"])
            elif r["var"] == "NAV_Y" and r["type"] == "double" and x is not None:
                track.append((r["t"] - t0, x, float(r["val"])))
        ev, last_ix, last_stop = [], None, None
        for r in rows:
            if r["t"] < t0:
                if r["var"] == "IVPHELM_ALLSTOP":
                    last_stop = r["val"]
                continue
            v = r["val"]
            if r["var"] == "WPT_INDEX" and r["type"] == "double":
                if v != last_ix:
                    ev.append(("WPT_INDEX=%g" % v, r["t"] - t0))
                last_ix = v
            elif r["var"] == "IVPHELM_ALLSTOP" and r["type"] == "string":
                if v != last_stop:
                    ev.append(("IVPHELM_ALLSTOP=%s" % v, r["t"] - t0))
                last_stop = v
        series = lambda var: [(r["t"] - t0, float(r["val"])) for r in rows
                              if r["var"] == var and r["type"] == "double" and r["t"] >= t0]
        return dict(track=track, events=ev, rudder=series("DESIRED_RUDDER"),
                    thrust=series("DESIRED_THRUST"), speed=series("NAV_SPEED"))

    g, k = side(G), side(K)
    figs = []
    # the comparison runs to the recording's last event (the vehicle's last completion)
    end = max([t for _, t in g["events"]] + [0.0])
    if not k["track"]:
        return [Figure("vehicle/track", False, "kelp posted no NAV_X/NAV_Y")]
    kt = [p[0] for p in k["track"]]

    def at(t):
        i = bisect.bisect_left(kt, t)
        if i <= 0:
            return k["track"][0][1:]
        if i >= len(kt):
            return k["track"][-1][1:]
        (ta, xa, ya), (tb, xb, yb) = k["track"][i - 1], k["track"][i]
        f = (t - ta) / (tb - ta) if tb > ta else 0.0
        return xa + f * (xb - xa), ya + f * (yb - ya)

    dist = []
    for t, x, y in g["track"]:
        if 0 <= t <= end:
            kx, ky = at(t)
            dist.append((math.hypot(kx - x, ky - y), t))
    if dist:
        worst = max(dist)
        med = sorted(d for d, _ in dist)[len(dist) // 2]
        figs.append(Figure("vehicle/track", worst[0] <= VEH_TRACK_M, "max %.2f m at %.1f s from DEPLOY (median %.2f m, %d points; tolerance %.1f m)"
                           % (worst[0], worst[1], med, len(dist), VEH_TRACK_M)))
    else:
        figs.append(Figure("vehicle/track", False, "the recording has no track after DEPLOY"))
    # events in order: the same sequence, each within VEH_EVENT_S
    gn, kn = [n for n, _ in g["events"]], [n for n, _ in k["events"]]
    if gn != kn:
        figs.append(Figure("vehicle/events", False, "24.8 %s; kelp %s" % (gn, kn)))
    else:
        worst = max([(abs(tk - tg), n, tg, tk) for (n, tg), (_, tk) in zip(g["events"], k["events"])] + [(0.0, "-", 0, 0)])
        figs.append(Figure("vehicle/events", worst[0] <= VEH_EVENT_S, "%d events; worst %s at %.2f s (24.8) / %.2f s (kelp) from DEPLOY (tolerance %.1f s)"
                           % (len(gn), worst[1], worst[2], worst[3], VEH_EVENT_S)))

    def peaks(side_, bounds):
        out = []
        for lo, hi in zip(bounds, bounds[1:]):
            w = [v for t, v in side_["rudder"] if lo <= t < hi]
            out.append(max(w, key=abs) if w else 0.0)
        return out

    gb = [0.0] + [t for _, t in g["events"]] + [end + 1.0]
    kb = [0.0] + [t for _, t in k["events"]] + [max([t for _, t in k["events"]] + [end]) + 1.0]
    gp, kp = peaks(g, gb), peaks(k, kb)
    # a leg whose peak is below VEH_TURN_RUDDER is no turn (a straight leg's corrections)
    # and a leg shorter than a second (a completion's iteration before the next behaviour takes
    # over) holds a sample or two of a moving rudder, not a turn's peak
    bad = [(i + 1, a, b) for i, (a, b) in enumerate(zip(gp, kp))
           if abs(a) >= VEH_TURN_RUDDER and gb[i + 1] - gb[i] >= 1.0
           and abs(abs(b) - abs(a)) > VEH_PEAK_PCT / 100.0 * abs(a)]
    ok = len(gp) == len(kp) and not bad
    figs.append(Figure("vehicle/rudder_peaks", ok, "" if ok else "legs 24.8 %d kelp %d; %s" % (
        len(gp), len(kp), ", ".join("leg %d: 24.8 %.1f, kelp %.1f" % x for x in bad[:4]))))
    for name in ("thrust", "speed"):
        gv = sorted(v for t, v in g[name] if 0 <= t <= end and v > 0)
        kv = sorted(v for t, v in k[name] if 0 <= t <= end and v > 0)
        if not gv:
            continue
        a, b = gv[len(gv) // 2], kv[len(kv) // 2] if kv else 0.0
        ok = abs(b - a) <= VEH_CRUISE_PCT / 100.0 * abs(a)
        figs.append(Figure("vehicle/%s" % name, ok, "median while under way: 24.8 %.2f, kelp %.2f (tolerance %.0f %%)" % (a, b, VEH_CRUISE_PCT)))
    return figs


def load_allow(path):
    rows = []
    if not path or not os.path.exists(path):
        return rows
    for line in open(path):
        line = line.strip()
        if not line.startswith("|"):
            continue
        cells = [c.strip().strip("`") for c in line.strip("|").split("|")]
        if len(cells) < 6 or cells[0].lower() == "scenario" or set(cells[0]) <= set("-: "):
            continue
        rows.append(cells)
    return rows


def load_open(path):
    """Differences still to be worked off (not defects): 'scenario figure-glob  # why' per line."""
    rows = []
    if not path or not os.path.exists(path):
        return rows
    for line in open(path):
        line = line.split("#", 1)[0].strip()
        if line:
            scn, fig = line.split(None, 1)
            rows.append((scn, fig.strip()))
    return rows


def run(args):
    allow = load_allow(args.allow)
    opened = load_open(args.open)
    found_open = []
    used = set()
    used_open = set()
    table = []
    status = 0
    failing = []
    for scn in args.scenarios:
        figs = compare(scn, args.golden, args.kelp)
        gated = any(fnmatch.fnmatch(scn, g) for g in GATED)
        agreed = sum(f.ok for f in figs)
        listed = nopen = 0
        print("== %s: %d of %d figures agree%s" % (scn, agreed, len(figs), "" if gated else " (not gated)"))
        for f in figs:
            if f.ok:
                if args.verbose:
                    print("   ok    %s" % f.fid)
                continue
            rows = [i for i, a in enumerate(allow) if fnmatch.fnmatch(scn, a[0]) and fnmatch.fnmatch(f.fid, a[1])]
            used.update(rows)
            hits = [i for i, o in enumerate(opened) if fnmatch.fnmatch(scn, o[0]) and fnmatch.fnmatch(f.fid, o[1])]
            used_open.update(hits)
            is_open = bool(hits)
            found_open.append((scn, f.fid))
            tag = "listed" if rows else "open" if is_open else ("DIFF" if gated else "diff")
            if rows:
                listed += 1
            elif is_open:
                nopen += 1
            elif gated:
                status = 1
                failing.append("%s %s: %s" % (scn, f.fid, f.detail))
            print("   %-6s %s: %s" % (tag, f.fid, f.detail))
        table.append((scn, len(figs), agreed, listed, nopen, gated))
    print()
    print("| scenario | figures | agree | % | upstream defects (docs/CONFORMANCE.md) | open (test/conformance/open.txt) | gated |")
    print("|---|---:|---:|---:|---:|---:|---|")
    for scn, n, a, l, o, g in table:
        print("| %s | %d | %d | %.0f%% | %d | %d | %s |" % (scn, n, a, 100.0 * a / n if n else 0, l, o, "yes" if g else "no (reported)"))
    if args.write_open:
        with open(args.write_open, "w") as f:
            for scn, fid in found_open:
                if not any(fnmatch.fnmatch(scn, a[0]) and fnmatch.fnmatch(fid, a[1]) for a in allow):
                    f.write("%s %s\n" % (scn, fid))
    stale = [a for i, a in enumerate(allow) if i not in used and any(fnmatch.fnmatch(s, a[0]) for s in args.scenarios)]
    for a in stale:
        print("note: docs/CONFORMANCE.md row no longer needed: %s %s" % (a[0], a[1]))
    for i, o in enumerate(opened):
        if i not in used_open and any(fnmatch.fnmatch(s, o[0]) for s in args.scenarios):
            print("note: test/conformance/open.txt line no longer needed: %s %s" % o)
    # the gated differences again, last, where a log's tail shows them
    for line in failing:
        print("DIFF (gated) %s" % line)
    print("conformance: %s" % ("PASS" if status == 0 else "FAIL (a gated figure differs and is neither an upstream defect in docs/CONFORMANCE.md nor open in test/conformance/open.txt)"))
    return status


def self_test(args):
    """The comparator must agree with the recording itself and must catch a change."""
    import tempfile, shutil
    scns = sorted(f[:-4] for f in os.listdir(os.path.join(args.golden, "missions")) if f.endswith(".scn"))
    bad = 0
    with tempfile.TemporaryDirectory() as d:
        for scn in scns:
            with open(os.path.join(d, scn + ".jsonl"), "w") as f:
                for r in load_rows(os.path.join(args.golden, "golden", scn + ".jsonl")):
                    f.write(json.dumps(r) + "\n")
            shutil.copy(os.path.join(args.golden, "golden", scn + ".meta.json"), d)
            figs = compare(scn, args.golden, d)
            n = sum(not f.ok for f in figs)
            print("self-test %s: recording against itself: %d of %d figures agree" % (scn, len(figs) - n, len(figs)))
            bad += n
        # mutate one scenario: drop one message delivery, rename a key, move one of the
        # driver's vehicles, post the status less often
        scn = "nodecomms_a3_messages"
        rows = load_rows(os.path.join(args.golden, "golden", scn + ".jsonl"))
        out = []
        dropped = moved = relay_dropped = False
        nstatus = 0
        for r in rows:
            if r["var"] == "NODE_MESSAGE_BEN" and not dropped:
                dropped = True
                continue
            # a report relayed to ben and unc but, here, not to cal: not the iteration's phase
            if r["var"] == "NODE_REPORT_CAL" and r["t"] > 20 and not relay_dropped:
                relay_dropped = True
                continue
            if r["var"] == "NODE_REPORT_ABE":
                r = dict(r, val=r["val"].replace("LAT=", "LATITUDE="))
            if r["var"] == "NODE_REPORT" and r["src"] == "driver" and r["t"] > 10 and not moved:
                moved = True
                r = dict(r, val=re.sub(r",X=([-\d.]+)", lambda m: ",X=%g" % (float(m.group(1)) + 5), r["val"], count=1))
            if r["var"] == "UFLDNODECOMMS_STATUS":
                nstatus += 1
                if nstatus % 4 == 0:
                    continue
            out.append(r)
        with open(os.path.join(d, scn + ".jsonl"), "w") as f:
            for r in out:
                f.write(json.dumps(r) + "\n")
        figs = compare(scn, args.golden, d)
        failed = {f.fid for f in figs if not f.ok}
        want = {"values/NODE_MESSAGE_BEN", "format/NODE_REPORT_ABE", "driver/values", "status/uFldNodeComms/cadence",
                "values/NODE_REPORT_CAL"}
        print("self-test mutated %s: failing figures %s" % (scn, sorted(failed)))
        if not want <= failed or not any(x.startswith("message/") for x in failed):
            print("self-test: the comparator missed a change")
            return 1
        def mutate_one(scn, change, want, what):
            """change the first row change() returns a new row for; the figure want must fail"""
            rows = load_rows(os.path.join(args.golden, "golden", scn + ".jsonl"))
            done = False
            for i, r in enumerate(rows):
                new = None if done else change(r)
                if new is not None:
                    rows[i], done = new, True
            with open(os.path.join(d, scn + ".jsonl"), "w") as f:
                for r in rows:
                    f.write(json.dumps(r) + "\n")
            failed = {f.fid for f in compare(scn, args.golden, d) if not f.ok}
            print("self-test mutated %s: failing figures %s" % (scn, sorted(failed)))
            if not done or want not in failed:
                print("self-test: the comparator missed %s" % what)
                return False
            return True

        def pulse_two_reports_off(r):  # v2 moves 1 m a report (2 m/s, 2 Hz)
            m = re.search(r",tx=([-\d.]+),", r["val"]) if r["var"] == "VIEW_COMMS_PULSE" and r["t"] > 20 else None
            if not m or "label=v32v2" not in r["val"]:
                return None
            return dict(r, val=r["val"].replace(m.group(0), ",tx=%g," % (float(m.group(1)) + 2), 1))

        def odometry_off(r):
            if r["var"] != "UPC_ODOMETRY_REPORT" or "vname=v3" not in r["val"] or r["t"] <= 17:
                return None
            return dict(r, val=re.sub(r"total_dist=([\d.]+)", lambda m: "total_dist=%.1f" % (float(m.group(1)) + 0.5), r["val"]))

        def summary_off(r):
            if r["var"] != "UMH_SUMMARY_MSGS" or r["t"] <= 10:
                return None
            return dict(r, val=re.sub(r"valid=(\d+)", lambda m: "valid=%d" % (int(m.group(1)) + 1), r["val"]))

        # a4: one pulse's far end two reports of its target away (one is the iteration's phase);
        # g1: one odometry value off by half a metre between its neighbours (not a skipped one);
        # b1: one summary's count changed (not a repeat, not superseded within an iteration)
        if not (mutate_one("nodecomms_a4_rates", pulse_two_reports_off, "values/VIEW_COMMS_PULSE",
                           "a pulse two reports off")
                and mutate_one("pathcheck_g1", odometry_off, "odometry/v3", "a changed odometry value")
                and mutate_one("msghandler_b1_default", summary_off, "values/UMH_SUMMARY_MSGS", "a changed summary")):
            return 1
    if bad:
        print("self-test: the recording does not agree with itself")
        return 1
    # the vehicle comparator, on kelp's own vehicle recordings: each agrees with itself, and a
    # vehicle 4 m off its track, a helm 2 s late or a rudder at 80 % is caught
    own = os.path.join(os.path.dirname(os.path.abspath(__file__)), "kelp-24.8")
    for f in sorted(os.listdir(os.path.join(own, "missions"))) if os.path.isdir(os.path.join(own, "missions")) else []:
        if not f.endswith(".scn"):
            continue
        G = load_rows(os.path.join(own, "golden", f[:-4] + ".jsonl"))
        if not is_vehicle(G):
            continue
        dep = min(r["t"] for r in G if r["var"] == "DEPLOY" and r["val"] == "true")
        cases = [("itself", lambda r: r, set()),
                 ("4 m east", lambda r: dict(r, val=r["val"] + 4) if r["var"] == "NAV_X" and r["t"] > dep + 20 else r,
                  {"vehicle/track"}),
                 ("helm 2 s late", lambda r: dict(r, t=r["t"] + 2) if r["src"] == "pHelmIvP" and r["t"] > dep + 20 else r,
                  {"vehicle/events"}),
                 ("rudder x 0.8", lambda r: dict(r, val=r["val"] * 0.8) if r["var"] == "DESIRED_RUDDER" else r,
                  {"vehicle/rudder_peaks"})]
        for name, fn, want in cases:
            failed = {x.fid for x in vehicle_figures(G, [fn(r) for r in G]) if not x.ok}
            print("self-test %s, %s: failing vehicle figures %s" % (f[:-4], name, sorted(failed)))
            if not want <= failed or (not want and failed):
                print("self-test: the vehicle comparator should fail %s" % sorted(want))
                return 1
    print("self-test: ok")
    return 0


FIRST_ITER_MAX_UP = 1.5


def app_phase(golden_dir, scn):
    """"APP PERIOD PHASE UPTIME" for a one-app mission: the app's iteration period (MOOS s,
    1/AppTick), where in it the recorded app's posts of its first two seconds after t0 fell
    (their median), and how long the recorded app had been up at t0 (from its first status'
    Uptime). The driver starts the replay at that phase of kelp's app, the candidate nearest
    that uptime, so that a report landing before or after an iteration, and what counts from
    the app's start, replay as recorded. "" for a mission of several apps (one phase cannot fit
    them all). 24.8's app slips against its clock by a fraction of a percent, so late in a run
    its timers' phase is its own: docs/CONFORMANCE.md lists what that moves."""
    tick, _ = mission_info(os.path.join(golden_dir, "missions", scn + ".moos"))
    apps = [a for a in tick if a.upper() not in ("ANTLER", "MOOSDB")]
    if len(apps) != 1 or tick[apps[0]] <= 0:
        return ""
    app, period = apps[0], 1.0 / tick[apps[0]]
    rows = load_rows(os.path.join(golden_dir, "golden", scn + ".jsonl"))
    ts = [r["t"] % period for r in rows if r["src"] == app and 0 <= r["t"] < 2]
    up = None
    for r in rows:
        if r["src"] == app and r["var"] == app.upper() + "_STATUS" and r["type"] == "string":
            u = dict(kv_pairs(r["val"]) or []).get("Uptime", "")
            if is_num(u):
                up = float(u) - r["t"]
                # a MOOS app starts up (OnStartUp: m_start_time) once connected to its
                # MOOSDB, 0.6-0.75 s after its process started in these recordings, and
                # iterates first one period later (its first status, posted at its first
                # iteration, says when: Uptime 0.85-1.01); kelp's app starts up at once and
                # iterates first one period later too. What counts from the start-up (the
                # hazard sensor's reset times) or from the first iteration (a beacon's
                # unsolicited timer, 24.8's m_iteration == 1) lines up when kelp's uptime at t0
                # is the recorded one less the connection time. A recording that begins after
                # the first status keeps the uptime as it is.
                if float(u) < FIRST_ITER_MAX_UP:
                    up -= max(0.0, float(u) - period)
                break
    if not ts or up is None:
        return ""
    # around the first (a phase near 0 has neighbours just under the period)
    d = sorted((t - ts[0] + period / 2) % period - period / 2 for t in ts)
    return "%s %.6f %.6f %.4f" % (app, period, (ts[0] + d[len(d) // 2]) % period, up)


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "--phase":
        # run.sh asks where the recorded app's iterations fell: compare.py --phase DIR SCENARIO
        print(app_phase(sys.argv[2], sys.argv[3]))
        return 0
    if len(sys.argv) == 3 and sys.argv[1] == "--gated":
        # run.sh asks which scenarios are gated (they run in a batch of their own)
        sys.exit(0 if any(fnmatch.fnmatch(sys.argv[2], g) for g in GATED) else 1)
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--golden", required=True)
    ap.add_argument("--kelp")
    ap.add_argument("--allow")
    ap.add_argument("--open", help="differences still open (test/conformance/open.txt)")
    ap.add_argument("--write-open", help="write this run's unlisted differences here")
    ap.add_argument("--self-test", action="store_true")
    ap.add_argument("-v", "--verbose", action="store_true")
    ap.add_argument("scenarios", nargs="*")
    args = ap.parse_args()
    if args.self_test:
        return self_test(args)
    if not args.scenarios:
        args.scenarios = sorted(f[:-4] for f in os.listdir(os.path.join(args.golden, "missions")) if f.endswith(".scn"))
    return run(args)


if __name__ == "__main__":
    sys.exit(main())
