#!/usr/bin/python3
"""Tests the page of `meshfit view` in a real browser (headless Chromium, driven through the
DevTools protocol over a pipe: standard library only).

    view_test.py --meshfit BIN --data EXAMPLES_DATA --work DIR [--cgal-meshes DIR] [--large FACES]

For the embedded example: fits it, writes the page, opens it, and checks with its own oracles
(the files and the screenshots, not the page's word): no script error; the result's screenshot is
not blank, shows at least 4 region hues, and loses dark pixels when the curve edges are hidden;
the template and the network are drawn; four pairs picked by real mouse clicks are saved as a
file equal to the pairs the test chose (read from examples/data/pairs.txt) that `meshfit fit`
accepts; the page warns for fewer than 4 pairs, for coplanar pairs and for mirrored pairs exactly
when the test's own geometry says so. Then every other example set (and the elephant when CGAL's
meshes are given) is fitted and its page checked. --large N: instead, a page for an icosphere of
at least N faces (coloured by octant) is opened, and its size, load time and frame time printed.
Exit 0 pass, 1 fail, 77 skipped (no Chromium).
"""
import argparse
import base64
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import threading
import time

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_pictures import decode_png  # noqa: E402

WIDTH, HEIGHT = 1000, 640
PANEL = 330  # the page's side panel; the 3D view is to its right


class Browser:
    """Headless Chromium with --remote-debugging-pipe: JSON messages ended by NUL on fds 3 and 4."""

    def __init__(self, chromium, profile, downloads):
        to_child_r, self.to_child = os.pipe()
        self.from_child, from_child_w = os.pipe()

        def fds():
            a, b = os.dup(to_child_r), os.dup(from_child_w)
            os.dup2(a, 3)
            os.dup2(b, 4)

        self.proc = subprocess.Popen(
            [chromium, "--headless", "--no-sandbox", "--remote-debugging-pipe", "--use-angle=swiftshader",
             "--enable-unsafe-swiftshader", "--no-first-run", "--disable-extensions", "--mute-audio",
             "--user-data-dir=" + profile, "--window-size=%d,%d" % (WIDTH, HEIGHT), "about:blank"],
            preexec_fn=fds, close_fds=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(to_child_r)
        os.close(from_child_w)
        self.next_id = 0
        self.replies = {}
        self.events = []
        self.cond = threading.Condition()
        threading.Thread(target=self._read, daemon=True).start()
        target = self.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = self.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        self.call("Browser.setDownloadBehavior", {"behavior": "allow", "downloadPath": downloads})
        for domain in ("Page", "Runtime"):
            self.call(domain + ".enable", session=True)
        self.call("Emulation.setDeviceMetricsOverride",
                  {"width": WIDTH, "height": HEIGHT, "deviceScaleFactor": 1, "mobile": False}, session=True)

    def _read(self):
        buffer = b""
        while True:
            chunk = os.read(self.from_child, 1 << 20)
            if not chunk:
                return
            buffer += chunk
            while b"\0" in buffer:
                message, buffer = buffer.split(b"\0", 1)
                m = json.loads(message)
                with self.cond:
                    if "id" in m:
                        self.replies[m["id"]] = m
                    else:
                        self.events.append(m)
                    self.cond.notify_all()

    def call(self, method, params=None, session=False, timeout=600):
        self.next_id += 1
        i = self.next_id
        m = {"id": i, "method": method, "params": params or {}}
        if session:
            m["sessionId"] = self.session
        os.write(self.to_child, json.dumps(m).encode() + b"\0")
        deadline = time.time() + timeout
        with self.cond:
            while i not in self.replies:
                if not self.cond.wait(max(0.0, deadline - time.time())) and time.time() > deadline:
                    raise RuntimeError("no reply to " + method)
            reply = self.replies.pop(i)
        if "error" in reply:
            raise RuntimeError("%s: %s" % (method, reply["error"]))
        return reply["result"]

    def js(self, expression):
        r = self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True, "awaitPromise": True},
                      session=True)
        if "exceptionDetails" in r:
            raise RuntimeError("script error in %s: %s" % (expression, r["exceptionDetails"]))
        return r["result"].get("value")

    def exceptions(self):
        with self.cond:
            return [e["params"]["exceptionDetails"] for e in self.events if e.get("method") == "Runtime.exceptionThrown"]

    def open(self, path, query="", timeout=300):
        with self.cond:
            self.events.clear()
        start = time.time()
        self.call("Page.navigate", {"url": "file://" + os.path.abspath(path) + query}, session=True)
        while time.time() - start < timeout:
            if self.exceptions():
                raise RuntimeError("page error: %s" % self.exceptions()[0])
            try:
                if self.js("!!(window.meshfitView && window.meshfitView.ready)"):
                    return time.time() - start
            except RuntimeError:
                pass
            time.sleep(0.05)
        raise RuntimeError("the page did not get ready in %d s" % timeout)

    def screenshot(self, path):
        data = self.call("Page.captureScreenshot", {"format": "png"}, session=True)["data"]
        with open(path, "wb") as f:
            f.write(base64.b64decode(data))
        return decode_png(path)

    def click(self, x, y):
        for kind in ("mousePressed", "mouseReleased"):
            self.call("Input.dispatchMouseEvent",
                      {"type": kind, "x": x, "y": y, "button": "left", "buttons": 1 if kind == "mousePressed" else 0,
                       "clickCount": 1}, session=True)

    def close(self):
        try:
            self.call("Browser.close", timeout=10)
        except Exception:
            pass
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()


