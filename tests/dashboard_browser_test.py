#!/usr/bin/python3
"""ctest: the history page (`suite history html`) in a real browser, Debian's chromium, headless.

The fixture program writes the page of a synthetic history (tests/results/synthetic_series.hpp)
and of an empty one; chromium opens each from file:// and is driven over the DevTools protocol
on a pipe (--remote-debugging-pipe: no port, standard library only), so that every console
message, uncaught exception and request is seen exactly. Checked: no console error, no
exception, no request that leaves file://; every chart drawn (the page sets data-drawn to the
number of canvases that show their medians); a label that tries to close the script element
stays text; every chart (each has 24 runs) draws the gate's runs' band over the last 10 runs, its
caption giving the band and the spread in percent; the machine, kernel and steps filters show
the right cards; the empty page says so.
The screenshot is kept as OUT_DIR/screenshot.png for a person to look at.

chromium is installed by scripts/install-deps.sh test: without it this test fails, saying so.

usage: dashboard_browser_test.py FIXTURE OUT_DIR     exit 0 clean, 1 with one line per problem
"""
import base64
import json
import os
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time

SERIES = 6  # charted: synthetic_history() and the spread one of tests/browser/dashboard_fixture.cpp (its zero counter is not)
RUNS, WINDOW = 24, 10  # its runs a series; DashboardOptions::window, the runs the band is drawn over
WIDTH, HEIGHT = 1280, 900
problems = []


def check(cond, message):
    if not cond:
        problems.append(message)


class Browser:
    """One headless chromium, spoken to over fds 3 (commands in) and 4 (replies and events out),
    each message a JSON object ended by a NUL byte."""

    def __init__(self, binary, profile, log_path):
        to_browser, self.commands = os.pipe()
        self.replies, from_browser = os.pipe()
        log = os.open(log_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        args = [binary, "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--remote-debugging-pipe", "--user-data-dir=" + profile,
                "--no-first-run", "--no-default-browser-check", "--disable-extensions", "--disable-background-networking",
                "--disable-component-update", "--disable-sync", "--mute-audio", "--hide-scrollbars", "about:blank"]
        self.pid = os.posix_spawn(binary, args, os.environ, file_actions=[
            (os.POSIX_SPAWN_OPEN, 0, "/dev/null", os.O_RDONLY, 0),
            (os.POSIX_SPAWN_DUP2, log, 1), (os.POSIX_SPAWN_DUP2, log, 2),
            (os.POSIX_SPAWN_DUP2, to_browser, 3), (os.POSIX_SPAWN_DUP2, from_browser, 4)])
        for fd in (to_browser, from_browser, log):
            os.close(fd)
        self.buffer, self.events, self.last_id, self.session = b"", [], 0, None

    def _read(self, deadline):
        while b"\0" not in self.buffer:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([self.replies], [], [], left)[0]:
                raise TimeoutError("chromium did not answer in time")
            chunk = os.read(self.replies, 1 << 20)
            if not chunk:
                raise EOFError("chromium closed its DevTools pipe (did it crash? see chromium.log)")
            self.buffer += chunk
        message, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(message)

    def call(self, method, params=None, timeout=30, browser_level=False):
        self.last_id += 1
        message = {"id": self.last_id, "method": method, "params": params or {}}
        if self.session and not browser_level:
            message["sessionId"] = self.session
        data = json.dumps(message).encode() + b"\0"
        while data:
            data = data[os.write(self.commands, data):]
        deadline = time.monotonic() + timeout
        while True:
            reply = self._read(deadline)
            if reply.get("id") == self.last_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def wait_event(self, method, timeout=30):
        deadline = time.monotonic() + timeout
        while True:
            for i, event in enumerate(self.events):
                if event.get("method") == method:
                    return self.events.pop(i)
            self.events.append(self._read(deadline))

    def evaluate(self, expression):
        result = self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True, "awaitPromise": True})
        if "exceptionDetails" in result:
            raise RuntimeError(f"{expression[:60]}...: {result['exceptionDetails'].get('text')}")
        return result["result"].get("value")

    def open_tab(self):
        target = self.call("Target.createTarget", {"url": "about:blank"}, browser_level=True)["targetId"]
        self.session = self.call("Target.attachToTarget", {"targetId": target, "flatten": True}, browser_level=True)["sessionId"]
        for domain in ("Runtime", "Log", "Page", "Network"):
            self.call(domain + ".enable")
        self.resize(HEIGHT)

    def resize(self, height):
        self.call("Emulation.setDeviceMetricsOverride", {"width": WIDTH, "height": height, "deviceScaleFactor": 1, "mobile": False})

    def load(self, path, timeout=30):
        self.events.clear()
        self.call("Page.navigate", {"url": "file://" + os.path.abspath(path)})
        self.wait_event("Page.loadEventFired", timeout)

    def close(self):
        try:
            self.call("Browser.close", browser_level=True, timeout=5)
        except (TimeoutError, EOFError, RuntimeError):
            pass
        for _ in range(50):
            if os.waitpid(self.pid, os.WNOHANG)[0]:
                return
            time.sleep(0.1)
        os.kill(self.pid, signal.SIGKILL)
        os.waitpid(self.pid, 0)


