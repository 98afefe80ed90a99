"""A real browser for the tests of ``kincalc view``'s page: headless Chromium, driven
through the DevTools protocol on a pipe (``--remote-debugging-pipe``), standard library
only.

    with Browser() as browser:
        tab = browser.tab()
        tab.open(Path("arm.html"))
        tab.eval("document.title")
        tab.screenshot(Path("arm.png"))
        tab.problems()          # console errors, uncaught exceptions, network requests

A tab drives the page as a user does (set a slider and fire its ``input`` event, click a
radio button, drag with the mouse) and reads what the page shows. ``.ci/run`` installs
Chromium (Debian's ``chromium`` package) when it is missing; where no browser is
installed the tests that need one are skipped, saying why (:data:`SKIP`).
"""

from __future__ import annotations

import base64
import fcntl
import json
import os
import select
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import pytest

#: the browsers tried, in order (Debian and Ubuntu name Chromium differently)
NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
#: the viewport pages are shown in (CSS pixels, device scale 1)
WINDOW = (1280, 860)
#: how long the browser may take to answer one command, s
TIMEOUT = 30


def find_browser() -> str | None:
    """The path of a Chromium-family browser, or None."""
    for name in NAMES:
        path = shutil.which(name)
        if path:
            return path
    return None


BROWSER = find_browser()
SKIP = None if BROWSER else (
    "no Chromium on this machine (looked for " + ", ".join(NAMES) + "): the page's browser "
    "tests need one; .ci/run installs it (apt-get install chromium)")


class BrowserError(RuntimeError):
    """The browser answered a command with an error, or not in time."""


class Browser:
    """One headless Chromium process; :meth:`tab` opens pages in it."""

    def __init__(self):
        if BROWSER is None:
            pytest.skip(SKIP)
        self._profile = tempfile.TemporaryDirectory(prefix="kincalc-browser-")
        to_browser, self._out = os.pipe()          # commands: we write, it reads fd 3
        self._in, from_browser = os.pipe()         # answers: it writes fd 4, we read

        def pipes():
            # in the child, before exec: the pipe ends become fds 3 and 4 (moved out of
            # the way first, so that neither is overwritten by the other's dup2)
            read_end = fcntl.fcntl(to_browser, fcntl.F_DUPFD, 10)
            write_end = fcntl.fcntl(from_browser, fcntl.F_DUPFD, 10)
            os.dup2(read_end, 3)
            os.dup2(write_end, 4)

        self.process = subprocess.Popen(
            [BROWSER, "--headless=new", "--remote-debugging-pipe", "--disable-gpu",
             "--no-sandbox", "--disable-dev-shm-usage", "--no-first-run",
             "--no-default-browser-check", "--disable-extensions",
             "--disable-background-networking", "--hide-scrollbars",
             f"--user-data-dir={self._profile.name}", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            preexec_fn=pipes, pass_fds=(3, 4, to_browser, from_browser))
        os.close(to_browser)
        os.close(from_browser)
        self._buffer = b""
        self._next_id = 0
        self.events: list[dict] = []

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self) -> None:
        """End the browser (the process this object started) and remove its profile."""
        if self.process.poll() is None:
            try:
                self.send("Browser.close")
            except (BrowserError, OSError):
                pass
            try:
                self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        for fd in (self._out, self._in):
            try:
                os.close(fd)
            except OSError:
                pass
        self._profile.cleanup()

    def send(self, method: str, params: dict | None = None, session: str | None = None,
             timeout: float = TIMEOUT) -> dict:
        """Send one DevTools command and return its result; events that arrive meanwhile
        are kept in :attr:`events`."""
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self._out, json.dumps(message).encode() + b"\0")
        while True:
            answer = self._receive(timeout)
            if answer.get("id") == self._next_id:
                if "error" in answer:
                    raise BrowserError(f"{method}: {answer['error']}")
                return answer.get("result", {})
            if "method" in answer:
                self.events.append(answer)

    def wait_for(self, method: str, session: str, timeout: float = TIMEOUT) -> dict:
        """The next event ``method`` of ``session`` (kept events first)."""
        deadline = time.monotonic() + timeout
        while True:
            for k, e in enumerate(self.events):
                if e["method"] == method and e.get("sessionId") == session:
                    return self.events.pop(k)
            self.events.append(self._receive(deadline - time.monotonic()))

    def _receive(self, timeout: float) -> dict:
        deadline = time.monotonic() + timeout
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([self._in], [], [], left)[0]:
                raise BrowserError(f"no answer from the browser in {timeout:.0f} s")
            chunk = os.read(self._in, 1 << 16)
            if not chunk:
                raise BrowserError("the browser closed its pipe (it exited)")
            self._buffer += chunk
        raw, _, self._buffer = self._buffer.partition(b"\0")
        return json.loads(raw)

    def tab(self, size=WINDOW) -> "Tab":
        """A new tab of ``size`` CSS pixels."""
        return Tab(self, size)