# ---- oracles on pixels -------------------------------------------------------------------------
def view_pixels(image):
    width, height, rows = image
    return [rows[y][x] for y in range(0, height) for x in range(PANEL + 2, width)]


def not_blank(pixels):
    background = (255, 255, 255)
    drawn = sum(1 for p in pixels if max(abs(p[i] - background[i]) for i in range(3)) > 24)
    return drawn / len(pixels)


def dark(pixels):
    return sum(1 for p in pixels if max(p) < 70)


def hues(pixels, min_share=0.002):
    """Hue buckets (of 24) holding at least min_share of the pixels, among saturated pixels."""
    import colorsys
    buckets = [0] * 24
    for p in pixels:
        h, l, s = colorsys.rgb_to_hls(p[0] / 255, p[1] / 255, p[2] / 255)
        if s > 0.35 and 0.25 < l < 0.85:
            buckets[int(h * 24) % 24] += 1
    return sum(1 for b in buckets if b >= min_share * len(pixels))


def crimson(pixels):
    return sum(1 for p in pixels if p[0] > 120 and p[1] < 60 and p[2] < 90)


# ---- files read by the test itself ---------------------------------------------------------------
def read_off(path):
    with open(path) as f:
        words = [w for line in f for w in line.split("#")[0].split()]
    assert words[0].endswith("OFF")
    nv, nf = int(words[1]), int(words[2])
    v = [tuple(float(x) for x in words[4 + 3 * i:7 + 3 * i]) for i in range(nv)]
    return v, nf


def read_pairs(path):
    pairs = []
    with open(path) as f:
        for line in f:
            line = line.split("#")[0].strip()
            if line:
                w = line.split()
                pairs.append((int(w[0]), float(w[1]), float(w[2]), float(w[3])))
    return pairs


def read_polylines(path):
    points = set()
    with open(path) as f:
        for line in f:
            w = line.split("#")[0].split()
            if w:
                n = int(w[0])
                for i in range(n):
                    points.add(tuple(float(x) for x in w[1 + 3 * i:4 + 3 * i]))
    return sorted(points)


def centred(points):
    c = [sum(p[k] for p in points) / len(points) for k in range(3)]
    return [[p[k] - c[k] for k in range(3)] for p in points]


def det3(m):
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def gram(a, b):
    return [[sum(p[r] * q[c] for p, q in zip(a, b)) for c in range(3)] for r in range(3)]


def coplanar(points):
    """Thickness of the points relative to their extent below 1e-3 (the page's threshold)."""
    c = centred(points)
    g = gram(c, c)
    trace = g[0][0] + g[1][1] + g[2][2]
    # det(G) / trace³ is about λ3 / λ1 times (λ2 / λ1): tiny exactly when the points are (nearly)
    # coplanar; the test's sets are exactly coplanar or clearly not.
    return det3(g) / trace ** 3 < 1e-12


def mirrored(template_points, network_points):
    return det3(gram(centred(template_points), centred(network_points))) < 0


class Checker:
    def __init__(self):
        self.failures = 0
        self.passes = 0

    def check(self, ok, what):
        print(("ok   " if ok else "FAIL ") + what, flush=True)
        if ok:
            self.passes += 1
        else:
            self.failures += 1
        return ok


def run(cmd, **kw):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


