#!/usr/bin/env python3
"""report.html in headless Chromium (issue 17): runs a short scenario with the
built `pavilion`, opens its report.html offline in Debian's chromium driven over
the DevTools protocol, and fails on any console error, uncaught exception, error
log entry, failed request or request off the page's own file; on a canvas
without a chart or a chart whose datasets drew nothing; and on a page without
the charts the scenario must give. Saves a full-page screenshot.

Python 3 standard library only (a minimal WebSocket client below).

Usage: report_browser_test.py --pavilion BIN --work DIR
                              [--screenshot FILE] [--report FILE] [--chromium BIN]
--report skips the run and checks an existing report.html.
"""
import argparse
import base64
import json
import os
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time
import urllib.parse
import urllib.request

# The run: the office floor with a few visitors, one errand robot localizing
# with the laser, a shove and a kidnap that make it lose track: every chart of
# the report gets data in 25 simulated seconds.
SCENARIO = """\
kind: scenario
name: browser_report
description: >-
  The report's browser test: Pygmalion runs errands on the office floor among a
  few visitors, is shoved and kidnapped (its localization loses track).
world: office_floor
seed: 3
duration_s: 25
physics:
  rate_hz: 200
materials:
  visitor:
    friction: 0.6
    color: [0.85, 0.55, 0.35]
crowd:
  present: 6
  max_present: 8
  arrivals_per_hour: 120
  material: visitor
  entrance: [[23.6, 15.1], [24.9, 15.1], [24.9, 16.4], [23.6, 16.4]]
  exit: [[23.6, 15.1], [24.9, 15.1], [24.9, 16.4], [23.6, 16.4]]
  watch_spots: 0
  visit: {min_exhibits: 1, max_exhibits: 2, visit_mean_s: 60, visit_std_s: 10,
          group_fraction: 0}
outputs:
  trajectory_rate_hz: 2
  scan_log: false
robots:
  - id: pygmalion
    model: pygmalion
    pose: [7.0, 7.25, 0.0]
    localization:
      rate_hz: 2
      initial_sigma: [0.01, 0.01, 0.01]
    mission:
      stations: [lab, office_03, mail_room]
      dwell_s: 1
      timeout_s: 60
      max_speed_mps: 0.4
events:
  - {at_s: 8, type: push, body: pygmalion, impulse: [30, 10]}
  - {at_s: 15, type: kidnap, robot: pygmalion, pose: [9.0, 7.25, 0.5]}
"""

# Charts the run must give, by their heading on the page.
REQUIRED_HEADINGS = ("Localization of pygmalion", "Visitors present", "Missions",
                     "Events over time", "Top-down view")
# A dataset "drew" when hiding the datasets changes at least this many pixels.
MIN_CHANGED_PIXELS = 30


class Failure(Exception):
    pass


