# SPDX-License-Identifier: MIT
"""The page of `ggrt serve` in a real browser: headless Chromium driven by
Selenium (Debian: chromium, chromium-driver, python3-selenium; run it with
the python3 that has selenium, /usr/bin/python3 on Debian). One browser,
one server per scene:
- every scene file under examples/scenes (models included) and
  tests/data/debug, and the scenes at the top of tests/data, at 64x48,
  depth 3: the page loads, a click shows the pixel's tree and the 3D
  view (every mesh and implicit-surface triangle; under examples/scenes
  not blank with the camera and rays presets), the image's rays and shadow verdicts are ggrt render's, no
  console error; every tab on glass, gears, knot and water;
- tracing first: a pixel of spd/gears.nff at depth 16 and 16 samples
  shows its tree within 1 s of the click while the image still renders;
  with every job slot taken the page says it is waiting (503, Retry-After);
- glass.nff at full size: the tree (refraction, TIR, the value equal to
  ggrt render's), collapsing, hover, the arrow keys and the URL, heatmap,
  find, the 3D view shaded by WebGL and linked to the tree (hover a node:
  its segment and its object in the image; click a segment: its node;
  j/k; arrows after a dropdown), the exports (tree JSON equal to
  /api/trace's bytes, SVG, OBJ, PNG, the command line, which is run),
  ledger, diagnostics, diff mode, a reload from the URL (3D camera too);
  option texts whose flags differ from their words: the copied command
  and the options panel keep them;
- light-path expressions on glass.nff: the path box (its keys not
  captured, a malformed path's column), the share heatmap with its legend
  (the count of matched pixels and every share equal ggrt find --path's),
  the tree filtered to the matching paths, hidden then dimmed (the rays
  kept and the summary equal ggrt trace --path's), the URL keeping it;
- the layout at 1280 and 1920 px wide: the tree panel inside the window in
  normal and diff mode and at 4x zoom (screenshots in build/browser/);
- Back and Forward (history): pixels, a tab, each a history entry restored
  whole from the address (the tree without asking the server again); the
  3D camera and the zoom change the entry in place;
- textures: tests/data/textured.nff (every kind of shape, textured) in the
  3D view through the scene's camera: at every textured hit of every 4th
  pixel the canvas shows the ray tree's surface colour (the texture at the
  renderer's (u, v)) under the view's shading, each flat object in more
  than one colour;
- implicit: examples/scenes/torus.nff in the 3D view through the scene's
  camera: the torus drawn as its surface (at its hits, its colour under the
  renderer's normal) and the floor seen around it and through its hole;
- regressions (fixes): one check per bug fixed in the page (the 3D
  view's redraw time, typing in the find and path boxes, ...);
- with --docs DIR, the linked 3D views of glass and knot, and the path
  filter on glass, as PNGs there (docs/serve.md shows them).
    /usr/bin/python3 tests/browser/browser_test.py build/ggrt [--screenshot FILE] [--docs DIR]
        [--only glass,layout,first,scenes,paths,history,textures,implicit,fixes,docs]
Prints one line per check and ends with "browser: N passed, M failed"."""
import json
import os
import re
import shlex
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import traceback
import urllib.error
import urllib.parse
import urllib.request

from selenium import webdriver
from selenium.common.exceptions import TimeoutException
from selenium.webdriver.chrome.options import Options
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support.ui import Select, WebDriverWait

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GGRT = os.path.abspath(sys.argv[1]) if len(sys.argv) > 1 else os.path.join(ROOT, "build", "ggrt")
SHOT = sys.argv[sys.argv.index("--screenshot") + 1] if "--screenshot" in sys.argv else None
DOCS = sys.argv[sys.argv.index("--docs") + 1] if "--docs" in sys.argv else None
ONLY = sys.argv[sys.argv.index("--only") + 1].split(",") if "--only" in sys.argv else None
OUT = os.path.dirname(os.path.abspath(SHOT)) if SHOT else tempfile.mkdtemp(prefix="ggrt-browser-out-")
SCENE = "examples/scenes/glass.nff"
PIXEL = (110, 100)
TABBED = ("glass.nff", "gears.nff", "knot.nff", "water.nff")  # every tab is opened on these
passed = failed = 0


def check(cond, name, detail=""):
    global passed, failed
    if cond:
        passed += 1
        print("ok   " + name)
    else:
        failed += 1
        print("FAIL " + name)
        for line in str(detail).splitlines()[:20]:
            print("     " + line)
    sys.stdout.flush()
    return cond


def find_binary(*names):
    for n in names:
        p = shutil.which(n) or (n if os.path.exists(n) else None)
        if p:
            return p
    return None


def browser(profile):
    o = Options()
    # SwiftShader: WebGL in software, as headless Chromium has no GPU.
    for a in ("--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
              "--disable-background-networking", "--disable-component-update", "--disable-sync",
              "--no-first-run", "--disable-default-apps", "--disable-extensions", "--window-size=1500,980",
              "--user-data-dir=" + profile):
        o.add_argument(a)
    o.binary_location = find_binary("chromium", "/usr/bin/chromium", "chromium-browser")
    o.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    drv = find_binary("chromedriver", "/usr/bin/chromedriver")
    return webdriver.Chrome(service=Service(drv), options=o)


def wait(d, what, fn, timeout=60):
    try:
        return WebDriverWait(d, timeout, poll_frequency=0.02).until(lambda _: fn())
    except TimeoutException:
        return None