def fit_and_view(meshfit, template, curves, pairs, out_dir, name, check):
    ply, report, html = (os.path.join(out_dir, name + s) for s in (".ply", ".json", ".html"))
    r = run([meshfit, "fit", "--quiet", "--template", template, "--curves", curves, "--correspondences", pairs,
             "--output", ply, "--report", report])
    if not check(r.returncode == 0, "%s: meshfit fit exits 0 (%s)" % (name, r.stderr.strip()[-200:])):
        return None
    r = run([meshfit, "view", "--quiet", "--template", template, "--curves", curves, "--correspondences", pairs,
             "--result", ply, "--result-report", report, "--output", html])
    check(r.returncode == 0, "%s: meshfit view exits 0 (%s)" % (name, r.stderr.strip()))
    return html


def check_result_view(browser, html, name, work, check, expect_hues=4):
    seconds = browser.open(html)
    check(not browser.exceptions() and not browser.js("meshfitView.errors.length"), name + ": no script error")
    print("     %s: page %.2f MB, ready in %.2f s" % (name, os.path.getsize(html) / 1e6, seconds))
    browser.js("meshfitView.setLayers({template: false, network: false, pairs: false, result: 0, curves: true})")
    with_curves = view_pixels(browser.screenshot(os.path.join(work, name + "-result.png")))
    browser.js("meshfitView.setLayers({curves: false})")
    without = view_pixels(browser.screenshot(os.path.join(work, name + "-result-nocurves.png")))
    share, h = not_blank(with_curves), hues(without)
    check(share > 0.05, "%s: result drawn (%.1f%% of the view)" % (name, 100 * share))
    check(h >= expect_hues, "%s: region colours (%d hues, want >= %d)" % (name, h, expect_hues))
    d1, d0 = dark(with_curves), dark(without)
    check(d1 > d0 + 200, "%s: curve edges drawn (%d dark pixels with them, %d without)" % (name, d1, d0))


