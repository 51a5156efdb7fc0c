# SPDX-License-Identifier: MIT
"""The page of `ggrt serve` in a real browser: headless Chromium driven by
Selenium (Debian: chromium, chromium-driver, python3-selenium; run it with
the python3 that has selenium, /usr/bin/python3 on Debian). Serves
examples/scenes/glass.nff, waits for the image, clicks pixel 110,100 and
checks the tree shows refraction and TIR and the value equals ggrt
render's, hovers, moves with the keyboard, reloads from the URL, toggles a
heatmap, types a find predicate, compares with a second set of options,
draws the 3D view, and finds no console errors. Saves a screenshot.
    /usr/bin/python3 tests/browser_test.py build/ggrt [--screenshot FILE]
Prints one line per check and ends with "browser: N passed, M failed"."""
import os
import re
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import traceback

from selenium import webdriver
from selenium.common.exceptions import TimeoutException
from selenium.webdriver.chrome.options import Options
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support.ui import Select, WebDriverWait

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GGRT = os.path.abspath(sys.argv[1]) if len(sys.argv) > 1 else os.path.join(ROOT, "build", "ggrt")
SHOT = sys.argv[sys.argv.index("--screenshot") + 1] if "--screenshot" in sys.argv else None
SCENE = "examples/scenes/glass.nff"
PIXEL = (110, 100)
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
    return cond


def find_binary(*names):
    for n in names:
        p = shutil.which(n) or (n if os.path.exists(n) else None)
        if p:
            return p
    return None


def browser(profile):
    o = Options()
    for a in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
              "--disable-component-update", "--disable-sync", "--no-first-run",
              "--disable-default-apps", "--disable-extensions", "--window-size=1500,980",
              "--user-data-dir=" + profile):
        o.add_argument(a)
    o.binary_location = find_binary("chromium", "/usr/bin/chromium", "chromium-browser")
    o.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    drv = find_binary("chromedriver", "/usr/bin/chromedriver")
    return webdriver.Chrome(service=Service(drv), options=o)


def wait(d, what, fn, timeout=60):
    try:
        return WebDriverWait(d, timeout, poll_frequency=0.05).until(lambda _: fn())
    except TimeoutException:
        return None


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


