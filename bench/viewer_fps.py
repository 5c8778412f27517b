#!/usr/bin/python3
# bench/viewer.sh's page side: headless Chromium on kelp-viewer's page; waits until N vehicles
# are shown, then counts the frames the page draws (window.kelpViewer.frames) and the stream
# messages it applies over SECONDS. Prints "page fps <f> messages/s <m> draw_ms <d> vehicles <v> trail <t>".
import shutil
import sys
import tempfile
import time
from selenium import webdriver
from selenium.webdriver.chrome.service import Service

url, n, secs = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
o = webdriver.ChromeOptions()
o.binary_location = "/usr/bin/chromium"
profile = tempfile.mkdtemp(prefix="kelp-chromium-")
for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1280,800",
          "--user-data-dir=" + profile):
    o.add_argument(a)
d = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=o)
try:
    d.get(url)
    end = time.time() + 30
    while time.time() < end and (d.execute_script("return window.kelpViewer ? Object.keys(window.kelpViewer.vehicles).length : 0") or 0) < n:
        time.sleep(0.2)
    get = "const S = window.kelpViewer; return [S.frames, S.messages, performance.now(), Object.keys(S.vehicles).length, S.drawMs, Object.values(S.vehicles).reduce((a, v) => a + v.trail.length, 0)];"
    f0, m0, t0, _, _, _ = d.execute_script(get)
    time.sleep(secs)
    f1, m1, t1, nv, dm, tr = d.execute_script(get)
    dt = (t1 - t0) / 1000
    print("page fps %.1f messages/s %.1f draw_ms %.1f vehicles %d trail %d" % ((f1 - f0) / dt, (m1 - m0) / dt, dm, nv, tr))
finally:
    d.quit()
    shutil.rmtree(profile, ignore_errors=True)
