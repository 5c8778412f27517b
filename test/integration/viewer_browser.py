#!/usr/bin/python3
# Drives kelp-viewer's page in headless Chromium (Debian's chromium + chromium-driver, with
# python3-selenium) for test/integration/viewer_browser.sh. Modes:
#   live URL OUT.json SHOT.png POKE_CMD...   the page during the fleet mission: vehicles, a
#                                            VIEW_POLYGON poked meanwhile, a real click on DEPLOY,
#                                            the state with vehicles moving, a screenshot
#   check OUT.json LOG.txt WARP              the page's positions against the shoreside log
#   replay URL OUT.json LIVE.json            replay mode: pause, seek with the slider (to the live
#                                            check's time: the same reports; near the start), play
# Prints "FAIL: ..." and exits 1 on a failed check.
import atexit
import json
import re
import shutil
import subprocess
import sys
import tempfile
import time


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


PROFILES = []
atexit.register(lambda: [shutil.rmtree(p, ignore_errors=True) for p in PROFILES])


def browser():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    o = webdriver.ChromeOptions()
    o.binary_location = "/usr/bin/chromium"
    PROFILES.append(tempfile.mkdtemp(prefix="kelp-chromium-"))
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1280,800",
              "--user-data-dir=" + PROFILES[-1], "--no-first-run"):
        o.add_argument(a)
    d = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=o)
    d.set_page_load_timeout(20)
    return d


def wait(d, js, secs, what):
    end = time.time() + secs
    while time.time() < end:
        v = d.execute_script(js)
        if v:
            return v
        time.sleep(0.2)
    fail("timed out (%gs) waiting for %s; page state: %s" % (secs, what, d.execute_script(
        "const S=window.kelpViewer; return S && JSON.stringify({seq:S.seq, n:Object.keys(S.vehicles), "
        "art:Object.keys(S.artifacts), conn:S.connected, replay:S.replay})")))


STATE_JS = """const S = window.kelpViewer, out = {now: S.now, veh: {}};
for (const v of Object.values(S.vehicles)) out.veh[v.name] = {x: v.x, y: v.y, rtime: v.rtime, spd: v.spd || 0, stale: v.stale, trail: v.trail.length};
return out;"""

COLOURS_JS = """const c = document.getElementById('map'), g = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
const seen = new Set(); for (let i = 0; i < g.length; i += 4 * 7) seen.add((g[i] << 16) | (g[i + 1] << 8) | g[i + 2]);
return seen.size;"""


def interact(d):
    """The pointer readout, selecting a vehicle (its report in the panel), wheel zoom, drag pan."""
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.actions.wheel_input import ScrollOrigin
    from selenium.webdriver.support.ui import Select
    canvas = d.find_element("id", "map")
    ActionChains(d).move_to_element_with_offset(canvas, 40, 30).perform()
    ro = d.find_element("id", "readout").text
    m = re.match(r"x=(-?[0-9.]+) y=(-?[0-9.]+)\s+lat=(-?[0-9.]+) lon=(-?[0-9.]+)", ro)
    if not m:
        fail("pointer readout %r" % ro)
    lat, lon = float(m.group(3)), float(m.group(4))
    if abs(lat - 43.8253) > 0.02 or abs(lon + 70.3304) > 0.03:
        fail("readout lat/lon %s far from the datum" % ro)
    Select(d.find_element("id", "vehicle-list")).select_by_value("alpha")
    wait(d, "return document.getElementById('sel-name').textContent === 'alpha' &&"
            " document.getElementById('sel-fields').textContent.includes('X (m)')", 5, "alpha's report in the panel")
    panel = d.find_element("id", "sel-fields").text
    scale0 = d.execute_script("return window.kelpViewer.view.scale")
    ActionChains(d).scroll_from_origin(ScrollOrigin.from_element(canvas), 0, -400).perform()
    wait(d, "return window.kelpViewer.view.scale > %f" % (scale0 * 1.2), 5, "the wheel to zoom in")
    v = d.execute_script("return [window.kelpViewer.view.cx, window.kelpViewer.view.scale]")
    ActionChains(d).move_to_element(canvas).click_and_hold().move_by_offset(120, 0).release().perform()
    cx = d.execute_script("return window.kelpViewer.view.cx")
    if abs((v[0] - cx) - 120 / v[1]) > 5 / v[1]:
        fail("dragging 120 px moved the view %.2f m, want %.2f" % (v[0] - cx, 120 / v[1]))
    return {"readout": ro, "panel": panel, "zoom": [scale0, v[1]]}