class WebSocket:
    """A WebSocket client (RFC 6455) for the DevTools protocol: text frames only."""

    def __init__(self, url, timeout_s=60.0):
        parts = urllib.parse.urlparse(url)
        self.sock = socket.create_connection((parts.hostname, parts.port), timeout=timeout_s)
        key = base64.b64encode(os.urandom(16)).decode()
        request = (f"GET {parts.path} HTTP/1.1\r\nHost: {parts.hostname}:{parts.port}\r\n"
                   "Upgrade: websocket\r\nConnection: Upgrade\r\n"
                   f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n")
        self.sock.sendall(request.encode())
        response = b""
        while b"\r\n\r\n" not in response:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise Failure("DevTools closed the connection during the WebSocket handshake")
            response += chunk
        head, self.buffer = response.split(b"\r\n\r\n", 1)
        if b" 101 " not in head.split(b"\r\n", 1)[0]:
            raise Failure("DevTools refused the WebSocket: " + head.decode(errors="replace"))

    def _read(self, n):
        while len(self.buffer) < n:
            chunk = self.sock.recv(1 << 16)
            if not chunk:
                raise Failure("DevTools closed the WebSocket")
            self.buffer += chunk
        data, self.buffer = self.buffer[:n], self.buffer[n:]
        return data

    def _send_frame(self, opcode, payload):
        header = bytes([0x80 | opcode])
        n = len(payload)
        if n < 126:
            header += bytes([0x80 | n])
        elif n < 1 << 16:
            header += bytes([0x80 | 126]) + struct.pack(">H", n)
        else:
            header += bytes([0x80 | 127]) + struct.pack(">Q", n)
        mask = os.urandom(4)
        masked = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        self.sock.sendall(header + mask + masked)

    def send(self, text):
        self._send_frame(0x1, text.encode())

    def receive(self):
        """The next whole text message (continuations joined; pings answered)."""
        message = b""
        while True:
            b0, b1 = self._read(2)
            opcode, n = b0 & 0x0F, b1 & 0x7F
            if n == 126:
                n = struct.unpack(">H", self._read(2))[0]
            elif n == 127:
                n = struct.unpack(">Q", self._read(8))[0]
            mask = self._read(4) if b1 & 0x80 else None
            payload = self._read(n)
            if mask:
                payload = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
            if opcode == 0x8:
                raise Failure("DevTools closed the WebSocket")
            if opcode == 0x9:
                self._send_frame(0xA, payload)
                continue
            if opcode in (0x0, 0x1, 0x2):
                message += payload
                if b0 & 0x80:
                    return message.decode()

    def close(self):
        try:
            self._send_frame(0x8, b"")
        except OSError:
            pass
        self.sock.close()


class DevTools:
    """Commands to one page; every event that arrives is kept in `events`."""

    def __init__(self, ws):
        self.ws = ws
        self.next_id = 0
        self.events = []

    def call(self, method, timeout_s=60.0, **params):
        self.next_id += 1
        self.ws.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            message = json.loads(self.ws.receive())
            if message.get("id") == self.next_id:
                if "error" in message:
                    raise Failure(f"{method}: {message['error']}")
                return message.get("result", {})
            if "method" in message:
                self.events.append(message)
        raise Failure(f"{method}: no answer within {timeout_s} s")

    def wait_for(self, method, timeout_s=60.0):
        if any(e["method"] == method for e in self.events):
            return
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            message = json.loads(self.ws.receive())
            if "method" in message:
                self.events.append(message)
                if message["method"] == method:
                    return
        raise Failure(f"no {method} within {timeout_s} s")

    def evaluate(self, expression, timeout_s=60.0):
        result = self.call("Runtime.evaluate", timeout_s=timeout_s, expression=expression,
                           awaitPromise=True, returnByValue=True)
        if "exceptionDetails" in result:
            raise Failure("evaluation failed: " + json.dumps(result["exceptionDetails"])[:2000])
        return result["result"].get("value")


def find_chromium(given):
    for candidate in ([given] if given else []) + [os.environ.get("PAVILION_CHROMIUM"),
                                                  "/usr/bin/chromium", shutil.which("chromium"),
                                                  shutil.which("chromium-browser")]:
        if candidate and os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return candidate
    raise Failure("chromium not found: the browser test needs Debian's chromium "
                  "(apt-get install chromium; `make test` installs it)")


def run_scenario(pavilion, work):
    scenario = os.path.join(work, "browser_report.yaml")
    with open(scenario, "w") as f:
        f.write(SCENARIO)
    out = os.path.join(work, "run")
    shutil.rmtree(out, ignore_errors=True)
    env = dict(os.environ, CI="1")
    started = time.monotonic()
    proc = subprocess.run([pavilion, "run", scenario, "--out", out], env=env,
                          capture_output=True, text=True, timeout=600)
    if proc.returncode != 0:
        raise Failure(f"pavilion run exited {proc.returncode}: {proc.stderr[-2000:]}")
    print(f"pavilion run: {time.monotonic() - started:.1f} s")
    return os.path.join(out, "report.html")


def start_chromium(chromium, profile):
    args = [chromium, "--headless=new", "--no-sandbox", "--disable-gpu",
            "--remote-debugging-port=0", f"--user-data-dir={profile}", "--no-first-run",
            "--no-default-browser-check", "--disable-extensions", "--disable-sync",
            "--disable-background-networking", "--disable-component-update", "--mute-audio",
            "--hide-scrollbars", "--window-size=1100,900", "about:blank"]
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            start_new_session=True)
    port_file = os.path.join(profile, "DevToolsActivePort")
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise Failure(f"chromium exited {proc.returncode}: "
                          + proc.stderr.read().decode(errors="replace")[-2000:])
        if os.path.exists(port_file):
            with open(port_file) as f:
                lines = f.read().split()
            if lines:
                return proc, int(lines[0])
        time.sleep(0.1)
    raise Failure("chromium did not open its DevTools port within 60 s")