def test_example(browser, meshfit, data, work, check):
    template, curves, pairs = (os.path.join(data, f) for f in ("template.off", "curves.polylines.txt", "pairs.txt"))
    html = fit_and_view(meshfit, template, curves, pairs, work, "example", check)
    if not html:
        return
    check_result_view(browser, html, "example", work, check, expect_hues=5)

    # Template and network, side by side, each drawn.
    browser.js("meshfitView.setLayers({template: true, network: false, pairs: false, result: -1})")
    t = view_pixels(browser.screenshot(os.path.join(work, "example-template.png")))
    check(not_blank(t) > 0.02 and hues(t) == 0, "example: template drawn, grey (%.1f%%)" % (100 * not_blank(t)))
    browser.js("meshfitView.setLayers({template: false, network: true})")
    n = view_pixels(browser.screenshot(os.path.join(work, "example-network.png")))
    check(crimson(n) > 300, "example: network curves drawn (%d crimson pixels)" % crimson(n))
    browser.js("meshfitView.setLayers({template: true, network: true, pairs: true, result: -1})")
    browser.screenshot(os.path.join(work, "example-pairs.png"))
    check(browser.js("meshfitView.warnings().length") == 0, "example: no warning for the example's 8 pairs")

    # Pick four pairs by clicking. The test's own pairs, by the rule examples/data/README.md gives
    # for pairs.txt (a network vertex goes with the icosphere vertex nearest to the normalised
    # (x/2, y/0.8, z/0.7)): among network vertices whose template vertex faces the camera (the
    # icosphere's normal is its position) and which have no other network vertex within 6 px on
    # the screen, four far apart and not coplanar.
    tv, _ = read_off(template)
    given = read_pairs(pairs)
    network_points = read_polylines(curves)
    screen = browser.js("[%s].map(p => meshfitView.screenOfPoint('network', p))" % ",".join(json.dumps(p) for p in network_points))
    def nearest(p):
        return min(range(len(tv)), key=lambda j: sum((tv[j][k] - p[k]) ** 2 for k in range(3)))
    candidates = []
    for q, target in zip(network_points, screen):
        d = (q[0] / 2, q[1] / 0.8, q[2] / 0.7)
        n = math.sqrt(sum(c * c for c in d))
        i = nearest([c / n for c in d])
        s = browser.js("meshfitView.screenOfPoint('template', %s)" % json.dumps(tv[i]))
        facing = sum(a * b for a, b in zip(tv[i], s["eye"])) / math.sqrt(sum(e * e for e in s["eye"])) > 0.3
        crowded = sum(1 for o in screen if (o["x"] - target["x"]) ** 2 + (o["y"] - target["y"]) ** 2 < 6 ** 2) > 1
        if facing and not crowded:
            candidates.append(((i,) + tuple(q), s, target))
    chosen = []
    while candidates and len(chosen) < 4:
        def spread_of(c):
            return min([sum((a - b) ** 2 for a, b in zip(c[0][1:], o[0][1:])) for o in chosen] or [0])
        best = max(candidates, key=spread_of) if chosen else candidates[0]
        candidates.remove(best)
        if len(chosen) == 3 and coplanar([c[0][1:] for c in chosen] + [best[0][1:]]):
            continue
        if all(best[0][0] != c[0][0] for c in chosen):
            chosen.append(best)
    if not check(len(chosen) == 4, "example: 4 pairs can be clicked in the default view (%d)" % len(chosen)):
        return
    chosen = chosen[:4]
    browser.js("document.getElementById('clear').click()")
    check(browser.js("meshfitView.pairs().length") == 0, "example: 'remove all' empties the list")
    for k, (pair, s, target) in enumerate(chosen):
        browser.click(s["x"], s["y"])
        browser.click(target["x"], target["y"])
        warned = any("at least 4" in w for w in browser.js("meshfitView.warnings()"))
        check(warned == (k + 1 < 4), "example: after %d picks, 'fewer than 4' warning %s" % (k + 1, "shown" if warned else "not shown"))
    downloads = os.path.join(work, "downloads")
    saved = os.path.join(downloads, "pairs.txt")
    if os.path.exists(saved):
        os.remove(saved)
    browser.js("document.getElementById('save').click()")
    deadline = time.time() + 20
    while not os.path.exists(saved) and time.time() < deadline:
        time.sleep(0.1)
    if not check(os.path.exists(saved), "example: 'save' downloads pairs.txt"):
        return
    time.sleep(0.3)
    got = read_pairs(saved)
    want = [c[0] for c in chosen]
    check(got == want, "example: the saved pairs are the clicked ones, coordinates exact\n       got  %s\n       want %s" % (got, want))
    fitted = os.path.join(work, "picked-fit.ply")
    r = run([meshfit, "fit", "--quiet", "--template", template, "--curves", curves, "--correspondences", saved,
             "--output", fitted])
    check(r.returncode == 0, "example: meshfit fit accepts the saved file and fits (%s)" % r.stderr.strip()[-300:])

    # Warnings against the test's own geometry: a mirrored set (each template vertex replaced by the
    # icosphere vertex nearest its mirror image in x = 0) and a coplanar set (pairs on one plane).
    mirror = [(nearest((-tv[i][0], tv[i][1], tv[i][2])), x, y, z) for (i, x, y, z) in given]
    sets = {"given": given, "mirror": mirror}
    flat = [p for p in given if p[3] == -0.25]  # the sole, z = -0.25
    if len(flat) >= 4:
        sets["coplanar"] = flat
    for label, ps in sets.items():
        path = os.path.join(work, "pairs-%s.txt" % label)
        with open(path, "w") as f:
            for (i, x, y, z) in ps:
                f.write("%d %r %r %r\n" % (i, x, y, z))
        page = os.path.join(work, "pairs-%s.html" % label)
        r = run([meshfit, "view", "--quiet", "--template", template, "--curves", curves, "--correspondences", path,
                 "--output", page])
        if not check(r.returncode == 0, "example: view of the %s pairs (%s)" % (label, r.stderr.strip())):
            continue
        browser.open(page)
        warnings = browser.js("meshfitView.warnings()")
        tp, np_ = [tv[p[0]] for p in ps], [p[1:] for p in ps]
        want_flat = coplanar(np_) or coplanar(tp)
        want_mirror = not want_flat and mirrored(tp, np_)
        got_flat, got_mirror = any("coplanar" in w for w in warnings), any("mirror" in w for w in warnings)
        check(got_flat == want_flat and got_mirror == want_mirror,
              "example: %s pairs: coplanar warning %s (expected %s), mirror warning %s (expected %s)"
              % (label, got_flat, want_flat, got_mirror, want_mirror))
        r = run([meshfit, "fit", "--quiet", "--template", template, "--curves", curves, "--correspondences", path,
                 "--output", os.path.join(work, "pairs-%s.ply" % label)])
        says_refused = any("refuses" in w for w in warnings)
        check(says_refused == (r.returncode != 0), "example: %s pairs: the page says fit refuses them: %s; meshfit fit "
              "exits %d" % (label, says_refused, r.returncode))
    check("mirror" in sets and mirrored([tv[p[0]] for p in mirror], [p[1:] for p in mirror]),
          "example: the mirrored set is mirrored by the test's own determinant")