class Tab:
    """One page of the browser, with what it logged."""

    def __init__(self, browser: Browser, size):
        self.browser = browser
        target = browser.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.target = target
        self.session = browser.send("Target.attachToTarget",
                                    {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Page", "Runtime", "Log", "Network"):
            self.send(f"{domain}.enable")
        self.send("Emulation.setDeviceMetricsOverride",
                  {"width": size[0], "height": size[1], "deviceScaleFactor": 1,
                   "mobile": False})

    def send(self, method: str, params: dict | None = None) -> dict:
        return self.browser.send(method, params, self.session)

    def open(self, page: Path) -> None:
        """Load ``page`` (a file) and wait for its load event."""
        self.send("Page.navigate", {"url": Path(page).resolve().as_uri()})
        self.browser.wait_for("Page.loadEventFired", self.session)

    def eval(self, expression: str):
        """The value of a JavaScript expression in the page (promises awaited); a page
        exception is a :class:`BrowserError`."""
        r = self.send("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                           "awaitPromise": True})
        if "exceptionDetails" in r:
            d = r["exceptionDetails"]
            raise BrowserError(d.get("exception", {}).get("description") or d.get("text"))
        return r["result"].get("value")

    def mouse(self, kind: str, x: float, y: float, **extra) -> None:
        """A mouse event at (x, y) (CSS pixels): ``mousePressed``, ``mouseMoved``,
        ``mouseReleased`` or ``mouseWheel`` (with ``deltaY``)."""
        params = {"type": kind, "x": x, "y": y, "button": "left",
                  "buttons": 1 if kind != "mouseReleased" else 0, "clickCount": 1}
        if kind == "mouseWheel":
            params.update(button="none", buttons=0, deltaX=0)
        self.send("Input.dispatchMouseEvent", {**params, **extra})

    def screenshot(self, path: Path) -> Path:
        """Save the viewport as a PNG."""
        data = self.send("Page.captureScreenshot", {"format": "png"})["data"]
        Path(path).write_bytes(base64.b64decode(data))
        return Path(path)

    def problems(self) -> list[str]:
        """Everything that went wrong or left the machine so far: console messages of
        level error or warning, uncaught exceptions, log entries of those levels, and
        requests for anything but the page's own file."""
        out = []
        for e in [e for e in self.browser.events if e.get("sessionId") == self.session]:
            p = e.get("params", {})
            if e["method"] == "Runtime.consoleAPICalled" and p["type"] in ("error", "warning",
                                                                           "assert"):
                out.append(f"console.{p['type']}: " + " ".join(
                    str(a.get("value", a.get("description"))) for a in p["args"]))
            elif e["method"] == "Runtime.exceptionThrown":
                d = p["exceptionDetails"]
                out.append("exception: " + (d.get("exception", {}).get("description")
                                            or d.get("text", "")))
            elif e["method"] == "Log.entryAdded" and p["entry"]["level"] in ("error",
                                                                              "warning"):
                out.append(f"log: {p['entry']['text']}")
            elif e["method"] == "Network.requestWillBeSent" and \
                    not p["request"]["url"].startswith("file:"):
                out.append(f"request: {p['request']['url'][:200]}")
        return out

    def close(self) -> None:
        self.browser.send("Target.closeTarget", {"targetId": self.target})