def live(url, out, shot, poke):
    d = browser()
    res = {}
    try:
        d.get(url)
        wait(d, "return window.kelpViewer && window.kelpViewer.cfg && Object.keys(window.kelpViewer.vehicles).length >= 2",
             25, "two vehicles in the page")
        btn = d.find_element("id", "cmd-0")
        if btn.text != "DEPLOY":
            fail("the first button is %r, want DEPLOY" % btn.text)
        # (b) a VIEW_POLYGON posted on the shoreside bus during the run
        r = subprocess.run(poke, capture_output=True, text=True)
        if r.returncode != 0:
            fail("kelp-poke: " + r.stdout + r.stderr)
        pts = wait(d, "const a = window.kelpViewer.artifacts['polygon:viewer_test']; return a && a.pts", 10,
                   "the poked VIEW_POLYGON in the page")
        if pts != [[-50, -50], [50, -50], [50, 50], [-50, 50]]:
            fail("polygon vertices %s" % pts)
        res["polygon"] = pts
        before = d.execute_script(STATE_JS)
        if any(v["spd"] > 0.2 for v in before["veh"].values()):
            fail("a vehicle moves before DEPLOY: %s" % before)
        # (c) a real click on the configured DEPLOY button
        btn.click()
        wait(d, "return Object.values(window.kelpViewer.vehicles).filter(v => (v.spd || 0) > 0.5).length >= 2", 25,
             "both vehicles under way after DEPLOY")
        time.sleep(1.0)
        st = d.execute_script(STATE_JS)
        st["now"] = d.execute_script("return window.kelpViewer.now")
        res["state"] = st
        res["pressed"] = d.execute_script("return window.kelpViewer.pressed")
        # the shoreside apps' AppCasts (kelp-viewer asks with APPCAST_REQ), shown in the pane
        res["casts"] = wait(d, "const c = Object.values(window.kelpViewer.casts).filter(c => c.node === 'shoreside');"
                               "return c.length >= 3 && document.querySelectorAll('#casts details').length >= 1 && c.map(c => c.proc)",
                            15, "the shoreside's AppCasts")
        res["colours"] = d.execute_script(COLOURS_JS)
        res["fps"] = d.execute_script("return window.kelpViewer.fps")
        res["ui"] = interact(d)
        d.find_element("id", "fit").click()  # the whole fleet again, alpha still selected
        time.sleep(0.5)
        # (d) the screenshot
        d.save_screenshot(shot)
    finally:
        d.quit()
    json.dump(res, open(out, "w"), indent=1)
    print("page: %d vehicles, polygon shown, DEPLOY clicked, %d colours, %s fps, AppCasts of %s" % (
        len(res["state"]["veh"]), res["colours"], res["fps"], ",".join(sorted(res["casts"]))))
    print("page: readout %r, alpha selected (%d panel rows), wheel zoom %.2f -> %.2f px/m, drag pans" % (
        res["ui"]["readout"], res["ui"]["panel"].count("\n") + 1, res["ui"]["zoom"][0], res["ui"]["zoom"][1]))


LAG_S = 4.0


def check(out, logtxt, warp):
    res = json.load(open(out))
    st = res["state"]
    reports = {}
    for line in open(logtxt, errors="replace"):
        f = line.split(" ", 3)
        if len(f) < 4 or not f[2].startswith("NODE_REPORT") or f[2] not in ("NODE_REPORT", "NODE_REPORT_LOCAL"):
            continue
        kv = dict(p.split("=", 1) for p in f[3].strip().split(",") if "=" in p)
        if "NAME" in kv and "TIME" in kv and "X" in kv:
            reports.setdefault(kv["NAME"], []).append((float(f[0]), kv["TIME"], float(kv["X"]), float(kv["Y"])))
    for name, v in st["veh"].items():
        rs = reports.get(name)
        if not rs:
            fail("%s: no NODE_REPORT in the shoreside log" % name)
        want = "%.2f" % v["rtime"]
        # 24.8's reports trim trailing zeros (TIME=1795910622.6): compared as numbers
        match = [r for r in rs if abs(float(r[1]) - v["rtime"]) < 0.006]
        if not match:
            fail("%s: the page's report (TIME=%s) is not in the log" % (name, want))
        _, _, x, y = match[-1]
        err = ((x - v["x"]) ** 2 + (y - v["y"]) ** 2) ** 0.5
        if err > 1.0:
            fail("%s: page (%.2f, %.2f), log (%.2f, %.2f): %.2f m apart" % (name, v["x"], v["y"], x, y, err))
        # it is live: no report newer than the page's was logged more than LAG_S (wall) before the
        # page's time. The viewer reads the bus once per AppTick; on a loaded CI host its process
        # and the browser wait their turn (2.5 s seen), so the bound is 4 s, not one tick.
        older = [r for r in rs if r[0] <= st["now"] - LAG_S * warp]
        newest = max(older, key=lambda r: float(r[1])) if older else None
        if newest and float(newest[1]) > v["rtime"] + 1e-6:
            fail("%s: the page shows TIME=%s but the log had %s %g s (wall) earlier" % (name, want, newest[1], LAG_S))
        logged = [float(r[1]) for r in rs if r[0] <= st["now"]]
        lag = max(logged) - v["rtime"] if logged else 0.0
        print("ok: %s at (%.2f, %.2f), its report TIME=%s in the log at (%.2f, %.2f): %.3f m; the newest"
              " logged report is %.2f MOOS s newer (%.2f wall s at warp %g)"
              % (name, v["x"], v["y"], want, x, y, err, max(lag, 0.0), max(lag, 0.0) / warp, warp))