def test_command_line(meshfit, data, work, check):
    template, curves, pairs = (os.path.join(data, f) for f in ("template.off", "curves.polylines.txt", "pairs.txt"))
    base = [meshfit, "view", "--quiet", "--template", template, "--curves", curves]
    page = os.path.join(work, "refused.html")
    if os.path.exists(page):
        os.remove(page)
    r = run(base + ["--result-report", pairs, "--result", template, "--output", page])
    check(r.returncode == 2 and "follows no --result" in r.stderr, "view: a --result-report before any --result is a usage error")
    r = run(base + ["--output", os.path.join(work, "page.txt")])
    check(r.returncode == 2 and ".html" in r.stderr, "view: an output that is not .html is a usage error")
    r = run([meshfit, "fit", "--template", template, "--curves", curves, "--correspondences", pairs, "--result", template,
             "--output", os.path.join(work, "x.ply")])
    check(r.returncode == 2, "fit: --result is refused")
    copy = os.path.join(work, "template-copy.html")
    shutil.copy(template, copy)
    r = run([meshfit, "view", "--quiet", "--template", copy, "--curves", curves, "--output", copy])
    with open(copy) as a, open(template) as b:
        same = a.read() == b.read()
    check(r.returncode == 1 and same, "view: an output equal to an input is refused and the input left as it was")
    bad = os.path.join(work, "pairs-bad.txt")
    with open(pairs) as f, open(bad, "w") as out:
        lines = f.read().splitlines()
        out.write("\n".join(lines[:2] + ["99999" + lines[2][lines[2].index(" "):]] + lines[3:]) + "\n")
    r = run(base + ["--correspondences", bad, "--output", page])
    check(r.returncode == 1 and "pairs-bad.txt:3" in r.stderr and "99999" in r.stderr and not os.path.exists(page),
          "view: a pair's missing template vertex names the line, and no page is left (%s)" % r.stderr.strip())
    r = run(base + ["--result", os.path.join(work, "missing.ply"), "--output", page])
    check(r.returncode == 1 and not os.path.exists(page), "view: a missing result is invalid input, no page is left")


def test_other_examples(browser, meshfit, data, cgal_meshes, work, check):
    sets = [("peanut", os.path.join(data, "template.off"), os.path.join(data, "curves-2.polylines.txt"),
             os.path.join(data, "pairs-2.txt"), 5),
            ("sheet", os.path.join(data, "sheet", "template.off"), os.path.join(data, "sheet", "curves.polylines.txt"),
             os.path.join(data, "sheet", "pairs.txt"), 3)]
    elephant = os.path.join(cgal_meshes or "", "elephant.off")
    if cgal_meshes and os.path.exists(elephant):
        sets.append(("elephant", elephant, os.path.join(data, "elephant", "curves.polylines.txt"),
                     os.path.join(data, "elephant", "pairs.txt"), 3))
    else:
        print("note: CGAL's elephant.off not given: the elephant example is not viewed")
    for name, template, curves, pairs, want_hues in sets:
        html = fit_and_view(meshfit, template, curves, pairs, work, name, check)
        if html:
            check_result_view(browser, html, name, work, check, expect_hues=want_hues)


def write_icosphere_ply(path, faces_wanted):
    """An icosphere of at least faces_wanted faces, patch_id = octant, as binary little-endian PLY."""
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    while len(f) < faces_wanted:
        mid = {}

        def m(a, b):
            key = (a, b) if a < b else (b, a)
            if key not in mid:
                p = [(v[a][k] + v[b][k]) / 2 for k in range(3)]
                n = math.sqrt(sum(x * x for x in p))
                v.append(tuple(x / n for x in p))
                mid[key] = len(v) - 1
            return mid[key]
        g = []
        for (a, b, c) in f:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            g += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = g
    with open(path, "wb") as out:
        out.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty double x\nproperty double y\n"
                   "property double z\nelement face %d\nproperty list uchar int vertex_indices\nproperty int patch_id\n"
                   "end_header\n" % (len(v), len(f))).encode())
        out.write(b"".join(struct.pack("<3d", *p) for p in v))
        face = struct.Struct("<B4i")
        for (a, b, c) in f:
            p = v[a]
            out.write(face.pack(3, a, b, c, (p[0] > 0) + 2 * (p[1] > 0) + 4 * (p[2] > 0)))
    return len(f)