def stop_chromium(proc):
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)  # the session started for it alone
            proc.wait()


def page_socket(port):
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10) as r:
            targets = json.load(r)
        pages = [t for t in targets if t.get("type") == "page" and "webSocketDebuggerUrl" in t]
        if pages:
            return pages[0]["webSocketDebuggerUrl"]
        time.sleep(0.2)
    raise Failure("chromium shows no page target")


# Per canvas: its chart, the pixels it drew, and how many change when its
# datasets are hidden (the data really drew).
CHECK_CANVASES = r"""
(async () => {
  const frame = () => new Promise((r) => requestAnimationFrame(() => r()));
  await frame(); await frame();
  const pixels = (c) => c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  // The section heading a canvas is under.
  const heading = (c) => {
    for (let e = c.closest('div'); e; e = e.previousElementSibling) {
      if (e.tagName === 'H2') return e.textContent;
    }
    return '';
  };
  const out = [];
  for (const c of document.querySelectorAll('canvas')) {
    const chart = (typeof Chart !== 'undefined') ? Chart.getChart(c) : undefined;
    const shown = pixels(c);
    let drawn = 0;
    for (let i = 3; i < shown.length; i += 4) if (shown[i] !== 0) drawn++;
    const entry = { id: c.id, width: c.width, height: c.height, drawn, chart: !!chart,
                    points: chart ? chart.data.datasets.map((d) => d.data.length) : [],
                    heading: heading(c) };
    if (chart) {
      chart.data.datasets.forEach((d, i) => chart.setDatasetVisibility(i, false));
      chart.update('none');
      const hidden = pixels(c);
      let changed = 0;
      for (let i = 0; i < shown.length; i += 4) {
        if (shown[i] !== hidden[i] || shown[i + 1] !== hidden[i + 1] ||
            shown[i + 2] !== hidden[i + 2] || shown[i + 3] !== hidden[i + 3]) changed++;
      }
      chart.data.datasets.forEach((d, i) => chart.setDatasetVisibility(i, true));
      chart.update('none');
      entry.data_pixels = changed;
    }
    out.push(entry);
  }
  await frame();
  return JSON.stringify({
    canvases: out,
    headings: [...document.querySelectorAll('h2')].map((h) => h.textContent),
    height: document.documentElement.scrollHeight
  });
})()
"""


def problems_in_events(events, page_url):
    """Console errors, exceptions, error log entries and failed or foreign requests."""
    problems = []
    for e in events:
        method, p = e["method"], e.get("params", {})
        if method == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            text = " ".join(str(a.get("value", a.get("description", ""))) for a in p.get("args", []))
            problems.append(f"console.{p['type']}: {text}")
        elif method == "Runtime.consoleAPICalled" and p.get("type") == "warning":
            print("console warning (not a failure):",
                  " ".join(str(a.get("value", "")) for a in p.get("args", [])))
        elif method == "Runtime.exceptionThrown":
            d = p.get("exceptionDetails", {})
            problems.append("uncaught exception: "
                            + d.get("exception", {}).get("description", d.get("text", "")))
        elif method == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
            problems.append("log error: " + p["entry"].get("text", "") + " "
                            + p["entry"].get("url", ""))
        elif method == "Network.loadingFailed":
            problems.append(f"request failed: {p.get('errorText')} ({p.get('type')})")
        elif method == "Network.responseReceived" and p.get("response", {}).get("status", 200) >= 400:
            problems.append(f"HTTP {p['response']['status']}: {p['response'].get('url')}")
        elif method == "Network.requestWillBeSent":
            url = p.get("request", {}).get("url", "")
            if not (url == page_url or url.startswith("data:")):
                problems.append("request off the self-contained page: " + url[:200])
    return problems


