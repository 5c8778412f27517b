#!/usr/bin/python3
# Drives kelp-viewer's page in headless Chromium (Debian's chromium + chromium-driver, with
# python3-selenium) for test/integration/viewer_browser.sh. Modes:
#   live URL OUT.json SHOT.png POKE_CMD...   the page during the fleet mission: vehicles, a
#                                            VIEW_POLYGON poked meanwhile, a real click on DEPLOY,
#                                            the state with vehicles moving, a screenshot
#   check OUT.json LOG.txt WARP              the page's positions against the shoreside log
#   replay URL OUT.json                      replay mode: pause, seek with the slider, play
# Prints "FAIL: ..." and exits 1 on a failed check.
import json
import os
import re
import subprocess
import sys
import tempfile
import time


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def browser():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    o = webdriver.ChromeOptions()
    o.binary_location = "/usr/bin/chromium"
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1280,800",
              "--user-data-dir=" + tempfile.mkdtemp(prefix="kelp-chromium-"), "--no-first-run"):
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
        time.sleep(2.0)
        st = d.execute_script(STATE_JS)
        st["now"] = d.execute_script("return window.kelpViewer.now")
        res["state"] = st
        res["pressed"] = d.execute_script("return window.kelpViewer.pressed")
        res["colours"] = d.execute_script(COLOURS_JS)
        res["fps"] = d.execute_script("return window.kelpViewer.fps")
        # (d) the screenshot
        d.save_screenshot(shot)
    finally:
        d.quit()
    json.dump(res, open(out, "w"), indent=1)
    print("page: %d vehicles, polygon shown, DEPLOY clicked, %d colours, %s fps" % (len(res["state"]["veh"]),
                                                                                   res["colours"], res["fps"]))


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
        match = [r for r in rs if r[1] == want]
        if not match:
            fail("%s: the page's report (TIME=%s) is not in the log" % (name, want))
        _, _, x, y = match[-1]
        err = ((x - v["x"]) ** 2 + (y - v["y"]) ** 2) ** 0.5
        if err > 1.0:
            fail("%s: page (%.2f, %.2f), log (%.2f, %.2f): %.2f m apart" % (name, v["x"], v["y"], x, y, err))
        # it is the last one: nothing newer was posted more than a second (wall) before the page's time
        older = [r for r in rs if r[0] <= st["now"] - 1.0 * warp]
        if older and float(max(older, key=lambda r: float(r[1]))[1]) > v["rtime"] + 1e-6:
            fail("%s: the page shows TIME=%s but the log had %s a second earlier" % (name, want, max(older)[1]))
        print("ok: %s at (%.2f, %.2f), its report TIME=%s in the log at (%.2f, %.2f): %.3f m" % (name, v["x"], v["y"],
                                                                                                  want, x, y, err))


def replay(url, out):
    d = browser()
    res = {}
    try:
        d.get(url)
        r = wait(d, "const S = window.kelpViewer; return S.replay && Object.keys(S.vehicles).length >= 1 && S.replay", 20,
                 "the replay state and a vehicle")
        if d.find_element("id", "replay").get_attribute("hidden"):
            fail("replay controls hidden")
        span = r["t1"] - r["t0"]
        if span < 5:
            fail("replay spans only %.1f s" % span)
        if r["playing"]:
            d.find_element("id", "play").click()  # pause
            wait(d, "return window.kelpViewer.replay && !window.kelpViewer.replay.playing", 5, "pause")
        res["slider_before"] = d.find_element("id", "slider").get_attribute("value")
        for frac in (0.6, 0.15):
            d.execute_script("const s = document.getElementById('slider'); s.value = arguments[0];"
                             "s.dispatchEvent(new Event('input')); s.dispatchEvent(new Event('change'));", int(frac * 1000))
            want = r["t0"] + frac * span
            wait(d, "const R = window.kelpViewer.replay; return R && Math.abs(R.t - %f) < 0.5" % want, 8,
                 "the replay at %.0f%%" % (frac * 100))
            time.sleep(0.6)
            res["at_%d" % int(frac * 100)] = d.execute_script(STATE_JS)
            res["slider_%d" % int(frac * 100)] = d.find_element("id", "slider").get_attribute("value")
        a, b = res["at_60"]["veh"], res["at_15"]["veh"]
        moved = [n for n in a if n in b and abs(a[n]["x"] - b[n]["x"]) + abs(a[n]["y"] - b[n]["y"]) > 1]
        if not moved:
            fail("seeking from 60%% to 15%% moved no vehicle: %s / %s" % (a, b))
        if abs(int(res["slider_15"]) - 150) > 20:
            fail("slider at %s after seeking to 15%%" % res["slider_15"])
        d.find_element("id", "play").click()
        t = d.execute_script("return window.kelpViewer.replay.t")
        wait(d, "const R = window.kelpViewer.replay; return R.playing && R.t > %f" % (t + 0.5), 8, "play to advance")
    finally:
        d.quit()
    json.dump(res, open(out, "w"), indent=1)
    print("replay: paused, seeked to 60%% and 15%% (slider %s -> %s), %d vehicles moved, playing again" % (
        res["slider_60"], res["slider_15"], len(moved)))


if __name__ == "__main__":
    m = sys.argv[1]
    if m == "live":
        live(sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:])
    elif m == "check":
        check(sys.argv[2], sys.argv[3], float(sys.argv[4]))
    elif m == "replay":
        replay(sys.argv[2], sys.argv[3])
    else:
        fail("mode?")