def test_large(browser, meshfit, data, work, faces, check):
    ply = os.path.join(work, "large.ply")
    n = write_icosphere_ply(ply, faces)
    curves = os.path.join(work, "large.polylines.txt")
    with open(curves, "w") as f:  # the three great circles between the octants
        for axis in range(3):
            pts = []
            for k in range(257):
                a = 2 * math.pi * k / 256
                p = [0.0, 0.0, 0.0]
                p[(axis + 1) % 3], p[(axis + 2) % 3] = math.cos(a), math.sin(a)
                pts.append(p if k < 256 else pts[0])
            f.write("%d %s\n" % (len(pts), " ".join("%r %r %r" % tuple(p) for p in pts)))
    html = os.path.join(work, "large.html")
    start = time.time()
    r = run([meshfit, "view", "--quiet", "--template", ply, "--curves", curves, "--result", ply, "--output", html])
    written = time.time() - start
    if not check(r.returncode == 0, "large: meshfit view exits 0 (%s)" % r.stderr.strip()):
        return
    seconds = browser.open(html)
    check(not browser.exceptions(), "large: no script error")
    print("     large: %d faces (template and result), page %.1f MB written in %.2f s, ready in %.2f s (page's own "
          "script %.2f s)" % (n, os.path.getsize(html) / 1e6, written, seconds, browser.js("meshfitView.loadMs") / 1000))
    browser.js("meshfitView.setLayers({template: false, network: false, pairs: false, result: 0})")
    full = browser.js("meshfitView.orbitBenchmark(2, false)")
    turning = browser.js("meshfitView.orbitBenchmark(10, true)")
    print("     large: software rendering (SwiftShader, %d cores): %.0f ms per frame in full, %.0f ms per frame while "
          "turning" % (os.cpu_count(), full, turning))
    pixels = view_pixels(browser.screenshot(os.path.join(work, "large.png")))
    check(not_blank(pixels) > 0.05 and hues(pixels) >= 4, "large: result drawn in region colours")
    notices = browser.js("meshfitView.notices")
    check(any("while the view turns" in x for x in notices), "large: the page says it turns a decimated copy: %s" % notices)
    seconds = browser.open(html, "?maxfaces=200000")
    notices = browser.js("meshfitView.notices")
    check(any("decimated" in x for x in notices), "large: with ?maxfaces=200000 the page says it shows a decimated mesh")
    browser.js("meshfitView.setLayers({template: false, network: false, pairs: false, result: 0})")
    ms = browser.js("meshfitView.orbitBenchmark(5, false)")
    pixels = view_pixels(browser.screenshot(os.path.join(work, "large-decimated.png")))
    check(not_blank(pixels) > 0.05 and hues(pixels) >= 4, "large: decimated result drawn in region colours (ready in "
          "%.2f s, orbit %.1f ms per frame)" % (seconds, ms))


def main():
    a = argparse.ArgumentParser()
    a.add_argument("--meshfit", required=True)
    a.add_argument("--data", required=True)
    a.add_argument("--work", required=True)
    a.add_argument("--cgal-meshes")
    a.add_argument("--large", type=int)
    a.add_argument("--chromium", default=shutil.which("chromium") or "/usr/bin/chromium")
    args = a.parse_args()
    if not os.path.exists(args.chromium):
        print("SKIPPED: Chromium not found (%s); install Debian's chromium to run the browser tests" % args.chromium)
        return 77
    os.makedirs(os.path.join(args.work, "downloads"), exist_ok=True)
    checker = Checker()
    profile = tempfile.mkdtemp(prefix="meshfit-chromium-")
    browser = Browser(args.chromium, profile, os.path.abspath(os.path.join(args.work, "downloads")))
    try:
        if args.large:
            test_large(browser, args.meshfit, args.data, args.work, args.large, checker.check)
        else:
            test_command_line(args.meshfit, args.data, args.work, checker.check)
            test_example(browser, args.meshfit, args.data, args.work, checker.check)
            test_other_examples(browser, args.meshfit, args.data, args.cgal_meshes, args.work, checker.check)
    except Exception as e:  # a broken page or browser is a failure, reported
        checker.check(False, "error: %r" % e)
    finally:
        browser.close()
        shutil.rmtree(profile, ignore_errors=True)
    print("%d passed, %d failed" % (checker.passes, checker.failures))
    return 1 if checker.failures else 0


if __name__ == "__main__":
    sys.exit(main())