def check_canvases(report, required_headings):
    problems = []
    for c in report["canvases"]:
        name = f"canvas {c['id']} ({c['heading'].strip() or 'no heading'})"
        if not c["chart"]:
            problems.append(f"{name}: no chart")
        elif not any(c["points"]):
            problems.append(f"{name}: no data points")
        elif c.get("data_pixels", 0) < MIN_CHANGED_PIXELS:
            problems.append(f"{name}: its datasets drew {c.get('data_pixels', 0)} pixels")
        if c["drawn"] == 0:
            problems.append(f"{name}: blank")
        print(f"  {name}: {c['width']}x{c['height']} px, {c['drawn']} drawn, "
              f"{c.get('data_pixels', 0)} by its data, points {c['points']}")
    for heading in required_headings:
        if not any(h.startswith(heading) for h in report["headings"]) or not any(
                c["heading"].startswith(heading) for c in report["canvases"]):
            problems.append(f"no chart under a heading '{heading}'")
    return problems


def screenshot(tools, height, path):
    tools.call("Emulation.setDeviceMetricsOverride", width=1100, height=min(int(height), 16000),
               deviceScaleFactor=1, mobile=False)
    tools.evaluate("new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)))"
                   ".then(() => true)")
    shot = tools.call("Page.captureScreenshot", timeout_s=120, format="png",
                      captureBeyondViewport=True)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "wb") as f:
        f.write(base64.b64decode(shot["data"]))
    print("screenshot:", path)


def check_report(chromium, report_html, screenshot_path, required_headings):
    page_url = "file://" + os.path.abspath(report_html)
    profile = tempfile.mkdtemp(prefix="pavilion-chromium-")
    proc = None
    try:
        proc, port = start_chromium(chromium, profile)
        tools = DevTools(WebSocket(page_socket(port)))
        for domain in ("Runtime", "Log", "Network", "Page"):
            tools.call(domain + ".enable")
        tools.call("Page.navigate", url=page_url)
        tools.wait_for("Page.loadEventFired")
        report = json.loads(tools.evaluate(CHECK_CANVASES))
        if screenshot_path:
            screenshot(tools, report["height"], screenshot_path)
        tools.call("Runtime.evaluate", expression="1")  # collect late events
        problems = (check_canvases(report, required_headings)
                    + problems_in_events(tools.events, page_url))
        tools.ws.close()
        return problems
    finally:
        if proc:
            stop_chromium(proc)
        shutil.rmtree(profile, ignore_errors=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pavilion", help="the built pavilion binary")
    parser.add_argument("--work", default=tempfile.gettempdir(), help="folder for the run")
    parser.add_argument("--screenshot", help="where to save the page's screenshot (PNG)")
    parser.add_argument("--report", help="check this report.html instead of running")
    parser.add_argument("--chromium", help="the chromium binary")
    args = parser.parse_args()
    started = time.monotonic()
    try:
        chromium = find_chromium(args.chromium)
        if args.report:
            report_html = args.report
        else:
            if not args.pavilion:
                raise Failure("--pavilion or --report is required")
            os.makedirs(args.work, exist_ok=True)
            report_html = run_scenario(args.pavilion, args.work)
        # The charts the test's own run must give; any report: every chart draws.
        required = () if args.report else REQUIRED_HEADINGS
        problems = check_report(chromium, report_html, args.screenshot, required)
    except Failure as e:
        problems = [str(e)]
    print(f"browser test: {time.monotonic() - started:.1f} s")
    if problems:
        for p in problems:
            print("FAIL:", p)
        return 1
    print("PASS: report.html draws every chart without an error")
    return 0


if __name__ == "__main__":
    sys.exit(main())