def replay(url, out, live_json):
    live = json.load(open(live_json))["state"]
    d = browser()
    res = {}
    try:
        d.get(url)
        # (the log starts with the recorders, before the vehicles are bridged to the shoreside:
        # the vehicles are looked for by seeking, below)
        r = wait(d, "const S = window.kelpViewer; return S.replay", 20, "the replay state")
        if d.find_element("id", "replay").get_attribute("hidden"):
            fail("replay controls hidden")
        span = r["t1"] - r["t0"]
        if span < 5 or not (r["t0"] < live["now"] < r["t1"]):
            fail("replay spans %.1f s, %.1f..%.1f; the live check was at %.1f" % (span, r["t0"], r["t1"], live["now"]))
        if r["playing"]:
            d.find_element("id", "play").click()  # pause
            wait(d, "return window.kelpViewer.replay && !window.kelpViewer.replay.playing", 5, "pause")

        def seek(frac, what):
            d.execute_script("const s = document.getElementById('slider'); s.value = arguments[0];"
                             "s.dispatchEvent(new Event('input')); s.dispatchEvent(new Event('change'));", int(round(frac * 1000)))
            want = r["t0"] + round(frac * 1000) / 1000 * span
            wait(d, "const R = window.kelpViewer.replay; return R && Math.abs(R.t - %f) < 0.5" % want, 8, what)
            time.sleep(0.4)
            return d.execute_script(STATE_JS), want, d.find_element("id", "slider").get_attribute("value")

        # the moment the live page was checked (vehicles under way): the same reports again
        at_live, t_live, _ = seek((live["now"] - r["t0"]) / span, "the replay at the live check's time")
        for n, v in live["veh"].items():
            w = at_live["veh"].get(n)
            if not w:
                fail("%s missing in the replay at %.1f" % (n, t_live))
            if not (t_live - 30 <= w["rtime"] <= t_live + 1):
                fail("%s: the replay at %.2f shows the report of %.2f" % (n, t_live, w["rtime"]))
            if abs(w["x"] - v["x"]) + abs(w["y"] - v["y"]) > 80:
                fail("%s: replay (%.1f, %.1f), live (%.1f, %.1f)" % (n, w["x"], w["y"], v["x"], v["y"]))
        # near the start (before DEPLOY): the vehicles at their start points, the slider there
        # (the first 5 % step at which every vehicle is there, before the live check's time)
        frac, fr_live = 0.05, (live["now"] - r["t0"]) / span
        while True:
            at_start, _, slider = seek(frac, "the replay at %d%%" % round(frac * 100))
            if all(n in at_start["veh"] for n in live["veh"]) or frac + 0.05 >= fr_live - 0.05:
                break
            frac += 0.05
        moved = [n for n in live["veh"] if n in at_start["veh"] and
                 abs(at_start["veh"][n]["x"] - at_live["veh"][n]["x"]) + abs(at_start["veh"][n]["y"] - at_live["veh"][n]["y"]) > 1]
        if len(moved) < len(live["veh"]):
            fail("seeking back moved only %s: %s / %s" % (moved, at_start, at_live))
        if abs(int(slider) - round(frac * 1000)) > 10:
            fail("slider at %s after seeking to %d%%" % (slider, round(frac * 100)))
        d.find_element("id", "play").click()
        t = d.execute_script("return window.kelpViewer.replay.t")
        wait(d, "const R = window.kelpViewer.replay; return R.playing && R.t > %f" % (t + 0.5), 8, "play to advance")
        res = {"at_live": at_live, "at_start": at_start, "slider": slider, "slider_frac": frac}
    finally:
        d.quit()
    json.dump(res, open(out, "w"), indent=1)
    print("replay: paused, seeked to the live check's time (same reports) and back to %d%% (slider %s, %d vehicles back at"
          " their starts), playing again" % (round(res["slider_frac"] * 100), res["slider"], len(res["at_start"]["veh"])))


if __name__ == "__main__":
    m = sys.argv[1]
    if m == "live":
        live(sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:])
    elif m == "check":
        check(sys.argv[2], sys.argv[3], float(sys.argv[4]))
    elif m == "replay":
        replay(sys.argv[2], sys.argv[3], sys.argv[4])
    else:
        fail("mode?")