def console_problems(events, page):
    """Errors the page caused: console.error/assert, uncaught exceptions, error log entries, and
    any request that is not for a local file (the page must work without a network)."""
    found = []
    for e in events:
        method, params = e.get("method"), e.get("params", {})
        if method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            found.append("console." + params["type"] + ": " + " ".join(str(a.get("value", a.get("description"))) for a in params.get("args", [])))
        elif method == "Runtime.exceptionThrown":
            d = params.get("exceptionDetails", {})
            found.append("uncaught: " + d.get("exception", {}).get("description", d.get("text", "?")))
        elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
            found.append("log: " + params["entry"].get("text", "") + " " + params["entry"].get("url", ""))
        elif method == "Network.requestWillBeSent":
            url = params.get("request", {}).get("url", "")
            if not url.startswith(("file://", "data:")):
                found.append("a request off the machine: " + url)
    return [f"{page}: {f}" for f in found]


def wait_drawn(browser, timeout=20):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        state = browser.evaluate("({drawn: document.body.dataset.drawn ?? null, charts: document.body.dataset.charts ?? null,"
                                 " failed: document.body.dataset.failed || ''})")
        if state["drawn"] is not None or state["failed"]:
            return state
        time.sleep(0.1)
    return {"drawn": None, "charts": None, "failed": f"data-drawn was not set within {timeout} s"}


# For each chart: the runs' band's datasets (Chart.js's own record of what it drew), how many of
# their points lie on the plot, whether the dashed centre line's colour (#b35c00) is on the
# canvas, and the card's caption of the band.
GATE_BANDS = """[...document.querySelectorAll("article.card")].map((card) => {
  const canvas = card.querySelector("canvas"), chart = Chart.getChart(canvas);
  const sets = chart.data.datasets.map((d, i) => ({d, i})).filter(({d}) => String(d.label || "").startsWith("runs' band"));
  const drawn = sets.map(({i}) => chart.isDatasetVisible(i) ?
      chart.getDatasetMeta(i).data.filter((p) => !p.skip && isFinite(p.y) && p.y >= chart.chartArea.top && p.y <= chart.chartArea.bottom).length : 0);
  const px = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
  let centre = false;
  for (let i = 0; i < px.length && !centre; i += 4)
    centre = px[i + 3] > 120 && Math.abs(px[i] - 179) < 30 && Math.abs(px[i + 1] - 92) < 30 && px[i + 2] < 40;
  return {sets: sets.length, drawn, centre, caption: (card.querySelector("p.gate") || {}).textContent || ""};
})"""

# Sets the filters and returns how many cards and machine headings are visible.
FILTER = """(function (machineIndex, kernel, stepsOnly) {
  const machine = document.getElementById("machine");
  machine.value = machineIndex < 0 ? "" : machine.options[machineIndex + 1].value;
  document.getElementById("kernel").value = kernel;
  document.getElementById("steps-only").checked = stepsOnly;
  machine.dispatchEvent(new Event("change"));
  const visible = (sel) => [...document.querySelectorAll(sel)].filter((e) => e.offsetParent !== null).length;
  return {cards: visible("article.card"), machines: visible("section.machine"), shown: document.body.dataset.shown,
          text: document.getElementById("shown").textContent};
})"""