class Server:
    """ggrt serve SCENE ARGS on a free port."""

    def __init__(self, scene, *args):
        self.p = subprocess.Popen([GGRT, "serve", scene, "--port", "0"] + list(args), cwd=ROOT,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.url = self.p.stdout.readline().strip()
        self.base = self.url.split("/?")[0]
        self.token = self.url.split("token=")[-1]

    def get(self, path, **params):
        q = urllib.parse.urlencode(params)
        req = urllib.request.Request(self.base + path + ("?" + q if q else ""),
                                     headers={"Authorization": "Bearer " + self.token})
        try:
            with urllib.request.urlopen(req, timeout=30) as r:
                return r.status, r.read()
        except urllib.error.HTTPError as e:
            return e.code, e.read()

    def stop(self):
        self.p.send_signal(signal.SIGINT)
        try:
            rc = self.p.wait(30)
        except subprocess.TimeoutExpired:
            self.p.kill()
            rc = "hung"
        return rc, self.p.stderr.read()[-500:]


def console_errors(d):
    return [e["message"] for e in d.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]


def attr(d, el_id, name):
    return d.find_element(By.ID, el_id).get_attribute(name)


def page_error(d):
    e = d.find_element(By.ID, "error")
    return e.get_attribute("textContent") if e.is_displayed() else ""


def cli_pixel():
    """The value ggrt render writes at PIXEL, as it prints it (%.9g)."""
    with tempfile.TemporaryDirectory() as t:
        out = subprocess.run([GGRT, "render", SCENE, "-q", "-o", os.path.join(t, "x.png"), "--pixel",
                              "%d,%d" % PIXEL], cwd=ROOT, stdout=subprocess.PIPE, text=True, check=True).stdout
    m = re.search(r"^pixel %d,%d (\S+ \S+ \S+)$" % PIXEL, out, re.M)
    return m.group(1)


def click_pixel(d, x, y, move_only=False):
    """Click (or hover) the centre of image pixel x, y: Selenium offsets
    count from the element's centre, in CSS pixels."""
    c = d.find_element(By.ID, "image")
    w, h = c.size["width"], c.size["height"]
    W, H = int(c.get_attribute("width")), int(c.get_attribute("height"))
    dx, dy = (x + 0.5) * w / W - w / 2, (y + 0.5) * h / H - h / 2
    a = ActionChains(d).move_to_element_with_offset(c, int(round(dx)), int(round(dy)))
    (a if move_only else a.click()).perform()


def overlay_alpha(d, x, y):
    return d.execute_script("const g = document.getElementById('overlay').getContext('2d');"
                            "return Array.from(g.getImageData(%d, %d, 1, 1).data);" % (x, y))


def selected_pixel(d):
    return attr(d, "pixel-head", "data-pixel")


# ---- every scene ----

def scene_files():
    out = []
    for top in ("examples/scenes", "tests/data/debug"):
        for dp, _, fn in os.walk(os.path.join(ROOT, top)):
            out += [os.path.relpath(os.path.join(dp, f), ROOT) for f in fn if f.endswith((".nff", ".obj", ".ply"))]
    # the scenes at the top of tests/data: not hostile/, whose inputs must
    # fail, nor meshes/, loader fixtures of which flat.obj must fail too
    out += [os.path.join("tests/data", f) for f in os.listdir(os.path.join(ROOT, "tests/data")) if f.endswith(".nff")]
    return sorted(out)


TAB_READY = {
    "tree": "return document.querySelectorAll('#tree-a details.node').length > 0",
    "rays3d": "return document.getElementById('box3d').parentElement.id === 'tab-rays3d'",
    "views": "const i = document.getElementById('svg-view'); return i.complete && i.naturalWidth > 0",
    "ledger": "return document.querySelectorAll('#ledger p').length > 0",
    "diag": "return document.querySelectorAll('#diag tr').length === 8",
    "text": "return document.getElementById('trace-text').textContent.length > 0",
}


def open_tabs(d):
    """Every tab in turn; the names of those whose content did not come."""
    bad = []
    for tab, ready in TAB_READY.items():
        d.find_element(By.CSS_SELECTOR, "#tabs [data-tab=%s]" % tab).click()
        if not wait(d, tab, lambda r=ready: d.execute_script(r), 15):
            bad.append(tab)
    d.find_element(By.CSS_SELECTOR, "#tabs [data-tab=tree]").click()
    return bad


def mesh_triangles(scene):
    """The triangles of every mesh as ggrt info counts them (0 for none)."""
    out = subprocess.run([GGRT, "info", scene], cwd=ROOT, stdout=subprocess.PIPE, text=True).stdout
    return sum(int(n) for n in re.findall(r"^\s+(\d+) triangles, ", out, re.M))


def cli_rays(scene, *args):
    """ggrt render's rays, shadow rays, blocked and attenuated ones."""
    with tempfile.TemporaryDirectory() as t:
        out = subprocess.run([GGRT, "render", scene, "-o", os.path.join(t, "x.exr")] + list(args), cwd=ROOT,
                             stdout=subprocess.PIPE, text=True).stdout
    m = re.search(r"shadow (\d+) \(blocked (\d+), attenuated (\d+)\), total (\d+)", out)
    return m and " ".join(m.group(k) for k in (4, 1, 2, 3))


def every_scene(d):
    t0, n, broken = time.time(), 0, []
    for sc in scene_files():
        srv = Server(sc, "-s", "64x48", "-d", "3")
        what, t1 = [], time.time()
        try:
            console_errors(d)
            d.get(srv.url)
            # The click goes in as soon as the page has the scene (the image
            # need not be there: tracing first).
            wait(d, "ready", lambda: d.execute_script("return !!window.ggrt") or page_error(d), 20)
            if not d.execute_script("return !!window.ggrt"):
                what.append("the page did not start: " + page_error(d))
            else:
                click_pixel(d, 32, 24)
                if not wait(d, "tree", lambda: selected_pixel(d) == "32,24" or page_error(d), 20) or page_error(d):
                    what.append("no tree for 32,24: " + page_error(d))
                if not wait(d, "image", lambda: attr(d, "viewport", "data-image") or page_error(d), 20) or page_error(d):
                    what.append("no image: " + page_error(d))
                want = cli_rays(sc, "-s", "64x48", "-d", "3")
                got = attr(d, "viewport", "data-rays-a")
                if not want or got != want:
                    what.append("the page counts rays and shadow verdicts %r, ggrt render %r" % (got, want))
                if not wait(d, "3D", lambda: attr(d, "box3d", "data-triangles"), 10):
                    what.append("no 3D view: " + d.find_element(By.ID, "note3d").text)
                want = mesh_triangles(sc)
                got = int(attr(d, "box3d", "data-mesh-triangles") or 0)
                if got != want:
                    what.append("the 3D view shades %d mesh triangles, ggrt info counts %d" % (got, want))
                # Implicit surfaces: every triangle /api/scene sends is shaded.
                shapes = json.loads(srv.get("/api/scene")[1])["shapes"]
                want = sum(s["surface"]["triangles"] for s in shapes if s and s.get("surface"))
                got = int(attr(d, "box3d", "data-surface-triangles") or 0)
                if got != want or (want == 0) != (not any(s and s["kind"] == "implicit" for s in shapes)):
                    what.append("the 3D view shades %d implicit-surface triangles, /api/scene sends %d" % (got, want))
                # The "camera" and "rays" presets show some of the scene
                # (acc-distant.nff: a camera 3e7 away looking through
                # 0.00001 degrees used to show nothing).
                if sc.startswith("examples/scenes/"):
                    for view in ("camera", "rays"):
                        d.find_element(By.CSS_SELECTOR, "#box3d [data-view=%s]" % view).click()
                        if not count_gl(d):
                            what.append("the 3D view is blank with the %s preset" % view)
                if os.path.basename(sc) in TABBED:
                    bad = open_tabs(d)
                    if bad:
                        what.append("tabs without content: " + ", ".join(bad))
            what += console_errors(d)
        finally:
            rc, err = srv.stop()
            if rc != 0:
                what.append("ggrt serve exit %s: %s" % (rc, err))
        n += 1
        tabs = " (every tab)" if os.path.basename(sc) in TABBED else ""
        if not check(not what, "%s: the page loads, a click shows the tree and the 3D view (every mesh "
                     "and implicit-surface triangle, not blank from the camera and the rays), ggrt render's ray counts, "
                     "no console error%s (%.1f s)" % (sc, tabs, time.time() - t1), "\n".join(what)):
            broken.append(sc)
    print("every scene: %d files in %.1f s; failing: %s" % (n, time.time() - t0, " ".join(broken) or "none"))


# ---- tracing first; a full queue waited for ----

def tracing_first(d):
    srv = Server("examples/scenes/spd/gears.nff")
    try:
        # 64 samples: about 11 s of rendering on 2 threads of a 2026 Xeon,
        # so that the image is still rendering when the tree is shown (at
        # 16 samples a CI run once saw it finish first, in 2.8 s)
        opts = "depth=16 samples=64"
        d.get(srv.url + "#a=" + urllib.parse.quote(opts))
        wait(d, "rendering", lambda: "rendering" in d.find_element(By.ID, "status-text").text, 20)
        t0 = time.time()
        click_pixel(d, 200, 200)
        ok = wait(d, "tree", lambda: selected_pixel(d) == "200,200", 10)
        polled = time.time() - t0
        # The page's own clock from the click to the tree shown (app.js,
        # data-clicked-at / data-shown-at): Selenium's polling, slow on a
        # loaded machine, is not part of what a user waits.
        try:
            dt = (float(attr(d, "pixel-head", "data-shown-at")) -
                  float(attr(d, "pixel-head", "data-clicked-at"))) / 1000
        except (TypeError, ValueError):
            dt = float("inf")
        rendering = not attr(d, "viewport", "data-image")
        nodes = len(d.find_elements(By.CSS_SELECTOR, "#tree-a details.node"))
        check(ok and dt < 1.0 and rendering and nodes > 1,
              "gears.nff, depth 16, 64 samples: pixel 200,200's tree (%d rays) %.2f s after the click "
              "(%.2f s as the test polled), the image still rendering" % (nodes, dt, polled),
              d.find_element(By.ID, "status-text").text)
        # Take every job slot, then ask for another image: 503 with
        # Retry-After, which the page waits out. Ask until the server says
        # 503 (the image above may have finished and freed its slot: a
        # faster machine did), with renders of 64 samples so none ends
        # before the page asks.
        # A job that ends between the 503 and the page's request frees a
        # slot and the page is served (a run of 2026-12-05 saw it): then
        # take the slots again and ask with other options, up to 3 times.
        # The page gives up a job it no longer shows: /api/cancel, and the
        # job stops a second later (SRV_CANCEL_GRACE) and frees its slot,
        # where the page's next request would be served, queued, not
        # refused (a CI run under load saw it three times running). So
        # first a cheap view, finished, and the gears render's slot freed:
        # then the page holds no job and gives none up.
        d.execute_script("location.hash = arguments[0]", "a=" + urllib.parse.quote("depth=1"))
        wait(d, "a cheap image", lambda: attr(d, "viewport", "data-image") and
             "rendering" not in d.find_element(By.ID, "status-text").text, 30)
        time.sleep(3)
        codes, ok, full = [], False, True
        for attempt in range(3):
            for i in range(12):
                codes.append(srv.get("/api/render", opts="depth=16 samples=64 cutoff=0.%d%02d"
                                     % (attempt, i + 1))[0])
                if codes[-1] == 503:
                    break
            full = full and codes[-1] == 503
            d.execute_script("location.hash = arguments[0]",
                             "a=" + urllib.parse.quote("depth=15 samples=%d" % (16 + attempt)))
            ok = wait(d, "waiting", lambda: attr(d, "status", "data-waiting") == "1" and
                      "waiting" in d.find_element(By.ID, "status-text").text, 10)
            if ok:
                break
        check(full, "every job slot taken: the server answers 503 (%s)" % " ".join(map(str, codes)))
        check(ok and not page_error(d), "every job slot busy (%s): the page says it is waiting (%s), no error"
              % (" ".join(map(str, codes)), d.find_element(By.ID, "status-text").text), page_error(d))
        errs = console_errors(d)
        # A 503 is logged by Chromium as a failed resource: that is the
        # server's answer, not a page error.
        errs = [e for e in errs if "503" not in e]
        check(not errs, "no console errors while waiting", "\n".join(errs))
    finally:
        # The server first, the page still open: leaving the page while
        # its requests wait for a job slot held chromedriver 40-70 s (12
        # s once the server is gone; cause not found: the page's timers
        # ran on, and the server answered in < 0.1 s throughout).
        rc, err = srv.stop()
        d.get("about:blank")
        check(rc == 0, "ggrt serve stopped cleanly with jobs running", err)


# ---- glass.nff: the tree, the views linked, the exports ----

def count_gl(d):
    """Pixels of the WebGL canvas that are not its background."""
    return d.execute_script(
        "const s = document.getElementById('gl3d'), c = document.createElement('canvas');"
        "c.width = s.width; c.height = s.height; const g = c.getContext('2d'); g.drawImage(s, 0, 0);"
        "const a = g.getImageData(0, 0, c.width, c.height).data; let n = 0;"
        "for (let i = 0; i < a.length; i += 4) if (Math.abs(a[i] - 247) + Math.abs(a[i + 1] - 247) +"
        " Math.abs(a[i + 2] - 244) > 12) n++; return n;")


def count_ov3d(d):
    return d.execute_script("const c = document.getElementById('ov3d'), g = c.getContext('2d');"
                            "const a = g.getImageData(0, 0, c.width, c.height).data; let n = 0;"
                            "for (let i = 3; i < a.length; i += 4) if (a[i]) n++; return n;")


def node_object(d, node_id):
    return d.execute_script(
        "const f = (n) => n.id === arguments[0] ? n : n.children.map(f).find((x) => x) || null;"
        "for (const r of window.ggrt.traces.a.json.roots) { const n = f(r); if (n) return n.hit ? n.hit.object : -1; }"
        "return -2;", node_id)


def cli_matched(where, *opts):
    out = subprocess.run([GGRT, "find", SCENE, "--where", where, "--format", "json", "--limit", "0"] + list(opts),
                         cwd=ROOT, stdout=subprocess.PIPE, text=True, check=True).stdout
    return json.loads(out)["matched"]


def linked(d):
    """Hover a node: its segment in 3D, its object in the image; click a
    segment: its node; j / k; arrows after a dropdown; the readout."""
    node = d.find_element(By.CSS_SELECTOR, "#tree-a details.node.kind-refract > summary")
    nid = int(node.find_element(By.XPATH, "..").get_attribute("data-id"))
    ActionChains(d).move_to_element(node).perform()
    obj = node_object(d, nid)
    ok = wait(d, "mask", lambda: attr(d, "objmask", "data-object") == str(obj) and
              int(attr(d, "objmask", "data-pixels") or 0) > 0, 30)
    hl = d.execute_script("return [window.ggrtView3d.hl, window.ggrtView3d.hlObject];")
    how = attr(d, "objmask", "data-how")
    got = int(attr(d, "objmask", "data-pixels") or 0)
    want = (cli_matched("some(kind == eye && object == %d)" % obj, "-d", "1", "-n", "1") if how == "seen first"
            else cli_matched("some(kind != shadow && object == %d)" % obj, "-n", "1"))
    check(ok and hl == [nid, obj] and got == want,
          "hovering refract #%d: its segment is drawn thick, object #%d outlined in the image "
          "(%d pixels, %s; ggrt find: %d)" % (nid, obj, got, how, want), "%s %s" % (hl, how))
    check("object #%d outlined" % obj in d.find_element(By.ID, "hover").text,
          "the readout names the node and its object", d.find_element(By.ID, "hover").text)
    # A click on a segment of the 3D view selects its node in the tree.
    ActionChains(d).move_to_element(d.find_element(By.ID, "pixel-title")).perform()
    seg = d.execute_script(
        "const v = window.ggrtView3d, c = document.getElementById('ov3d');"
        "for (const s of v.segs) { if (s.kind === 'shadow' || s.id === 0) continue;"
        " const x = (s.s[0][0] + s.s[1][0]) / 2, y = (s.s[0][1] + s.s[1][1]) / 2;"
        " if (x < 5 || y < 5 || x > c.clientWidth - 5 || y > c.clientHeight - 5) continue;"
        " const near = [[0, 0], [3, 3], [-3, 3], [3, -3], [-3, -3]].map(([a, b]) => v.pick(x + a, y + b));"
        " if (near.every((p) => p && p.id === s.id && p.side === 'a')) return [s.id, x, y, c.clientWidth, c.clientHeight]; }"
        "return null;")
    if check(seg is not None, "the 3D view has a segment to click", seg):
        sid, x, y, w, h = seg
        ActionChains(d).move_to_element_with_offset(d.find_element(By.ID, "ov3d"), int(x - w / 2),
                                                    int(y - h / 2)).click().perform()
        ok = wait(d, "select", lambda: d.execute_script("return document.body.dataset.selectedNode") == "a:%d" % sid, 5)
        el = d.find_element(By.CSS_SELECTOR, '#tree-a details.node[data-id="%d"]' % sid)
        check(ok and "selected" in el.get_attribute("class") and el.is_displayed(),
              "clicking ray #%d in the 3D view selects its node in the tree" % sid)
        # j: the next node of the tree.
        ids = [int(e.get_attribute("data-id")) for e in d.find_elements(By.CSS_SELECTOR, "#tree-a details.node")]
        nxt = ids[min(len(ids) - 1, ids.index(sid) + 1)]
        ActionChains(d).send_keys("j").perform()
        ok = wait(d, "j", lambda: d.execute_script("return document.body.dataset.selectedNode") == "a:%d" % nxt, 5)
        check(ok and d.execute_script("return window.ggrtView3d.hl") == nxt and
              d.find_element(By.ID, "hover").text.find("#%d " % nxt) >= 0,
              "j selects the next node (#%d): its segment, and the readout follows" % nxt,
              d.find_element(By.ID, "hover").text)
    # The overlay dropdown does not keep the arrows: they move the pixel.
    Select(d.find_element(By.ID, "overlay-select")).select_by_value("none")
    ActionChains(d).send_keys(Keys.ARROW_RIGHT).perform()
    ok = wait(d, "arrow", lambda: selected_pixel(d) == "%d,%d" % (PIXEL[0] + 1, PIXEL[1]), 5)
    hov = d.find_element(By.ID, "hover").text
    check(ok and hov.startswith("pixel %d,%d " % (PIXEL[0] + 1, PIXEL[1])),
          "after choosing an overlay, the right arrow moves the pixel and the readout follows", hov)
    ActionChains(d).send_keys(Keys.ARROW_LEFT).perform()
    wait(d, "arrow", lambda: selected_pixel(d) == "%d,%d" % PIXEL, 5)


def downloads(d, srv, folder):
    """The export buttons: what each file holds."""
    d.execute_cdp_cmd("Browser.setDownloadBehavior", {"behavior": "allow", "downloadPath": folder})
    tag = "%d-%d" % PIXEL
    files = {"json": "ggrt-trace-%s.json" % tag, "svg": "ggrt-rays-%s.svg" % tag, "obj": "ggrt-rays-%s.obj" % tag,
             "image": "ggrt-image.png", "overlay": "ggrt-find.png"}
    for k in files:
        d.find_element(By.CSS_SELECTOR, "#export [data-export=%s]" % k).click()
        time.sleep(0.2)
    got = {}
    for k, f in files.items():
        p = os.path.join(folder, f)
        wait(d, f, lambda p=p: os.path.exists(p) and os.path.getsize(p) > 0, 10)
        got[k] = open(p, "rb").read() if os.path.exists(p) else b""
    code, want = srv.get("/api/trace", x=PIXEL[0], y=PIXEL[1])
    check(got["json"] == want, "tree JSON: the bytes of /api/trace (%d)" % len(want))
    check(got["svg"].lstrip().startswith((b"<svg", b"<?xml")) and b"</svg>" in got["svg"], "rays SVG: an SVG")
    tree = json.loads(want)
    def rays(n):
        k = 1 + sum(1 for L in (n["hit"] or {}).get("lights", []) if L["verdict"] != "facing-away")
        return k + sum(rays(c) for c in n["children"])
    nrays = sum(rays(r) for r in tree["roots"])
    lines = [ln for ln in got["obj"].decode().splitlines() if ln.startswith("l ")]
    check(len(lines) == nrays and got["obj"].count(b"\nv ") == 2 * nrays,
          "rays OBJ: %d line segments, one a ray and shadow ray" % len(lines), "want %d" % nrays)
    check(got["image"][:8] == b"\x89PNG\r\n\x1a\n" and got["image"] == srv.get("/api/image", format="png")[1],
          "image PNG: /api/image's")
    check(got["overlay"][:8] == b"\x89PNG\r\n\x1a\n", "mask PNG: the find mask on screen")
    # The command line for what is on screen prints the same tree.
    cmd = shlex.split(d.find_element(By.ID, "cmd-trace").get_attribute("value"))
    out = subprocess.run([GGRT] + cmd[1:] + ["--format", "json"], cwd=ROOT, stdout=subprocess.PIPE).stdout
    check(cmd[:2] == ["ggrt", "trace"] and out == want, "the copied command (%s) prints the same JSON"
          % " ".join(cmd), out[:200])
    cmd = shlex.split(d.find_element(By.ID, "cmd-find").get_attribute("value"))
    out = subprocess.run([GGRT] + cmd[1:], cwd=ROOT, stdout=subprocess.PIPE, text=True).stdout
    m = re.search(r"(\d+) of \d+ pixels match", out)
    page = re.match(r"(\d+) pixels? match", d.find_element(By.ID, "find-result").text)
    check(m and page and m.group(1) == page.group(1), "the find command (%s) matches as many pixels as the page (%s)"
          % (" ".join(cmd), page.group(1) if page else "?"), out[:200])


def glass(d, want):
    srv = Server(SCENE)
    folder = tempfile.mkdtemp(prefix="ggrt-dl-")
    try:
        check(srv.url.startswith("http://127.0.0.1:"), "ggrt serve printed its URL", srv.url)
        t0 = time.time()
        console_errors(d)
        d.set_window_size(1500, 980)
        d.get(srv.url)
        ok = wait(d, "image", lambda: attr(d, "viewport", "data-image"))
        check(ok, "the image is shown (%.1f s after loading)" % (time.time() - t0),
              d.find_element(By.ID, "status-text").text)
        # Click 110,100: the tree shows the refraction into the glass and TIR inside it.
        click_pixel(d, *PIXEL)
        ok = wait(d, "tree", lambda: selected_pixel(d) == "%d,%d" % PIXEL)
        check(ok, "clicking pixel %d,%d selects it" % PIXEL, d.find_element(By.ID, "pixel-title").text)
        tir = d.find_elements(By.CSS_SELECTOR, "#tree-a .node.kind-tir")
        refr = d.find_elements(By.CSS_SELECTOR, "#tree-a .node.kind-refract")
        check(len(tir) > 0 and len(refr) > 0, "the tree shows refraction and a TIR node (%d tir, %d refract)" %
              (len(tir), len(refr)))
        check(tir and tir[0].find_element(By.CSS_SELECTOR, "summary .kind").text == "tir" and
              tir[0].is_displayed(), "the TIR node is visible and labelled tir")
        got = attr(d, "pixel-value", "data-rgb")
        check(got == want, "the pixel value equals ggrt render --pixel's: %s" % got, "page %r, CLI %r" % (got, want))
        head = d.find_element(By.CSS_SELECTOR, "#tree-a h3").get_attribute("textContent")
        check(head.endswith("colour " + want), "the traced colour in the tree equals it too", head)
        # Collapsing a node hides its children.
        root = d.find_element(By.CSS_SELECTOR, "#tree-a > details.node")
        root.find_element(By.TAG_NAME, "summary").click()
        # A closed <details> keeps its content's boxes (content-visibility:
        # hidden): checkVisibility says whether it is rendered.
        hidden = d.execute_script("return [arguments[0].checkVisibility(), arguments[1].open];", tir[0], root)
        check(hidden == [False, False], "a node collapses (the TIR node is hidden)", hidden)
        root.find_element(By.TAG_NAME, "summary").click()
        # Hover shows coordinates and value.
        click_pixel(d, 200, 150, move_only=True)
        click_pixel(d, *PIXEL, move_only=True)
        hov = d.find_element(By.ID, "hover").get_attribute("textContent")
        check(hov.startswith("pixel %d,%d  %s" % (PIXEL + (want,))), "hover shows the coordinates and value", hov)
        # Keyboard: the right arrow moves to the next pixel; the URL keeps it.
        d.find_element(By.ID, "image").send_keys(Keys.ARROW_RIGHT)
        ok = wait(d, "arrow", lambda: selected_pixel(d) == "111,100")
        check(ok and ("px=111%2C100" in d.current_url or "px=111,100" in d.current_url),
              "the right arrow selects 111,100 and the URL says so", d.current_url)
        d.find_element(By.ID, "image").send_keys(Keys.ARROW_LEFT)
        wait(d, "arrow", lambda: selected_pixel(d) == "%d,%d" % PIXEL)
        # The 3D view: WebGL shades the scene, the rays are drawn over it.
        wait(d, "3D", lambda: attr(d, "box3d", "data-triangles"), 10)
        shaded, drawn = count_gl(d), count_ov3d(d)
        check(shaded > 5000 and drawn > 300, "the 3D view shades the scene (%d pixels, %s triangles) and draws "
              "the rays, lights and camera over it (%d pixels)" % (shaded, attr(d, "box3d", "data-triangles"), drawn),
              d.find_element(By.ID, "note3d").text)
        linked(d)
        # A heatmap overlay.
        Select(d.find_element(By.ID, "overlay-select")).select_by_value("rays")
        ok = wait(d, "heatmap", lambda: attr(d, "overlay", "data-kind") == "rays")
        px = overlay_alpha(d, *PIXEL)
        check(ok and px[3] == 255 and "rays per pixel" in d.find_element(By.ID, "legend-text").text,
              "the rays heatmap overlays the image, with its legend", px)
        check("ov=rays" in d.current_url, "the URL keeps the overlay", d.current_url)
        # A find predicate typed into the box.
        box = d.find_element(By.ID, "find-input")
        box.clear()
        box.send_keys("some(kind ==", Keys.ENTER)
        ok = wait(d, "bad", lambda: "bad" in box.get_attribute("class"))
        res = d.find_element(By.ID, "find-result").text
        check(ok and re.match(r"1:\d+: ", res) and "ov=find" not in d.current_url,
              "a predicate with a syntax error is refused, saying where (%s)" % res, res)
        box.clear()
        box.send_keys("some(kind == tir)", Keys.ENTER)
        ok = wait(d, "find", lambda: attr(d, "overlay", "data-kind") == "find")
        res = d.find_element(By.ID, "find-result").text
        m = re.match(r"(\d+) pixels? match", res)
        check(ok and m and int(m.group(1)) > 0 and "bad" not in box.get_attribute("class"),
              "find some(kind == tir): matches appear (%s)" % res, res)
        check(overlay_alpha(d, *PIXEL)[3] == 255, "pixel %d,%d is in the find mask" % PIXEL)
        check(overlay_alpha(d, 5, 5)[3] == 0, "a pixel of the sky is not")
        downloads(d, srv, folder)
        # The 3D tab: the view moves in, larger.
        d.find_element(By.CSS_SELECTOR, "#tabs [data-tab=rays3d]").click()
        ok = wait(d, "rays3d", lambda: d.execute_script(TAB_READY["rays3d"]), 5)
        h = d.find_element(By.ID, "stack3d").size["height"]
        check(ok and count_gl(d) > 5000, "the rays 3D tab shows the view larger (%d px high)" % h)
        # Drag to turn the 3D camera: the address keeps it.
        ov = d.find_element(By.ID, "ov3d")
        ActionChains(d).move_to_element_with_offset(ov, 0, 60).click_and_hold().move_by_offset(60, 0) \
            .move_by_offset(40, 10).release().perform()
        cam = urllib.parse.parse_qs(urllib.parse.urlparse(d.current_url).fragment).get("cam", [""])[0]
        check(cam.count(",") == 5, "turning the 3D view puts its camera in the address (cam=%s)" % cam)
        d.find_element(By.CSS_SELECTOR, "#tabs [data-tab=views]").click()
        ok = wait(d, "svg", lambda: d.execute_script(TAB_READY["views"]))
        check(ok, "the top and side views load")
        # The ledger: the pixel's colour term by term, adding up to it.
        d.find_element(By.CSS_SELECTOR, "#tabs [data-tab=ledger]").click()
        ok = wait(d, "ledger", lambda: d.find_elements(By.CSS_SELECTOR, "#ledger p[data-holds]"))
        rows = d.find_elements(By.CSS_SELECTOR, "#ledger tr")
        check(ok and len(rows) > 1 and ok[0].get_attribute("data-holds") == "1",
              "the ledger lists %d terms that add up to the pixel" % (len(rows) - 1),
              ok[0].text if ok else "no ledger")
        # The diagnostics: every invariant of ggrt check at this pixel.
        d.find_element(By.CSS_SELECTOR, "#tabs [data-tab=diag]").click()
        ok = wait(d, "diag", lambda: d.execute_script(TAB_READY["diag"]))
        check(ok and "invariant" in d.find_element(By.ID, "diag").text,
              "the diagnostics list the 7 invariants at the pixel", d.find_element(By.ID, "diag").text[:200])
        d.find_element(By.CSS_SELECTOR, "#tabs [data-tab=tree]").click()
        # The URL restores the view after a reload, the 3D camera too.
        d.get(d.current_url)
        ok = wait(d, "reload", lambda: selected_pixel(d) == "%d,%d" % PIXEL
                  and attr(d, "overlay", "data-kind") in ("rays", "find"))
        back = d.execute_script("const v = window.ggrtView3d; return [v.yaw, v.pitch, v.dist]"
                                ".concat(v.target).map((x) => Number(x.toPrecision(6))).join(',');")
        check(ok and back == cam, "reloading the URL restores the pixel, the overlay and the 3D camera (%s)" % back,
              d.current_url)
        if SHOT:
            os.makedirs(os.path.dirname(os.path.abspath(SHOT)), exist_ok=True)
            Select(d.find_element(By.ID, "overlay-select")).select_by_value("none")
            wait(d, "none", lambda: attr(d, "overlay", "data-kind") == "none")
            d.execute_script("window.scrollTo(0, 0); document.activeElement.blur();")
            d.save_screenshot(SHOT)
            print("screenshot: " + SHOT)
        # Diff mode against depth 2.
        d.find_element(By.CSS_SELECTOR, "#diff-panel summary").click()
        Select(d.find_element(By.ID, "opt-b-depth")).select_by_value("2")
        d.find_element(By.ID, "render-b").click()
        ok = wait(d, "diff", lambda: attr(d, "overlay", "data-kind") == "diff"
                  and selected_pixel(d) == "%d,%d" % PIXEL)
        res = d.find_element(By.ID, "diff-result").text
        trees = d.find_elements(By.CSS_SELECTOR, "#tree-b .node")
        check(ok and re.match(r"\d+ of 120000 pixels differ in value, \d+ in their ray trees", res) and trees,
              "diff mode: the divergence map and both trees (%s)" % res[:60], res)
        ok = wait(d, "divergence", lambda: d.find_element(By.ID, "divergence").is_displayed())
        div = d.find_element(By.ID, "divergence").text
        marked = d.find_elements(By.CSS_SELECTOR, "#tree-a .node.diverge, #tree-b .node.diverge")
        check(ok and div.startswith("first divergence: ray #") and marked,
              "diff mode: the first divergent ray is named and marked (%s)" % div, div)
        errors = console_errors(d)
        check(not errors, "no console errors", "\n".join(errors))
        copied_options(d, srv)
    finally:
        d.get("about:blank")
        rc, err = srv.stop()
        check(rc == 0, "ggrt serve stopped cleanly", err)
        shutil.rmtree(folder, ignore_errors=True)


# Option texts whose flags differ from their words (the SPD rule alone,
# corners alone, spd over a depth), and every other setting a page can
# change: all of ggRenderOptionsParse's words but size, threads and crop.
COPIED_OPTS = ["spd-rules", "spd-rules corners", "corners depth=3", "depth=2 spd", "force-effects phong=fast",
               "ray-budget=3 samples=2",
               "offset=1e-05 sphere=textbook refract=exact fresnel=schlick texture=nearest wavelengths=one",
               "cutoff=0.01 implicit-tol=1e-06 gradient=1e-05 intersect=float shadows=opaque offset=fixed"]


def copied_options(d, srv):
    """For each text of side a: the copied ggrt trace prints /api/trace's JSON for it, and the
    options panel's render keeps it (the same options as /api/render reads them)."""
    for text in COPIED_OPTS:
        d.get("about:blank")
        d.get(srv.url + "#" + urllib.parse.urlencode({"px": "%d,%d" % PIXEL, "a": text}))
        ok = wait(d, "tree", lambda: d.find_elements(By.CSS_SELECTOR, "#tree-a details.node") and
                  d.find_element(By.ID, "cmd-trace").get_attribute("value"), 30)
        cmd = shlex.split(d.find_element(By.ID, "cmd-trace").get_attribute("value")) if ok else []
        out = subprocess.run([GGRT] + cmd[1:] + ["--format", "json"], cwd=ROOT, stdout=subprocess.PIPE).stdout \
            if cmd[:2] == ["ggrt", "trace"] else b""
        code, want = srv.get("/api/trace", x=PIXEL[0], y=PIXEL[1], opts=text)
        check(code == 200 and out == want, "options '%s': the copied command (%s) prints /api/trace's JSON"
              % (text, " ".join(cmd)), out[:200])
        # The panel shows the text, and its render button keeps it.
        d.find_element(By.ID, "render-a").click()
        time.sleep(0.3)
        again = urllib.parse.parse_qs(urllib.parse.urlparse(d.current_url).fragment).get("a", [""])[0]
        canon = [json.loads(srv.get("/api/render", opts=t)[1] or b"{}").get("options") for t in (text, again)]
        check(canon[0] and canon[0] == canon[1], "options '%s': the panel's render keeps them ('%s')" % (text, again),
              canon)


# ---- light-path expressions: the path box, the tree filter, the share heatmap ----

LPE = "C<TS>.*"


def on_path_ids(tree, paths):
    """The rays on the matching paths: each term's ray and its ancestors."""
    parent = {}

    def walk(n, up):
        parent[n["id"]] = up
        for k in n["children"]:
            walk(k, n["id"])
    for r in tree["roots"]:
        walk(r, -1)
    on = set()
    for t in paths["terms"]:
        i = t["node"]
        while i >= 0:
            on.add(i)
            i = parent[i]
    return on, set(parent)


def paths(d, folder):
    """Type a path (keys not captured by the page), a malformed one's
    column, the share heatmap against ggrt find --path (count and every
    share), the tree filtered (hidden, then dimmed) against ggrt trace
    --path, the URL keeping the path."""
    srv = Server(SCENE)
    try:
        console_errors(d)
        d.set_window_size(1500, 980)
        d.get(srv.url + "#px=%d,%d" % PIXEL)
        wait(d, "ready", lambda: attr(d, "viewport", "data-image") and selected_pixel(d))
        box = d.find_element(By.ID, "path-input")
        box.send_keys("C<X>")
        ok = wait(d, "bad", lambda: "bad" in (box.get_attribute("class") or ""), 10)
        res = d.find_element(By.ID, "path-result").text
        check(ok and res.startswith("1:3: "), "a malformed path is marked with its column (%s)" % res, res)
        box.clear()
        # Letters that are shortcuts elsewhere (o: overlay, e/c: expand, j/k, f, p) only type.
        typed = "C<TS>[object == 1 || object != 1].*"
        box.send_keys(typed)
        time.sleep(0.4)
        st = d.execute_script("return [window.ggrt.state.overlay, document.activeElement.id];")
        check(box.get_attribute("value") == typed and st == ["none", "path-input"],
              "typing a path is not captured by the page's keys", "%r %r" % (box.get_attribute("value"), st))
        box.clear()
        box.send_keys(LPE + Keys.ENTER)
        ok = wait(d, "heatmap", lambda: attr(d, "overlay", "data-kind") == "path" and
                  attr(d, "path-result", "data-matched"), 60)
        ref = json.loads(subprocess.run([GGRT, "find", SCENE, "--path", LPE, "--format", "json", "-q", "--limit",
                                         "120000"], cwd=ROOT, stdout=subprocess.PIPE, text=True, check=True).stdout)
        got = int(attr(d, "path-result", "data-matched") or -1)
        check(ok and got == ref["matched"] > 0, "the path box finds %d pixels, as ggrt find --path (%d)"
              % (got, ref["matched"]), d.find_element(By.ID, "path-result").text)
        page = d.execute_script("const o = window.ggrt.overlay(), out = [];"
                                "o.values.forEach((v, i) => { if (v) out.push([i, v]); }); return out;")
        want = {m["pixel"][1] * 400 + m["pixel"][0]: struct.unpack("<f", struct.pack("<f", m["share"]))[0]
                for m in ref["matches"]}
        pg = {i: struct.unpack("<f", struct.pack("<f", v))[0] for i, v in page}
        diff = [i for i in set(pg) | set(want) if pg.get(i, 0) != want.get(i, 0)]
        check(len(want) == ref["matched"] and not diff,
              "the heatmap's share of every pixel equals ggrt find --path's (%d shares)" % len(want),
              "%d differ, e.g. %s" % (len(diff), [(i, pg.get(i), want.get(i)) for i in diff[:5]]))
        mx = max(want.values())
        top = max(want, key=lambda i: want[i])
        legend = d.find_element(By.ID, "legend-text").text
        check(int(attr(d, "legend", "height") or 0) > 0 and "share" in legend and
              overlay_alpha(d, top % 400, top // 400)[3] > 0,
              "the heatmap is drawn with its legend (largest share %.4f)" % mx, legend)
        # The tree: only the rays of the matching paths.
        ok = wait(d, "filter", lambda: d.find_elements(By.ID, "path-summary"), 30)
        tr = json.loads(subprocess.run([GGRT, "trace", SCENE, "--pixel", "%d,%d" % PIXEL, "--format", "json"],
                                       cwd=ROOT, stdout=subprocess.PIPE, text=True, check=True).stdout)
        pj = json.loads(subprocess.run([GGRT, "trace", SCENE, "--pixel", "%d,%d" % PIXEL, "--path", LPE, "--format",
                                        "json"], cwd=ROOT, stdout=subprocess.PIPE, text=True, check=True).stdout)
        on, every = on_path_ids(tr, pj)
        summ = d.find_element(By.ID, "path-summary")
        check(ok and summ.get_attribute("data-matched") == str(pj["matched"]) and
              float(summ.get_attribute("data-share")) == pj["share"],
              "the tree's path summary equals ggrt trace --path's (%d of %d paths, share %.4f)"
              % (pj["matched"], pj["paths"], pj["share"]), summ.text)
        vis = d.execute_script("const out = {};"
                               "for (const n of document.querySelectorAll('#tree-a details.node'))"
                               " out[n.dataset.id] = n.checkVisibility(); return out;")
        shown = {int(k) for k, v in vis.items() if v}
        check(shown == on and every - on, "the tree shows only the rays on matching paths (%s of %d)"
              % (sorted(on), len(every)), "shown %s, want %s" % (sorted(shown), sorted(on)))
        d.find_element(By.ID, "path-dim").click()
        vis = d.execute_script("const out = {};"
                               "for (const n of document.querySelectorAll('#tree-a details.node'))"
                               " out[n.dataset.id] = [n.checkVisibility(),"
                               " getComputedStyle(n.querySelector(':scope > summary')).opacity]; return out;")
        dimmed = {int(k) for k, v in vis.items() if v[0] and float(v[1]) < 1}
        check(all(v[0] for v in vis.values()) and dimmed == every - on,
              "dim the other paths: every ray shown, the others greyed (%s)" % sorted(dimmed), vis)
        # The copied commands print what is on screen.
        runs = []
        for box in ("cmd-trace", "cmd-find"):
            cmd = shlex.split(d.find_element(By.ID, box).get_attribute("value"))
            runs.append(subprocess.run([GGRT] + cmd[1:] + (["--format", "json"] if box == "cmd-trace" else []),
                                       cwd=ROOT, stdout=subprocess.PIPE, text=True).stdout if cmd[:1] == ["ggrt"]
                        else "")
        check(runs[0] and json.loads(runs[0]) == pj and
              runs[1].startswith("%s: %d of 120000 pixels match --path %s" % (SCENE, ref["matched"], LPE)),
              "the copied ggrt trace --path and ggrt find --path commands print what the page shows",
              "\n".join(r[:200] for r in runs))
        url = d.current_url
        check("path=" + urllib.parse.quote(LPE, safe="") in url.replace("*", "%2A") and "pdim=1" in url,
              "the URL keeps the path and the dimming", url)
        if folder:
            os.makedirs(folder, exist_ok=True)
            d.execute_script("window.scrollTo(0, 0); document.activeElement.blur();")
            time.sleep(0.3)
            d.save_screenshot(os.path.join(folder, "serve-paths-glass.png"))
            print("docs screenshot: " + os.path.join(folder, "serve-paths-glass.png"))
        d.get("about:blank")
        d.get(url)
        ok = wait(d, "reload", lambda: attr(d, "overlay", "data-kind") == "path" and
                  d.find_elements(By.ID, "path-summary"), 60)
        check(ok and d.find_element(By.ID, "path-input").get_attribute("value") == LPE and
              d.find_element(By.ID, "path-dim").is_selected(),
              "a reload from the URL brings back the path, its heatmap and filter")
        errors = console_errors(d)
        check(not errors, "paths: no console errors", "\n".join(errors))
    finally:
        d.get("about:blank")
        rc, err = srv.stop()
        check(rc == 0, "ggrt serve stopped cleanly", err)


# ---- the layout at 1280 and 1920 px ----

INSIDE = ("const W = document.documentElement.clientWidth, out = [];"
          "for (const id of ['right', 'tree-a', 'tree-b']) { const e = document.getElementById(id);"
          " if (!e || e.hidden || e.offsetParent === null) continue; const r = e.getBoundingClientRect();"
          " if (r.left < -0.5 || r.right > W + 0.5 || r.width < 200) out.push(id + ' ' + Math.round(r.left) + '..' +"
          " Math.round(r.right) + ' of ' + W); }"
          "if (document.documentElement.scrollWidth > W + 1) out.push('the page scrolls sideways: ' +"
          " document.documentElement.scrollWidth + ' > ' + W); return out;")


def layout(d):
    srv = Server(SCENE)
    try:
        for width in (1280, 1920):
            d.set_window_size(width, 1000)
            d.get(srv.url + "#px=%d,%d" % PIXEL)
            wait(d, "image", lambda: attr(d, "viewport", "data-image") and selected_pixel(d))
            for mode, h in (("normal", "px=110,100"), ("diff", "px=110,100&diff=1&b=depth%3D2"),
                            ("zoom4", "px=110,100&zoom=4"), ("diff-zoom4", "px=110,100&zoom=4&diff=1&b=depth%3D2")):
                d.execute_script("location.hash = arguments[0]", h)
                diff = "diff" in mode
                ok = wait(d, mode, lambda: selected_pixel(d) == "110,100" and
                          (not diff or d.find_elements(By.CSS_SELECTOR, "#tree-b details.node")) and
                          d.find_element(By.ID, "image").size["width"] >= (1600 if "zoom4" in mode else 0), 30)
                time.sleep(0.2)
                bad = d.execute_script(INSIDE)
                shot = os.path.join(OUT, "layout-%d-%s.png" % (width, mode))
                d.save_screenshot(shot)
                check(ok and not bad, "%d px, %s: the tree panel lies inside the window (%s)"
                      % (width, mode, shot), "\n".join(bad) if bad else "the view did not come")
        errors = console_errors(d)
        check(not errors, "layout: no console errors", "\n".join(errors))
    finally:
        d.get("about:blank")
        d.set_window_size(1500, 980)
        srv.stop()


# ---- Back and Forward ----

# What the page shows of the selected pixel: its number, title, value, ray
# counts, the tree's text, and the tab shown.
SHOWN = ("const q = (s) => document.querySelector(s); if (!q('#pixel-head')) return [location.href];"
         "return [q('#pixel-head').dataset.pixel || '', q('#pixel-title').textContent,"
         " q('#pixel-value').textContent, q('#pixel-rays').textContent, q('#tree-a').textContent,"
         " q('#tabs button.active').dataset.tab];")
CAM = ("const v = window.ggrtView3d; return [v.yaw, v.pitch, v.dist].concat(v.target)"
       ".map((x) => Number(x.toPrecision(6))).join(',');")


def url_cam(d):
    return urllib.parse.parse_qs(urllib.parse.urlparse(d.current_url).fragment).get("cam", [""])[0]


def history(d):
    """Back and Forward walk through the pixels and tabs the user chose: each
    is a history entry (pushState), restored whole from the address (the
    tree without asking the server again, no banner, no "tracing"); turning
    the 3D view and zooming replace the entry instead of adding one."""
    srv = Server(SCENE, "-s", "64x48")
    A, B, C = (17, 16), (40, 30), (41, 30)  # glass with TIR, the floor, its neighbour (an arrow key)
    name = lambda p: "%d,%d" % p  # noqa: E731
    # A tab of its own: Chromium keeps at most 50 entries a tab, which the
    # steps before may have filled, and history.length would stay at 50.
    first = d.current_window_handle
    d.switch_to.new_window("tab")
    try:
        d.get(srv.url)
        wait(d, "image", lambda: attr(d, "viewport", "data-image"), 60)
        wait(d, "3d", lambda: attr(d, "box3d", "data-triangles"), 10)
        console_errors(d)
        length = lambda: d.execute_script("return history.length")  # noqa: E731
        shown = lambda: d.execute_script(SHOWN)  # noqa: E731

        def settled(p):
            return wait(d, name(p), lambda: (lambda s: s[0] == name(p) and s[1] == "pixel " + name(p) and
                                             "#" in s[4])(shown()), 30)

        h0 = length()
        seen = {}
        for p, how in ((A, "click"), (B, "click"), (C, "arrow")):
            if how == "click":
                click_pixel(d, *p)
            else:
                d.find_element(By.ID, "image").send_keys(Keys.ARROW_RIGHT)
            settled(p)
            seen[p] = shown()
        check(len({tuple(v) for v in seen.values()}) == 3 and all(seen[p][0] == name(p) for p in seen),
              "pixels %s, %s (clicked) and %s (arrow key) are shown in turn" % (name(A), name(B), name(C)),
              [v[:2] for v in seen.values()])
        check(length() == h0 + 3, "each pixel is a history entry (history.length %d -> %d)" % (h0, length()))
        # From here on: what the page asks the server, what the title and the banner say.
        d.execute_script(
            "window.__calls = []; window.__said = [];"
            "const real = window.fetch; window.fetch = function (u, o) { window.__calls.push(String(u));"
            " return real(u, o); };"
            "const e = document.getElementById('error'), t = document.getElementById('pixel-title');"
            "new MutationObserver(() => window.__said.push(t.textContent + (e.hidden ? '' : ' | banner: ' +"
            " e.textContent))).observe(document.body, { subtree: true, childList: true, characterData: true,"
            " attributes: true, attributeFilter: ['hidden'] });"
            "window.__shows = 0; window.__events = [];"
            "new MutationObserver(() => window.__shows++).observe(document.getElementById('pixel-head'),"
            " { attributes: true, attributeFilter: ['data-shown-at'] });"
            "for (const k of ['popstate', 'hashchange']) window.addEventListener(k, () => window.__events.push(k));")
        d.back()
        ok_b = wait(d, "back to B", lambda: shown() == seen[B], 15)
        d.back()
        ok_a = wait(d, "back to A", lambda: shown() == seen[A], 15)
        now = shown()
        check(ok_b and ok_a, "Back twice shows %s again: its readout and its tree (%s)" % (name(A), now[:3]),
              "want %r\ngot  %r\nurl %s" % (seen[A][:4], now[:4], d.current_url))
        if not (ok_b and ok_a):
            return  # the page was left: nothing more to see
        tree = json.loads(srv.get("/api/trace", x=A[0], y=A[1])[1])

        def count(n):
            return 1 + sum(count(k) for k in n["children"])
        colour = " ".join("%.9g" % c for c in tree["color"])
        want = "%d rays, colour %s" % (sum(count(r) for r in tree["roots"]), colour)
        head = d.execute_script("const h = document.querySelector('#tree-a h3'); return h ? h.textContent : ''")
        check(head == want and "px=%d%%2C%d" % A in d.current_url,
              "the tree shown is %s's as /api/trace gives it (%s), the address says px=%s" % (name(A), head, name(A)),
              "want %r, got %r; %s" % (want, head, d.current_url))
        calls, said, shows, events = d.execute_script(
            "return [window.__calls, window.__said, window.__shows, window.__events]")
        check(calls == [] and not [s for s in said if "tracing" in s or "banner" in s] and not page_error(d),
              "restoring pixels already fetched asks the server nothing and shows no banner (%d requests)"
              % len(calls), "requests %r\nsaid %r" % (calls, sorted(set(said))))
        check(shows == 2, "each step back shows its pixel once (%d times for 2 steps; events %s)"
              % (shows, " ".join(events)))
        d.forward()
        ok = wait(d, "forward to B", lambda: shown() == seen[B], 15)
        check(ok and length() == h0 + 3, "Forward shows %s again, history.length unchanged (%d)" % (name(B), length()),
              shown()[:3])
        # A tab is an entry too.
        d.find_element(By.CSS_SELECTOR, "#tabs [data-tab=ledger]").click()
        wait(d, "ledger", lambda: d.find_elements(By.CSS_SELECTOR, "#ledger p[data-holds]"), 15)
        d.back()
        ok = wait(d, "tree tab", lambda: shown() == seen[B] and d.find_element(By.ID, "tab-ledger").get_attribute(
            "hidden") is not None, 15)
        d.forward()
        ok = ok and wait(d, "ledger tab", lambda: shown()[5] == "ledger" and shown()[0] == name(B) and
                         d.find_element(By.ID, "tab-ledger").is_displayed(), 15)
        check(ok, "a tab is an entry: Back shows %s's tree again, Forward its ledger" % name(B), shown()[5])
        # Turning and panning the 3D view, zooming the image: the entry is replaced.
        n = length()
        ov = d.find_element(By.ID, "ov3d")
        for dx, shift in ((60, False), (-25, False), (30, True)):
            a = ActionChains(d).move_to_element_with_offset(ov, 0, 40)
            if shift:
                a = a.key_down(Keys.SHIFT)
            a = a.click_and_hold().move_by_offset(dx, 0).move_by_offset(dx // 2, 10).release()
            (a.key_up(Keys.SHIFT) if shift else a).perform()
        Select(d.find_element(By.ID, "zoom")).select_by_value("2")
        cam = url_cam(d)
        check(length() == n and cam.count(",") == 5 and "zoom=2" in d.current_url,
              "turning the 3D view and zooming add no entry (history.length %d -> %d, cam=%s)" % (n, length(), cam))
        d.back()
        ok = wait(d, "tree tab", lambda: shown()[5] == "tree" and shown()[0] == name(B), 15)
        follows = d.execute_script("return !window.ggrtView3d.userMoved") and not url_cam(d)
        d.forward()
        ok = ok and wait(d, "ledger tab", lambda: shown()[5] == "ledger" and d.execute_script(CAM) == cam, 15)
        check(ok and follows, "Back: the 3D view frames the rays as it did; Forward: the camera turned by hand "
              "(%s)" % d.execute_script(CAM), "cam %s, follows %s" % (cam, follows))
        # Back to the page as it was loaded: no pixel selected, nothing of the last one left.
        for _ in range(3):
            d.back()
        ok = wait(d, "no pixel", lambda: shown()[:2] == ["", "no pixel selected"] and not shown()[4], 15)
        check(ok and length() == h0 + 3 and "px=" not in d.current_url,
              "Back to the page as loaded: no pixel selected, no tree left", shown()[:5])
        errors = console_errors(d)
        check(not errors and not page_error(d), "history: no console errors, no banner",
              "\n".join(errors) + page_error(d))
    finally:
        d.close()
        d.switch_to.window(first)
        srv.stop()


# ---- the screenshots of docs/serve.md ----

def docs_shots(d, folder):
    os.makedirs(folder, exist_ok=True)
    for scene, px, kind, name in (("examples/scenes/glass.nff", (110, 100), "tir", "serve-3d-glass.png"),
                                  ("examples/scenes/knot.nff", (160, 130), "eye", "serve-3d-knot.png")):
        srv = Server(scene)
        try:
            d.set_window_size(1600, 940)
            d.get(srv.url + "#px=%d,%d" % px)
            wait(d, "ready", lambda: attr(d, "viewport", "data-image") and selected_pixel(d) and
                 attr(d, "box3d", "data-triangles"))
            node = d.find_element(By.CSS_SELECTOR, "#tree-a details.node.kind-%s > summary" % kind)
            ActionChains(d).move_to_element(node).perform()
            wait(d, "mask", lambda: int(attr(d, "objmask", "data-pixels") or 0) > 0, 30)
            time.sleep(0.3)
            d.save_screenshot(os.path.join(folder, name))
            print("docs screenshot: " + os.path.join(folder, name))
        finally:
            d.get("about:blank")
            srv.stop()


# ---- textures in the 3D view ----

TEX_SCENE = "tests/data/textured.nff"  # every kind of shape, each with a texture
TEX_SIZE = (160, 120)


def gl_colours(d, points):
    """For each point of the scene, the 3D canvas's colours in the 3 x 3
    canvas pixels around where it projects (the view's own matrix), or
    None off the canvas."""
    return d.execute_script(
        "const v = window.ggrtView3d, s = document.getElementById('gl3d');"
        "const c = document.createElement('canvas'); c.width = s.width; c.height = s.height;"
        "const g = c.getContext('2d'); g.drawImage(s, 0, 0);"
        "const a = g.getImageData(0, 0, c.width, c.height).data, m = v.mvp;"
        "return arguments[0].map((p) => {"
        " const q = [0, 1, 2, 3].map((i) => m[i] * p[0] + m[4 + i] * p[1] + m[8 + i] * p[2] + m[12 + i]);"
        " const x = Math.floor((q[0] / q[3] * 0.5 + 0.5) * c.width), y = Math.floor((0.5 - q[1] / q[3] * 0.5) * c.height);"
        " if (!(x >= 1 && y >= 1 && x < c.width - 1 && y < c.height - 1)) return null;"
        " const out = []; for (let j = -1; j <= 1; j++) for (let i = -1; i <= 1; i++) {"
        "  const k = 4 * ((y + j) * c.width + x + i); out.push([a[k], a[k + 1], a[k + 2]]); }"
        " return out; });", points)


def srgb(c):
    c = min(1.0, max(0.0, c))
    return 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055


def textures(d):
    """tests/data/textured.nff (a sphere, cone, rectangles, triangle, pp
    fan, concave polygon and meshes, each textured, over a checker), the
    3D view through the scene's camera: where the eye ray of every 4th
    pixel meets a textured surface, the canvas there (the best of the 3 x 3
    pixels around the hit point's projection) is the colour the view
    should give it: the ray tree's surface colour (the texture at the
    renderer's (u, v) times the material's), sRGB-encoded, times the view's
    Lambert term at the hit's normal. Each textured object must match at
    most pixels (the view's triangles stand for curved surfaces, so not
    all), and each flat one must not be one colour. On the page before
    textures (flat colours) every object fails. Implicit surfaces are drawn
    as their boxes and are left out."""
    srv = Server(TEX_SCENE, "-s", "%dx%d" % TEX_SIZE, "-d", "1")
    try:
        console_errors(d)
        d.get(srv.url + "#tab=rays3d")
        wait(d, "3d", lambda: attr(d, "box3d", "data-triangles") or page_error(d), 30)
        loaded = wait(d, "textures", lambda: attr(d, "box3d", "data-textures"), 20)
        scene = json.loads(srv.get("/api/scene")[1])
        info = json.loads(srv.get("/api/info")[1])
        images = len(set(m["texture"] for m in scene["materials"] if "texture" in m))
        check(loaded == str(images), "textures: the 3D view has the %d textures the materials use (%s)"
              % (images, loaded), d.find_element(By.ID, "note3d").text)
        d.find_element(By.CSS_SELECTOR, "#box3d [data-view=camera]").click()
        time.sleep(0.3)
        cam = info["camera"]
        l1, l2 = view_lights(cam)
        hits = []
        for y in range(2, TEX_SIZE[1], 4):
            for x in range(2, TEX_SIZE[0], 4):
                st, b = srv.get("/api/trace", x=x, y=y, opts="depth=1", sample=0)
                h = json.loads(b)["roots"][0].get("hit") if st == 200 else None
                sh = h and scene["shapes"][h["object"]]
                if not h or "texture" not in scene["materials"][h["material"]] or sh["kind"] == "implicit":
                    continue
                n = h["ns"]
                lam = 0.3 + 0.55 * abs(sum(a * b for a, b in zip(n, l1))) + 0.25 * abs(sum(a * b for a, b in zip(n, l2)))
                want = [min(255.0, 255 * srgb(c) * lam) for c in h["surface"]]
                hits.append((h["object"], sh["kind"], h["point"], want))
        cols = gl_colours(d, [p for _, _, p, _ in hits])
        by = {}
        for (obj, kind, _, want), near in zip(hits, cols):
            if near is None:
                continue
            err = min(max(abs(a - b) for a, b in zip(want, g)) for g in near)
            by.setdefault((obj, kind), []).append((err, tuple(near[4])))
        kinds = set()
        for (obj, kind), l in sorted(by.items()):
            errs = sorted(e for e, _ in l)
            within = sum(1 for e in errs if e <= 24) / len(errs)
            flat = kind in ("rect", "triangle", "polygon")
            colours = len(set(c for _, c in l))
            good = len(l) >= 5 and errs[len(errs) // 2] <= 8 and within >= 0.85 and (not flat or colours >= 5)
            kinds.add(kind)
            check(good, "textures: object %d (%s, %s): %d of %d pixels within 24 of the texture's colour "
                  "there, median off by %d%s" % (obj, kind, scene["materials"][scene["shapes"][obj]["material"]]
                                                 .get("texture"), round(within * len(l)), len(l),
                                                 errs[len(errs) // 2],
                                                 ", %d colours" % colours if flat else ""),
                  "off by %s" % " ".join("%.0f" % e for e in errs[-20:]))
        check(kinds == {"sphere", "cone", "rect", "triangle", "polygon", "mesh"},
              "textures: every kind of shape is checked (%s)" % " ".join(sorted(kinds)))
        if SHOT:
            d.find_element(By.ID, "gl3d").screenshot(os.path.join(os.path.dirname(os.path.abspath(SHOT)),
                                                                  "textures-3d.png"))
        # The options' texture knob picks the filter, as in the render of
        # those options: nearest for these bilinear textures.
        tn = "const v = window.ggrtView3d, gl = document.getElementById('gl3d').getContext('webgl'); v.draw();" \
             " return gl.getUniform(v.texProg, gl.getUniformLocation(v.texProg, 'tn'));"
        before = d.execute_script(tn)
        d.get(srv.url + "#tab=rays3d&a=texture%3Dnearest")
        wait(d, "textures", lambda: attr(d, "box3d", "data-textures"), 20)
        check(before == 0 and d.execute_script(tn) == 1,
              "textures: the options' texture=nearest samples the bilinear textures nearest")
        check(not console_errors(d), "textures: no console error", console_errors(d))
    finally:
        d.get("about:blank")
        srv.stop()


IMP_SCENE = "examples/scenes/torus.nff"
IMP_SIZE = (160, 120)


def implicit(d):
    """examples/scenes/torus.nff in the 3D view through the scene's
    camera: the torus is drawn as its surface. Where the eye ray of every
    4th pixel meets the torus, the canvas there (the best of the 3 x 3
    pixels around the hit point's projection) is the view's colour of its
    material under the Lambert term at the renderer's normal; where it
    meets the floor through the hole or around the ring inside the
    torus's box, the floor's (its checker at the hit, as the textures step
    computes it) -- on the page that drew the box, a translucent box
    covered both, and every torus pixel showed the floor through it."""
    srv = Server(IMP_SCENE, "-s", "%dx%d" % IMP_SIZE, "-d", "1")
    try:
        console_errors(d)
        d.get(srv.url + "#tab=rays3d")
        wait(d, "3d", lambda: attr(d, "box3d", "data-triangles") or page_error(d), 30)
        wait(d, "textures", lambda: attr(d, "box3d", "data-textures"), 20)
        scene = json.loads(srv.get("/api/scene")[1])
        info = json.loads(srv.get("/api/info")[1])
        d.find_element(By.CSS_SELECTOR, "#box3d [data-view=camera]").click()
        time.sleep(0.3)
        cam = info["camera"]
        l1, l2 = view_lights(cam)
        imp = [i for i, s in enumerate(scene["shapes"]) if s and s["kind"] == "implicit"]
        lo, hi = scene["shapes"][imp[0]]["lo"], scene["shapes"][imp[0]]["hi"]
        hits = []
        for y in range(2, IMP_SIZE[1], 4):
            for x in range(2, IMP_SIZE[0], 4):
                st, b = srv.get("/api/trace", x=x, y=y, opts="depth=1", sample=0)
                h = json.loads(b)["roots"][0].get("hit") if st == 200 else None
                if not h:
                    continue
                on = h["object"] in imp
                # the floor where the box would have covered it: under the
                # box, within its outline as the camera sees it
                p = h["point"]
                under = not on and abs(p[0]) < hi[0] and abs(p[1]) < hi[1]
                if not on and not under:
                    continue
                mt = scene["materials"][h["material"]]
                lam = 0.3 + 0.55 * abs(sum(a * b for a, b in zip(h["ns"], l1))) + \
                    0.25 * abs(sum(a * b for a, b in zip(h["ns"], l2)))
                if "texture" in mt:
                    want = [min(255.0, 255 * srgb(c) * lam) for c in h["surface"]]
                else:
                    want = [255 * (0.2 + 0.8 * min(1.0, max(0.0, c))) * lam for c in mt["color"]]
                hits.append(("torus" if on else "floor", p, want))
        cols = gl_colours(d, [p for _, p, _ in hits])
        by = {"torus": [], "floor": []}
        for (what, _, want), near in zip(hits, cols):
            if near is not None:
                by[what].append(min(max(abs(a - b) for a, b in zip(want, g)) for g in near))
        for what in ("torus", "floor"):
            errs = sorted(by[what])
            within = sum(1 for e in errs if e <= 24) / max(1, len(errs))
            check(len(errs) >= 20 and within >= 0.85 and errs[len(errs) // 2] <= 8,
                  "implicit: %s: %d of %d pixels within 24 of its colour there, median off by %s"
                  % ("the torus drawn as its surface" if what == "torus" else "the floor around and through it",
                     round(within * len(errs)), len(errs), "%.1f" % errs[len(errs) // 2] if errs else "-"),
                  "off by %s" % " ".join("%.0f" % e for e in errs[-20:]))
        n = sum(s["surface"]["triangles"] for s in scene["shapes"] if s and s.get("surface"))
        check(attr(d, "box3d", "data-surface-triangles") == str(n) and "box" not in d.find_element(By.ID, "note3d").text,
              "implicit: the view shades the %d triangles of the surface, and notes no box" % n,
              d.find_element(By.ID, "note3d").text)
        if SHOT:
            d.find_element(By.ID, "gl3d").screenshot(os.path.join(os.path.dirname(os.path.abspath(SHOT)),
                                                                  "torus-3d.png"))
        check(not console_errors(d), "implicit: no console error", console_errors(d))
    finally:
        d.get("about:blank")
        srv.stop()


# ---- regressions: one check per bug fixed in the page ----

def fix_3d_clip(d):
    """The 3D view clips its rays to the canvas: a ray that runs far off
    screen (nan.nff, pixel 48,36, a node hovered) used to reach the 2D
    canvas at 1e5 px and take seconds per redraw."""
    srv = Server("tests/data/debug/nan.nff", "-s", "96x72", "-d", "5")
    try:
        d.get(srv.url)
        wait(d, "image", lambda: attr(d, "viewport", "data-image") or page_error(d), 60)
        click_pixel(d, 48, 36)
        wait(d, "pixel", lambda: selected_pixel(d) == "48,36", 30)
        wait(d, "3d", lambda: attr(d, "box3d", "data-triangles"), 10)
        node = d.find_elements(By.CSS_SELECTOR, "#tree-a details.node > summary")[1]
        ActionChains(d).move_to_element(node).perform()
        time.sleep(0.5)
        ms = d.execute_script(
            "const out = []; for (let i = 0; i < 4; i++) { const t0 = performance.now();"
            " window.ggrtView3d.draw();"
            " document.getElementById('ov3d').getContext('2d').getImageData(0, 0, 1, 1);"
            " out.push(performance.now() - t0); } return out.slice(1);")  # the first: a warm-up
        far = d.execute_script("return Math.max(0, ...window.ggrtView3d.segs.flatMap("
                               "(s) => s.s.flat().map(Math.abs)));")
        check(max(ms) < 500 and far < 5000, "the 3D view redraws nan.nff's rays in %s ms (< 500), "
              "its segments within %.0f px of the canvas" % ("/".join("%.0f" % t for t in ms), far))
    finally:
        d.get("about:blank")
        srv.stop()


def fix_typing(d):
    """Typing with pauses in the find and path boxes: the check of the text
    as typed marks an error without selecting it (the next keystroke used
    to overwrite the selection); on submit the error's column is selected."""
    srv = Server(SCENE, "-s", "64x48")
    try:
        d.get(srv.url)
        wait(d, "image", lambda: attr(d, "viewport", "data-image"), 60)
        for box_id, chunks in (("find-input", ["some(kind == ", "ti", "r)"]), ("path-input", ["C.*<RS'", "tir'>.*"])):
            box = d.find_element(By.ID, box_id)
            box.click()
            for c in chunks:
                box.send_keys(c)
                time.sleep(0.8)
            got = box.get_attribute("value")
            check(got == "".join(chunks), "typing %r with pauses in #%s keeps the text (%r)"
                  % ("".join(chunks), box_id, got))
        box = d.find_element(By.ID, "path-input")
        box.clear()
        box.send_keys("C<X>" + Keys.ENTER)
        ok = wait(d, "bad", lambda: d.execute_script(
            "const b = document.getElementById('path-input');"
            "return b.classList.contains('bad') && b.selectionStart === 2 && b.selectionEnd === 3;"), 10)
        check(ok, "submitting a malformed path selects its error's column")
    finally:
        d.get("about:blank")
        srv.stop()


def view_lights(cam):
    """The 3D view's shader's two light directions through the scene's
    camera (view3d.js): towards the eye and the camera's up."""
    def unit(a):
        n = sum(x * x for x in a) ** 0.5
        return [x / n for x in a]
    return unit([cam["from"][i] - cam["at"][i] for i in range(3)]), unit(cam["up"])


def fix_cancel(d):
    """A render given up for another (the options changed in the address)
    is cancelled: the new one does not wait behind it, and while it waits
    the status line says behind what."""
    srv = Server(SCENE, "-s", "400x300")
    try:
        d.get(srv.url)
        wait(d, "image", lambda: attr(d, "viewport", "data-image"), 60)
        d.execute_script("location.hash = '#a=' + encodeURIComponent('depth=16 samples=64')")
        time.sleep(2)
        t0 = time.time()
        d.execute_script("location.hash = '#a=' + encodeURIComponent('depth=3')")
        said = set()
        # Uncancelled, the first render (depth 16, 64 samples) holds the
        # only job slot for minutes; cancelled, the new image comes in
        # 7-13 s (2026-12-07, 13.2 s beside another user's work).
        while time.time() - t0 < 40 and attr(d, "viewport", "data-image") != "opts=depth%3D3":
            said.add(d.find_element(By.ID, "status-text").get_attribute("textContent"))
            time.sleep(0.05)
        dt = time.time() - t0
        check(attr(d, "viewport", "data-image") == "opts=depth%3D3" and dt < 30,
              "a render given up for another is cancelled: the new image in %.1f s (< 30)" % dt)
        behind = [t for t in said if "queued behind render" in t]
        check(behind, "the status line says what a queued render waits behind (%s)" % (behind[:1] or said))
    finally:
        d.get("about:blank")
        srv.stop()


def fix_binary_202(d):
    """An image, mask or float request answered 202 (its job was replaced
    and runs again) asks again: the JSON progress is not taken as data."""
    srv = Server(SCENE, "-s", "64x48")
    try:
        d.get(srv.url)
        wait(d, "image", lambda: attr(d, "viewport", "data-image"), 60)
        got = d.execute_async_script(
            "const done = arguments[arguments.length - 1], real = window.fetch; let n = 0;"
            "window.fetch = function (u, o) {"
            " if (String(u).indexOf('/api/image') >= 0 && n++ === 0) return Promise.resolve(new Response("
            "  '{\"job\":{\"id\":1,\"state\":\"queued\",\"done\":0,\"total\":1}}',"
            "  { status: 202, headers: { 'Content-Type': 'application/json' } }));"
            " return real(u, o); };"
            "window.ggrt.api('/api/image', { format: 'f32' }, 'buf')"
            " .then((r) => done([r.status, r.body.byteLength, n]), (e) => done(['error', e.message, n]))"
            " .finally(() => { window.fetch = real; });")
        check(got == [200, 64 * 48 * 12, 2], "a 202 to an f32 request is asked again, not taken as the floats (%s)"
              % got)
    finally:
        d.get("about:blank")
        srv.stop()


def fix_server_gone(d):
    """With the server stopped, a click says the server is not answering,
    and the pixel's title does not stay "tracing"."""
    srv = Server(SCENE, "-s", "64x48")
    try:
        d.get(srv.url)
        wait(d, "image", lambda: attr(d, "viewport", "data-image"), 60)
        srv.stop()
        click_pixel(d, 10, 10)
        wait(d, "error", lambda: page_error(d), 10)
        err, title = page_error(d), d.find_element(By.ID, "pixel-title").text
        check("not answering" in err and "tracing" not in title,
              "the server stopped: the page says it is not answering (%r, %r)" % (err, title))
    finally:
        d.get("about:blank")
        if srv.p.poll() is None:
            srv.stop()


def fix_hashchange(d):
    """The address changed in the open page: the visible tab, the diff
    panel and the 3D camera follow it."""
    srv = Server(SCENE, "-s", "64x48")
    try:
        d.get(srv.url + "#px=10,10")
        wait(d, "image", lambda: attr(d, "viewport", "data-image") and selected_pixel(d), 60)
        wait(d, "3d", lambda: attr(d, "box3d", "data-triangles"), 10)
        d.execute_script("location.hash = '#px=10,10&tab=ledger&diff=1&b=depth%3D2&cam=1,0.5,7,0,0,0'")
        ok = wait(d, "tab", lambda: d.execute_script(
            "return !document.getElementById('tab-ledger').hidden && document.getElementById('tab-tree').hidden"
            " && document.querySelector('#tabs button.active').dataset.tab === 'ledger'"
            " && document.getElementById('diff-panel').open && window.ggrtView3d.dist === 7;"), 10)
        check(ok, "a changed address shows its tab, opens the diff panel and takes its 3D camera",
              d.execute_script("return [document.querySelector('#tabs button.active').dataset.tab,"
                               " document.getElementById('diff-panel').open, window.ggrtView3d.dist]"))
    finally:
        d.get("about:blank")
        srv.stop()


def fix_zoom_keys(d):
    """+ and - step the zoom on screen: up to 8x, down from 5x to 4x."""
    srv = Server(SCENE, "-s", "64x48")
    try:
        d.get(srv.url + "#zoom=4")
        wait(d, "image", lambda: attr(d, "viewport", "data-image"), 60)
        d.find_element(By.ID, "image").click()
        zs = []
        for k in "++++-":
            ActionChains(d).send_keys(k).perform()
            time.sleep(0.1)
            zs.append(d.execute_script("return window.ggrt.state.zoom"))
        check(zs == [5, 6, 7, 8, 7], "+ and - step the zoom from 4x: %s" % zs)
    finally:
        d.get("about:blank")
        srv.stop()


BIG_OPTS = "depth=16 samples=64 corners ray-budget=100000"  # a check or find of it is 413


def fix_stale_messages(d):
    """A new request's success clears the error it superseded: the 413 of
    a pixel's diagnostics goes when another pixel is traced; a B option
    text the server refuses takes the B tree and the comparison of before
    away; a find that fails takes the overlay and legend of the one before."""
    srv = Server(SCENE, "-s", "64x48")
    try:
        d.get(srv.url + "#px=40,30&tab=diag&a=" + urllib.parse.quote(BIG_OPTS))
        wait(d, "413", lambda: "413" in page_error(d) or "MiB" in page_error(d), 60)
        first = page_error(d)
        d.find_element(By.CSS_SELECTOR, "#tabs [data-tab=tree]").click()
        click_pixel(d, 20, 20)
        wait(d, "pixel", lambda: selected_pixel(d) == "20,20", 30)
        time.sleep(0.5)
        check("MiB" in first and page_error(d) == "" and
              d.execute_script("return document.querySelectorAll('#tree-a details.node').length") > 0,
              "a pixel traced after another's failed diagnostics clears the banner (was %r, now %r)"
              % (first[:60], page_error(d)))

        d.get("about:blank")
        d.get(srv.url + "#px=10,10&diff=1&b=depth%3D2")
        wait(d, "B", lambda: d.execute_script(
            "return !document.getElementById('tree-b').hidden && !document.getElementById('divergence').hidden"
            " && document.querySelectorAll('#tree-b details.node').length > 0"), 60)
        d.execute_script("location.hash = '#px=10,10&diff=1&b=cutoff%3Dabc'")
        wait(d, "error", lambda: "cutoff" in page_error(d), 30)
        time.sleep(0.5)
        got = d.execute_script(
            "return [document.getElementById('tree-b').hidden, document.getElementById('divergence').hidden,"
            " document.getElementById('diff-result').textContent]")
        check("cutoff" in page_error(d) and got == [True, True, ""],
              "a B option text the server refuses hides the B tree and the comparison (%r; %r)"
              % (page_error(d), got))

        d.get("about:blank")
        d.get(srv.url + "#ov=find&find=" + urllib.parse.quote("some(kind == tir)"))
        wait(d, "find", lambda: attr(d, "overlay", "data-kind") == "find", 60)
        before = d.find_element(By.ID, "legend-text").get_attribute("textContent")
        d.execute_script("location.hash = '#ov=find&find=' + encodeURIComponent('some(kind == tir)')"
                         " + '&a=' + encodeURIComponent('%s')" % BIG_OPTS)
        wait(d, "find error", lambda: attr(d, "overlay", "data-kind") == "find-error", 60)
        time.sleep(0.3)
        painted = d.execute_script(
            "const c = document.getElementById('overlay'), a = c.getContext('2d').getImageData(0, 0, c.width,"
            " c.height).data; let n = 0; for (let i = 3; i < a.length; i += 4) if (a[i]) n++; return n;")
        legend = d.find_element(By.ID, "legend-text").get_attribute("textContent")
        check(before and attr(d, "overlay", "data-kind") == "find-error" and painted == 0 and legend == "",
              "a failed find clears the overlay and legend of the one before (%d pixels drawn, legend %r)"
              % (painted, legend))
    finally:
        d.get("about:blank")
        srv.stop()


def fix_image_race(d):
    """An image answer that comes after a newer view's (the options changed
    meanwhile) does not replace the newer image: the hover readout reads
    the values of the options shown."""
    srv = Server(SCENE, "-s", "64x48")

    def floats(opts):
        srv.get("/api/render", opts=opts)  # starts the render
        wait(d, "render", lambda: srv.get("/api/image", format="f32", opts=opts)[0] == 200, 30)
        return struct.unpack("<%df" % (64 * 48 * 3), srv.get("/api/image", format="f32", opts=opts)[1])

    try:
        a2, a3 = floats("depth=1"), floats("depth=3")
        px = next((x, y) for y in range(48) for x in range(64) if a2[3 * (y * 64 + x)] != a3[3 * (y * 64 + x)])
        d.get(srv.url)
        wait(d, "image", lambda: attr(d, "viewport", "data-image"), 60)
        # The depth=1 image's answers are held back 3 s; depth=3 is asked
        # for while they are held.
        d.execute_script(
            "const real = window.fetch; window.heldBack = 0;"
            "window.fetch = async function (u, o) {"
            " if (String(u).indexOf('/api/image') >= 0 && String(u).indexOf('depth%3D1') >= 0) {"
            "  window.heldBack++; await new Promise((r) => setTimeout(r, 3000)); }"
            " return real(u, o); };"
            "location.hash = '#a=depth%3D1';")
        wait(d, "held", lambda: d.execute_script("return window.heldBack >= 2"), 30)
        d.execute_script("location.hash = '#a=depth%3D3'")
        wait(d, "image", lambda: attr(d, "viewport", "data-image") == "opts=depth%3D3", 30)
        time.sleep(3.5)  # the held-back answers are in
        click_pixel(d, px[0], px[1], move_only=True)
        time.sleep(0.2)
        hov = d.find_element(By.ID, "hover").get_attribute("textContent").split("\n")[0]
        want = "pixel %d,%d  %s" % (px[0], px[1], " ".join("%.9g" % v for v in a3[3 * (px[1] * 64 + px[0]):][:3]))
        check(hov == want, "an image answer older than the view shown does not replace it: the hover "
              "reads depth=3's value (%r, want %r)" % (hov, want))
    finally:
        d.get("about:blank")
        srv.stop()


def fix_mask_options(d):
    """The outline of an object no eye ray reaches first (glass.nff's
    bubble) comes from the page's options: changed options find it again
    (with corners it is in more pixels) instead of the first options'."""
    srv = Server(SCENE, "-s", "160x120")

    def hover_bubble():
        wait(d, "bubble", lambda: d.execute_script(
            "const t = window.ggrt.traces; if (!t.a) return false; let id = -1;"
            "const walk = (n) => { if (id < 0 && n.hit && n.hit.object === 2) id = n.id; n.children.forEach(walk); };"
            "t.a.json.roots.forEach(walk); return id >= 0 && !!document.querySelector("
            "'#tree-a details.node[data-id=\"' + id + '\"]');"), 30)
        node = d.execute_script(
            "const t = window.ggrt.traces; let id = -1;"
            "const walk = (n) => { if (id < 0 && n.hit && n.hit.object === 2) id = n.id; n.children.forEach(walk); };"
            "t.a.json.roots.forEach(walk);"
            "const e = document.querySelector('#tree-a details.node[data-id=\"' + id + '\"]');"
            "for (let p = e; p && p.tagName === 'DETAILS'; p = p.parentElement) p.open = true;"
            "e.scrollIntoView({ block: 'center' }); return e.querySelector(':scope > summary');")
        ActionChains(d).move_to_element(d.find_element(By.ID, "pixel-title")).perform()
        ActionChains(d).move_to_element(node).perform()
        wait(d, "mask", lambda: attr(d, "objmask", "data-object") == "2" and
             int(attr(d, "objmask", "data-pixels") or 0) > 0, 60)
        return int(attr(d, "objmask", "data-pixels") or 0), attr(d, "objmask", "data-how")

    try:
        d.get(srv.url + "#px=80,50")
        wait(d, "image", lambda: attr(d, "viewport", "data-image") and selected_pixel(d) == "80,50", 60)
        n1, how1 = hover_bubble()
        d.execute_script("location.hash = '#px=80,50&a=corners'")
        wait(d, "image", lambda: attr(d, "viewport", "data-image") == "opts=corners" and
             d.execute_script("return window.ggrt.traces.key.indexOf('corners') >= 0"), 60)
        time.sleep(0.5)
        n2, how2 = hover_bubble()
        ask = dict(where="some(kind != shadow && object == 2)", limit="0", opts="corners samples=1")
        wait(d, "find", lambda: srv.get("/api/find", **ask)[0] == 200, 60)
        want = json.loads(srv.get("/api/find", **ask)[1]).get("matched")
        check(how1 == how2 == "seen through other surfaces" and n2 == want and n1 != n2,
              "the bubble's outline follows the options: %d pixels, with corners %d (ggrt find: %s)"
              % (n1, n2, want))
    finally:
        d.get("about:blank")
        srv.stop()


def fix_value_readout(d):
    """The pixel's value and its ray counts are apart on screen (three
    spaces between them in one text used to collapse into one)."""
    srv = Server(SCENE, "-s", "64x48")
    try:
        d.get(srv.url + "#px=10,10")
        wait(d, "value", lambda: attr(d, "viewport", "data-image") and attr(d, "pixel-value", "data-rgb"), 60)
        got = d.execute_script(
            "const v = document.getElementById('pixel-value'), r = document.getElementById('pixel-rays');"
            "if (!r) return [v.textContent, null, 0];"
            "const a = v.getBoundingClientRect(), b = r.getBoundingClientRect();"
            "return [v.textContent, r.textContent, b.top >= a.bottom - 1 ? 'next line' : b.left - a.right];")
        check(re.match(r"^\S+ \S+ \S+$", got[0]) and got[1] and got[1].startswith("rays: eye ") and
              (got[2] == "next line" or got[2] >= 8),
              "the value and the ray counts are apart (%r, %r: %s)" % tuple(got))
    finally:
        d.get("about:blank")
        srv.stop()


def fix_pixel_offset(d):
    """A click selects the pixel under the mouse where the image's box
    starts at a fraction of a CSS pixel (a status line that wrapped put
    it at 60.375: the pixel a row above was chosen), at 1x and 3x."""
    srv = Server(SCENE, "-s", "64x48")
    try:
        got = []
        for zoom in (1, 3):
            page_off_grid(d, srv, zoom)
            c = d.find_element(By.ID, "image")
            w, h = c.size["width"], c.size["height"]
            for x, y in ((5, 5), (30, 20), (50, 41), (63, 47)):
                # The pointer at whole CSS pixels from the in-view centre
                # (floor of the box's middle): at 1x on the top row of the
                # pixel as painted, where 0.375 px above it is another row.
                ActionChains(d).move_to_element_with_offset(
                    c, zoom * x + zoom // 2 - w // 2, zoom * y + zoom // 2 - h // 2).click().perform()
                wait(d, "pixel", lambda: selected_pixel(d), 30)
                time.sleep(0.1)
                got.append((zoom, (x, y), selected_pixel(d)))
        bad = [g for g in got if g[2] != "%d,%d" % g[1]]
        check(not bad, "a click selects the pixel under it, the image 0.375 px off the grid (%d of %d "
              "clicks right; wrong: %s)" % (len(got) - len(bad), len(got), bad))
        pixel_offset_hidpi(d, srv)
    finally:
        d.execute_cdp_cmd("Emulation.clearDeviceMetricsOverride", {})
        d.get("about:blank")
        srv.stop()


def page_off_grid(d, srv, zoom):
    """The page at a zoom, its image's box moved 0.375 CSS px off the
    pixel grid (where a status line that wrapped once put it)."""
    d.get("about:blank")
    d.get(srv.url + "#zoom=%d" % zoom)
    wait(d, "image", lambda: attr(d, "viewport", "data-image"), 60)
    d.execute_script("document.getElementById('viewport').style.marginTop = '0.375px'")


def pixel_offset_hidpi(d, srv):
    """On a 2x screen the pointer moves by half CSS pixels: a click and the
    hover readout name the pixel under it in both halves of a pixel, to
    the last column and row, the image's box 0.375 px off the grid (a
    click's own position is cut to whole CSS pixels, its offsetX rounded:
    the right half of each pixel chose the next one)."""
    size = d.get_window_size()
    d.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                      {"width": size["width"], "height": size["height"], "deviceScaleFactor": 2, "mobile": False})
    got = []
    for zoom in (1, 3):
        page_off_grid(d, srv, zoom)
        left, top = d.execute_script("const r = document.getElementById('image').getBoundingClientRect();"
                                     "return [Math.round(2 * r.left) / 2, Math.round(2 * r.top) / 2]")
        for x, y in ((5, 5), (30, 20), (63, 47)):
            for fx, fy in ((0.1, 0.1), (0.6, 0.7), (0.9, 0.9)):
                px, py = left + zoom * (x + fx), top + zoom * (y + fy)
                for typ in ("mouseMoved", "mousePressed", "mouseReleased"):
                    d.execute_cdp_cmd("Input.dispatchMouseEvent", {"type": typ, "x": px, "y": py,
                                                                   "button": "left", "clickCount": 1})
                time.sleep(0.1)
                hover = d.find_element(By.ID, "hover").get_attribute("textContent").split("  ")[0]
                got.append((zoom, (x, y), (fx, fy), selected_pixel(d), hover))
    bad = [g for g in got if g[3] != "%d,%d" % g[1] or g[4] != "pixel %d,%d" % g[1]]
    check(not bad, "on a 2x screen a click and the hover readout name the pixel under the pointer "
          "(%d of %d right; wrong: %s)" % (len(got) - len(bad), len(got), bad[:4]))


def fix_zoom_select(d):
    """The zoom dropdown says the zoom on screen (fit, or 1x to 16x), each
    of its entries can be chosen, and + never zooms out: a small image
    fitted at 11x goes to 12x, not down to 8x."""
    srv = Server("tests/data/debug/nan.nff")
    try:
        d.get(srv.url)
        wait(d, "image", lambda: attr(d, "viewport", "data-image"), 60)
        on_screen = lambda: d.execute_script(  # noqa: E731
            "return Math.round(parseFloat(document.getElementById('image').style.width) / window.ggrt.W)")
        fitted, sel0 = on_screen(), d.find_element(By.ID, "zoom").get_attribute("value")
        d.find_element(By.ID, "image").click()
        ActionChains(d).send_keys("+").perform()
        time.sleep(0.2)
        plus, sel1 = on_screen(), d.find_element(By.ID, "zoom").get_attribute("value")
        Select(d.find_element(By.ID, "zoom")).select_by_value("4")
        time.sleep(0.2)
        four = on_screen()
        Select(d.find_element(By.ID, "zoom")).select_by_value("0")
        time.sleep(0.2)
        back, sel2 = on_screen(), d.find_element(By.ID, "zoom").get_attribute("value")
        check(sel0 == "0" and plus == min(16, max(fitted + 1, 1)) and sel1 == str(plus) and four == 4 and
              back == fitted and sel2 == "0",
              "the zoom dropdown follows the zoom: fit %dx ('%s'), + %dx ('%s'), 4x chosen %dx, fit again "
              "%dx ('%s')" % (fitted, sel0, plus, sel1, four, back, sel2))
    finally:
        d.get("about:blank")
        srv.stop()


def fix_find_box(d):
    """An emptied find box takes the find away, as the path box does; the
    status line says the image's summary again after an error is undone;
    a failed find leaves no mask to save; a scene with no radiance bound
    says "unbounded", not nan."""
    srv = Server(SCENE, "-s", "64x48")
    try:
        d.get(srv.url + "#ov=find&find=" + urllib.parse.quote("some(kind == tir)"))
        wait(d, "find", lambda: attr(d, "overlay", "data-kind") == "find", 60)
        box = d.find_element(By.ID, "find-input")
        box.clear()
        box.send_keys(Keys.ENTER)
        wait(d, "cleared", lambda: d.execute_script("return window.ggrt.state.find === ''"), 30)
        time.sleep(0.3)
        got = d.execute_script("return [window.ggrt.state.overlay, location.hash.indexOf('find=') >= 0,"
                               " document.getElementById('find-result').textContent]")
        check(got == ["none", False, ""], "an emptied find box takes the find away (%r)" % got)

        d.execute_script("location.hash = '#a=cutoff%3D-1'")
        wait(d, "error", lambda: "cutoff" in page_error(d), 30)
        d.find_element(By.ID, "reset-a").click()
        wait(d, "reset", lambda: page_error(d) == "", 30)
        time.sleep(0.5)
        st = d.find_element(By.ID, "status-text").get_attribute("textContent")
        check(st.startswith("rendered A"), "after the error is undone the status line is the image's again (%r)" % st)

        d.execute_script("location.hash = '#ov=find&find=' + encodeURIComponent('some(kind == tir)')"
                         " + '&a=' + encodeURIComponent('%s')" % BIG_OPTS)
        wait(d, "find error", lambda: attr(d, "overlay", "data-kind") == "find-error", 60)
        d.find_element(By.CSS_SELECTOR, "#export [data-export=overlay]").click()
        time.sleep(0.3)
        note = d.find_element(By.ID, "export-note").get_attribute("textContent")
        check(note == "no overlay or mask on the image", "a failed find leaves no mask to save (%r)" % note)
    finally:
        d.get("about:blank")
        srv.stop()
    srv = Server("examples/scenes/knot.nff", "-s", "64x48")
    try:
        d.get(srv.url + "#px=32,24&tab=diag")
        wait(d, "diagnostics", lambda: "radiance bound" in d.find_element(By.ID, "right").text, 60)
        text = [t for t in d.find_element(By.ID, "right").text.split("\n") if "radiance bound" in t]
        check(text and "unbounded" in text[0] and "nan" not in text[0],
              "a scene with no radiance bound says so in the diagnostics (%r)" % text)
    finally:
        d.get("about:blank")
        srv.stop()


def fix_narrow(d):
    """At 800x600 the page does not scroll sideways (the tree panel goes
    under the image), and the two-view SVG's legend fits its width."""
    srv = Server(SCENE, "-s", "160x120")
    size = d.get_window_size()
    try:
        d.set_window_size(800, 600)
        d.get(srv.url + "#px=80,50")
        wait(d, "tree", lambda: d.execute_script("return document.querySelectorAll('#tree-a details.node').length > 0"), 60)
        w = d.execute_script("return [document.documentElement.scrollWidth, window.innerWidth]")
        check(w[0] <= w[1], "at 800x600 nothing scrolls sideways (page %d px, window %d px)" % tuple(w))
        code, body = srv.get("/api/trace", x="80", y="50", format="svg")
        svg = body.decode()
        width = float(re.search(r"<svg[^>]* width='([0-9.]+)'", svg).group(1))
        ends = [float(x) + 7.0 * len(t) for x, t in re.findall(r"<text x='([0-9.]+)' y='[0-9.]+' font-size='12'>([^<]*)<", svg)]
        check(code == 200 and ends and max(ends) <= width,
              "the trace SVG's legend fits its %g px (its last label ends by %g)" % (width, max(ends or [0])))
    finally:
        d.set_window_size(size["width"], size["height"])
        d.get("about:blank")
        srv.stop()


def fix_zero_and_overlay_key(d):
    """A 0 typed in a text field of the options panel goes to the server,
    which says what the field takes, in view when the page is scrolled
    down (it used to be dropped without a word;
    "scene" in the depth list is still the server's own depth); `o` cycles
    only the overlays with something to show: find, path and diff once
    there is a find, a path or a B side."""
    srv = Server(SCENE, "-s", "64x48")
    try:
        d.get(srv.url)
        wait(d, "image", lambda: attr(d, "viewport", "data-image"), 60)
        for name in ("ray-budget", "offset", "implicit-tol", "gradient"):
            d.execute_script("document.getElementById('opt-a-%s').value = '0';"
                             "document.getElementById('render-a').click();" % name)
            ok = wait(d, "error", lambda: name + " must be" in page_error(d), 30)
            got = d.execute_script("return window.ggrt.state.a")
            check(ok and got == name + "=0", "a 0 typed for %s reaches the server, which refuses it (%r; %r)"
                  % (name, got, page_error(d)[:80]))
            d.find_element(By.ID, "reset-a").click()
            wait(d, "reset", lambda: page_error(d) == "", 30)
        d.execute_script("window.scrollTo(0, document.body.scrollHeight);"
                         "document.getElementById('opt-a-ray-budget').value = '-1';"
                         "document.getElementById('render-a').click();")
        wait(d, "error", lambda: "ray-budget must be" in page_error(d), 30)
        box = d.execute_script("const r = document.getElementById('error').getBoundingClientRect();"
                               "return [window.scrollY, r.top, r.bottom, window.innerHeight]")
        check(box[0] > 0 and box[1] >= 0 and box[2] <= box[3],
              "an option refused with the page scrolled down is said in view (scrolled %d px, banner %g to %g of %d)"
              % tuple(box))
        d.find_element(By.ID, "reset-a").click()
        wait(d, "reset", lambda: page_error(d) == "", 30)
        d.execute_script("window.scrollTo(0, 0)")
        d.execute_script("document.getElementById('opt-a-depth').value = '0';"
                         "document.getElementById('render-a').click();")
        time.sleep(0.3)
        got = d.execute_script("return window.ggrt.state.a")
        check(got == "", "'scene' in the depth list is the server's depth (option text %r)" % got)

        def cycle(n):
            seen = []
            for _ in range(n):
                ActionChains(d).send_keys("o").perform()
                time.sleep(0.1)
                seen.append(d.execute_script("return window.ggrt.state.overlay"))
            return seen
        d.find_element(By.ID, "image").click()
        got = cycle(4)
        check(got == ["rays", "depth", "time", "none"], "with no find, path or B side, o cycles %s" % got)
        d.execute_script("location.hash = '#find=' + encodeURIComponent('some(kind == tir)')")
        wait(d, "find", lambda: d.execute_script("return window.ggrt.state.find !== ''"), 30)
        got = cycle(5)
        check(got == ["rays", "depth", "time", "find", "none"], "with a find, o cycles %s" % got)
    finally:
        d.get("about:blank")
        srv.stop()

def fix_hover_after_diff(d):
    """The hover readout is said again when the view changes: with diff
    mode turned off it no longer shows B's value and the diff map's words
    for the pixel under the mouse; the status line says what its second
    time is."""
    srv = Server(SCENE, "-s", "64x48")
    try:
        d.get(srv.url + "#ov=diff&diff=1&b=depth%3D2")
        wait(d, "diff", lambda: attr(d, "overlay", "data-kind") == "diff", 60)
        c = d.find_element(By.ID, "image")
        ActionChains(d).move_to_element(c).perform()
        hover = lambda: d.find_element(By.ID, "hover").get_attribute("textContent")
        wait(d, "hover", lambda: "\nB " in hover(), 10)
        before = hover()
        d.find_element(By.ID, "diff-on").click()
        wait(d, "diff off", lambda: d.execute_script("return !window.ggrt.state.diff"), 30)
        wait(d, "readout", lambda: "\nB " not in hover(), 10)
        after = hover()
        check("\nB " in before and ("differs" in before or "same" in before),
              "with diff mode on, the readout has B and the map's words (%r)" % before)
        check(after.startswith("pixel ") and "\nB " not in after and "differs" not in after and "same" not in after,
              "diff mode turned off takes B and the map's words out of the readout (%r)" % after)
        st = d.find_element(By.ID, "status-text").get_attribute("textContent")
        check(re.match(r"rendered A in [0-9.]+ s \(this page waited [0-9.]+ s\): ", st) is not None,
              "the status line says what its second time is (%r)" % st)
        d.execute_script("location.hash = '#ov=time'")
        wait(d, "time", lambda: attr(d, "overlay", "data-kind") == "time", 60)
        legend = d.find_element(By.ID, "legend-text").get_attribute("textContent")
        check(re.match(r"time per pixel \(seconds\), 0 to [0-9.e+-]+( \(the 99\.9th percentile; [0-9]+ pixels? "
                       r"over it, up to [0-9.e+-]+\))?$", legend) is not None,
              "the time overlay's legend names its scale (%r)" % legend)
    finally:
        d.get("about:blank")
        srv.stop()

def fix_numeric_line(d):
    """The tree tab shows each hit's numeric state (error bound, offset,
    TIR margin, edge) as ggrt trace's text does; it was only in the text
    tab, and it is the number a TIR question needs."""
    srv = Server(SCENE)
    try:
        d.get(srv.url + "#px=110,100")
        wait(d, "tree", lambda: d.execute_script("return document.querySelectorAll('#tree-a details.node').length > 0"), 60)
        page = d.execute_script("return [...document.querySelectorAll('#tree-a .numeric')]"
                                ".map((e) => e.textContent.replace(/^numeric /, ''))")
        out = subprocess.run([GGRT, "trace", SCENE, "--pixel", "110,100"], cwd=ROOT, stdout=subprocess.PIPE,
                             text=True).stdout
        want = [re.sub(r", traversal .*$", "", ln.split("numeric: ", 1)[1]) for ln in out.splitlines() if "numeric: " in ln]
        check(want and page == want and any("tir margin" in t for t in page),
              "the tree tab's numeric lines are ggrt trace's (%d of them; %r)" % (len(want), page[:2]))
    finally:
        d.get("about:blank")
        srv.stop()

def fixes(d):
    if os.environ.get("GG_BROWSER_FIXES"):
        for name in os.environ["GG_BROWSER_FIXES"].split(","):
            globals()[name](d)
        return
    for f in (fix_3d_clip, fix_typing, fix_cancel, fix_binary_202, fix_server_gone, fix_hashchange,
              fix_zoom_keys, fix_stale_messages, fix_image_race, fix_mask_options,
              fix_value_readout, fix_pixel_offset, fix_zoom_select, fix_find_box, fix_narrow,
              fix_zero_and_overlay_key, fix_hover_after_diff, fix_numeric_line):
        try:
            f(d)
        except Exception:  # noqa: BLE001 -- one check that cannot go on fails, the others still run
            check(False, "%s ran to the end" % f.__name__, traceback.format_exc())


def main():
    t0 = time.time()
    want = cli_pixel()
    profile = tempfile.mkdtemp(prefix="ggrt-browser-")
    d = None
    try:
        d = browser(profile)
        steps = [("glass", lambda: glass(d, want)), ("layout", lambda: layout(d)),
                 ("first", lambda: tracing_first(d)), ("scenes", lambda: every_scene(d)),
                 ("paths", lambda: paths(d, DOCS)), ("history", lambda: history(d)),
                 ("textures", lambda: textures(d)), ("implicit", lambda: implicit(d)),
                 ("fixes", lambda: fixes(d))]
        if DOCS:
            steps.append(("docs", lambda: docs_shots(d, DOCS)))
        for name, step in steps:
            if ONLY and name not in ONLY:
                continue
            t1 = time.time()
            try:
                step()
            except Exception:  # noqa: BLE001 -- a step that cannot go on fails, the others still run
                check(False, "the %s steps ran to the end" % name, traceback.format_exc())
            print("(%s: %.1f s)" % (name, time.time() - t1))
    finally:
        if d:
            d.quit()
        shutil.rmtree(profile, ignore_errors=True)
    print("browser: %d passed, %d failed (%.1f s)" % (passed, failed, time.time() - t0))
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