def main():
    t0 = time.time()
    want = cli_pixel()
    profile = tempfile.mkdtemp(prefix="ggrt-browser-")
    srv = subprocess.Popen([GGRT, "serve", SCENE, "--port", "0"], cwd=ROOT, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
    url = srv.stdout.readline().strip()
    d = None
    try:
        check(url.startswith("http://127.0.0.1:"), "ggrt serve printed its URL", url)
        d = browser(profile)
        d.get(url)
        ok = wait(d, "image", lambda: d.find_element(By.ID, "viewport").get_attribute("data-image"))
        check(ok, "the image is shown (%.1f s after loading)" % (time.time() - t0),
              d.find_element(By.ID, "status-text").text)
        # Click 110,100: the tree shows the refraction into the glass and TIR inside it.
        click_pixel(d, *PIXEL)
        ok = wait(d, "tree", lambda: d.find_element(By.ID, "pixel-head").get_attribute("data-pixel") == "%d,%d" % PIXEL)
        check(ok, "clicking pixel %d,%d selects it" % PIXEL, d.find_element(By.ID, "pixel-title").text)
        tir = d.find_elements(By.CSS_SELECTOR, "#tree-a .node.kind-tir")
        refr = d.find_elements(By.CSS_SELECTOR, "#tree-a .node.kind-refract")
        check(len(tir) > 0 and len(refr) > 0, "the tree shows refraction and a TIR node (%d tir, %d refract)" %
              (len(tir), len(refr)))
        check(tir and tir[0].find_element(By.CSS_SELECTOR, "summary .kind").text == "tir" and
              tir[0].is_displayed(), "the TIR node is visible and labelled tir")
        got = d.find_element(By.ID, "pixel-value").get_attribute("data-rgb")
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
        ok = wait(d, "arrow", lambda: d.find_element(By.ID, "pixel-head").get_attribute("data-pixel") == "111,100")
        check(ok and "px=111%2C100" in d.current_url or "px=111,100" in d.current_url,
              "the right arrow selects 111,100 and the URL says so", d.current_url)
        d.find_element(By.ID, "image").send_keys(Keys.ARROW_LEFT)
        wait(d, "arrow", lambda: d.find_element(By.ID, "pixel-head").get_attribute("data-pixel") == "%d,%d" % PIXEL)
        # A heatmap overlay.
        Select(d.find_element(By.ID, "overlay-select")).select_by_value("rays")
        ok = wait(d, "heatmap", lambda: d.find_element(By.ID, "overlay").get_attribute("data-kind") == "rays")
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
        ok = wait(d, "find", lambda: d.find_element(By.ID, "overlay").get_attribute("data-kind") == "find")
        res = d.find_element(By.ID, "find-result").text
        m = re.match(r"(\d+) pixels? match", res)
        check(ok and m and int(m.group(1)) > 0 and "bad" not in box.get_attribute("class"),
              "find some(kind == tir): matches appear (%s)" % res, res)
        check(overlay_alpha(d, *PIXEL)[3] == 255, "pixel %d,%d is in the find mask" % PIXEL)
        check(overlay_alpha(d, 5, 5)[3] == 0, "a pixel of the sky is not")
        # The 3D view of the rays draws something.
        d.find_element(By.CSS_SELECTOR, "#tabs [data-tab=rays3d]").click()
        drawn = d.execute_script("const c = document.getElementById('view3d'), g = c.getContext('2d');"
                                 "const a = g.getImageData(0, 0, c.width, c.height).data; let n = 0;"
                                 "for (let i = 3; i < a.length; i += 4) if (a[i]) n++; return n;")
        check(drawn > 1000, "the 3D view draws the scene and the rays (%d pixels)" % drawn)
        d.find_element(By.CSS_SELECTOR, "#tabs [data-tab=views]").click()
        ok = wait(d, "svg", lambda: d.execute_script("const i = document.getElementById('svg-view');"
                                                     "return i.complete && i.naturalWidth > 0;"))
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
        ok = wait(d, "diag", lambda: len(d.find_elements(By.CSS_SELECTOR, "#diag tr")) == 8)
        check(ok and "invariant" in d.find_element(By.ID, "diag").text,
              "the diagnostics list the 7 invariants at the pixel", d.find_element(By.ID, "diag").text[:200])
        d.find_element(By.CSS_SELECTOR, "#tabs [data-tab=tree]").click()
        # The URL restores the view after a reload.
        d.get(d.current_url)
        ok = wait(d, "reload", lambda: d.find_element(By.ID, "pixel-head").get_attribute("data-pixel") == "%d,%d" % PIXEL
                  and d.find_element(By.ID, "overlay").get_attribute("data-kind") in ("rays", "find"))
        check(ok, "reloading the URL restores the pixel and the overlay", d.current_url)
        if SHOT:
            os.makedirs(os.path.dirname(os.path.abspath(SHOT)), exist_ok=True)
            Select(d.find_element(By.ID, "overlay-select")).select_by_value("none")
            wait(d, "none", lambda: d.find_element(By.ID, "overlay").get_attribute("data-kind") == "none")
            d.execute_script("window.scrollTo(0, 0); document.activeElement.blur();")
            d.save_screenshot(SHOT)
            print("screenshot: " + SHOT)
        # Diff mode against depth 2.
        d.find_element(By.CSS_SELECTOR, "#diff-panel summary").click()
        Select(d.find_element(By.ID, "opt-b-depth")).select_by_value("2")
        d.find_element(By.ID, "render-b").click()
        ok = wait(d, "diff", lambda: d.find_element(By.ID, "overlay").get_attribute("data-kind") == "diff"
                  and d.find_element(By.ID, "pixel-head").get_attribute("data-pixel") == "%d,%d" % PIXEL)
        res = d.find_element(By.ID, "diff-result").text
        trees = d.find_elements(By.CSS_SELECTOR, "#tree-b .node")
        check(ok and re.match(r"\d+ of 120000 pixels differ in value, \d+ in their ray trees", res) and trees,
              "diff mode: the divergence map and both trees (%s)" % res[:60], res)
        ok = wait(d, "divergence", lambda: d.find_element(By.ID, "divergence").is_displayed())
        div = d.find_element(By.ID, "divergence").text
        marked = d.find_elements(By.CSS_SELECTOR, "#tree-a .node.diverge, #tree-b .node.diverge")
        check(ok and div.startswith("first divergence: ray #") and marked,
              "diff mode: the first divergent ray is named and marked (%s)" % div, div)
        errors = [e for e in d.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]
        check(not errors, "no console errors", "\n".join(e["message"] for e in errors))
    except Exception:  # noqa: BLE001 -- a step that cannot go on fails the test, which still cleans up
        check(False, "the browser steps ran to the end", traceback.format_exc())
    finally:
        if d:
            d.quit()
        srv.send_signal(signal.SIGINT)
        try:
            rc = srv.wait(30)
        except subprocess.TimeoutExpired:
            srv.kill()
            rc = "hung"
        check(rc == 0, "ggrt serve stopped cleanly", srv.stderr.read()[-500:])
        shutil.rmtree(profile, ignore_errors=True)
    print("browser: %d passed, %d failed (%.1f s)" % (passed, failed, time.time() - t0))
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