def check_full_page(browser, page_dir, screenshot):
    browser.load(os.path.join(page_dir, "index.html"))
    state = wait_drawn(browser)
    check(not state["failed"], f"the page reports a failure: {state['failed']}")
    check(state["charts"] == str(SERIES), f"{state['charts']} charts on the page, {SERIES} series in the fixture")
    check(state["drawn"] == str(SERIES), f"{state['drawn']} of {SERIES} charts drawn (a canvas without its medians' colour is blank)")
    if state["failed"] or state["drawn"] is None:
        return console_problems(browser.events, "page")  # the filters and the picture would only repeat it
    facts = browser.evaluate("""({title: document.title, canvases: document.querySelectorAll("canvas").length,
        injected: document.querySelectorAll("main script").length,
        steps: [...document.querySelectorAll(".steps li")].map((li) => li.textContent),
        contexts: [...document.querySelectorAll(".meta")].map((p) => p.textContent)})""")
    check(facts["title"] == "suite history (synthetic)", f"the title is {facts['title']!r}: a label's markup ran")
    check(facts["injected"] == 0, "a label's <script> became an element")
    check(any("</script>" in c for c in facts["contexts"]), "the hostile context is not shown as text")
    check(len(facts["steps"]) == 4, f"{len(facts['steps'])} steps listed, 4 in the fixture: {facts['steps']}")
    check(any(s.startswith("step at ") and "-15.0 %, worse" in s for s in facts["steps"]), f"no '-15.0 %, worse' step: {facts['steps']}")
    bands = browser.evaluate(GATE_BANDS)
    check(len(bands) == SERIES, f"{len(bands)} cards checked for the runs' band, {SERIES} series")
    for i, b in enumerate(bands):
        check(b["sets"] == 3 and b["drawn"] == [WINDOW] * 3,
              f"chart {i} ({RUNS} runs): the runs' band is {b['sets']} datasets with {b['drawn']} points on the plot, "
              f"expected its edges and centre over the last {WINDOW} runs")
        check(b["centre"], f"chart {i}: no pixel of the band's dashed centre line")
        check(b["caption"].startswith(f"runs' band: the gate's band (last {WINDOW} runs): ") and "runs' spread" in b["caption"]
              and b["caption"].endswith(" %"), f"chart {i}: the caption does not give the band and its spread: {b['caption']!r}")
    # No axis below 0, even where a run's repetitions spread past its median; the counter that
    # is 0 in every run is named once and has no chart.
    axes = browser.evaluate("""[...document.querySelectorAll("article.card canvas")].map((c) => Chart.getChart(c).scales.y.min)""")
    check(all(y >= 0 for y in axes), f"a chart's axis goes below 0: {axes}")
    zero = browser.evaluate("(document.getElementById('all-zero') || {}).textContent || ''")
    check("add random" in zero and "counter major-faults" in zero and "0 in every run" in zero,
          f"the counter that is 0 in every run is not listed once: {zero!r}")
    legend = browser.evaluate("document.querySelector('.legend').textContent")
    check("repetitions' spread" in legend and f"the gate's band (last {WINDOW} runs)" in legend,
          f"the legend does not tell the repetitions' spread from the runs' band: {legend!r}")
    # Machine B has two series; two series are of kernel add; three have a step.
    for args, cards, machines in (("1, '', false", 2, 1), ("-1, 'add', false", 2, 1), ("-1, '', true", 3, 2), ("0, 'triad', true", 0, 0),
                                  ("-1, '', false", SERIES, 2)):
        got = browser.evaluate(FILTER + f"({args})")
        check(got["cards"] == cards and got["machines"] == machines and got["shown"] == str(cards),
              f"filter ({args}): {got['cards']} cards on {got['machines']} machines shown ({got['text']!r}), expected {cards} on {machines}")
    # The whole page in one picture: the viewport as tall as the content, then a frame to redraw.
    height = int(browser.call("Page.getLayoutMetrics")["cssContentSize"]["height"])
    browser.resize(min(max(height, HEIGHT), 6000))
    browser.evaluate("new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))")
    png = base64.b64decode(browser.call("Page.captureScreenshot", {"format": "png"})["data"])
    with open(screenshot, "wb") as f:
        f.write(png)
    check(png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 30_000, f"the screenshot is not a plausible PNG ({len(png)} bytes)")
    browser.resize(HEIGHT)
    return console_problems(browser.events, "page")


def check_empty_page(browser, page_dir):
    browser.load(os.path.join(page_dir, "index.html"))
    facts = browser.evaluate("""({empty: (document.getElementById("empty") || {}).textContent || "",
        canvases: document.querySelectorAll("canvas").length})""")
    check(facts["empty"].startswith("The history is empty"), f"the empty page does not say so: {facts['empty']!r}")
    check(facts["canvases"] == 0, f"the empty page has {facts['canvases']} canvases")
    return console_problems(browser.events, "empty page")


def main():
    if len(sys.argv) != 3:
        print(__doc__.strip().splitlines()[-1].strip(), file=sys.stderr)
        return 2
    fixture, out = sys.argv[1], sys.argv[2]
    started = time.monotonic()
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if not chromium:
        print("dashboard_browser_test: FAIL: chromium is not installed, so the history page cannot be checked in a browser; "
              "install it with scripts/install-deps.sh test (Debian's chromium)")
        return 1
    os.makedirs(out, exist_ok=True)
    page, empty = os.path.join(out, "page"), os.path.join(out, "empty")
    for args in ([fixture, page], [fixture, empty, "--empty"]):
        r = subprocess.run(args, capture_output=True, text=True, timeout=60)
        if r.returncode != 0:
            print(f"dashboard_browser_test: FAIL: {' '.join(args)} exited {r.returncode}: {r.stderr.strip()}")
            return 1
    screenshot = os.path.join(out, "screenshot.png")
    with tempfile.TemporaryDirectory(prefix="suite-chromium-") as profile:
        log = os.path.join(out, "chromium.log")
        browser = Browser(chromium, profile, log)
        try:
            browser.open_tab()
            errors = check_full_page(browser, page, screenshot) + check_empty_page(browser, empty)
        except (TimeoutError, EOFError, RuntimeError) as e:
            errors = [f"driving chromium failed: {e} (its log: {log})"]
        finally:
            browser.close()
    problems.extend(errors)
    for p in problems:
        print("dashboard_browser_test: " + p)
    print(f"dashboard_browser_test: {SERIES} charts and the empty page checked in {os.path.basename(chromium)} in "
          f"{time.monotonic() - started:.1f} s, {len(problems)} problem(s); screenshot: {screenshot}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
