"""Headless Chromium driven through the DevTools protocol over a pipe (``--remote-debugging-
pipe``: messages are JSON, each ended by a NUL byte, read from fd 3 and written to fd 4 of the
browser; no port, no driver, no extra package; every other descriptor of ours is close-on-exec,
as Python makes them). Used by the browser tests of the 3D view and
by ``benchmarks/bench_view.py``: open a page (optionally with the network cut), run script in
it, take screenshots, and collect every error the page logs and every request it makes."""

from __future__ import annotations

import base64
import fcntl
import io
import json
import os
import queue
import shutil
import subprocess
import tempfile
import threading
import time

#: the flags of every headless run (tests/test_report.py's, plus a window size)
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run", "--disable-quic",
         "--hide-scrollbars", "--mute-audio"]


def chromium_path() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


class Browser:
    """One headless Chromium with one page. ``errors``: console errors, uncaught exceptions
    and error log entries; ``requests``: the URLs the page asked for (none but the page's
    own file and data: URLs is expected of an offline page)."""

    def __init__(self, width: int = 1280, height: int = 900, offline: bool = False,
                 timeout_s: float = 60.0):
        path = chromium_path()
        if path is None:
            raise RuntimeError("headless Chromium is not installed")
        self.timeout = timeout_s
        self.profile = tempfile.mkdtemp(prefix="elastokin-chromium-")
        ends = os.pipe() + os.pipe()  # (to the browser, ours), (ours, from the browser)
        # above 4, so that moving them to 3 and 4 in the child cannot overwrite one
        to_browser, self._write, self._read, from_browser = (
            fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10) for fd in ends)
        for fd in ends:
            os.close(fd)

        def pipes_at_3_and_4() -> None:  # in the child, before exec
            os.dup2(to_browser, 3)
            os.dup2(from_browser, 4)

        self.log = tempfile.TemporaryFile()
        self.proc = subprocess.Popen(
            [path, *FLAGS, f"--user-data-dir={self.profile}", "--remote-debugging-pipe",
             f"--window-size={width},{height}", "about:blank"],
            preexec_fn=pipes_at_3_and_4, close_fds=False, stdin=subprocess.DEVNULL,
            stdout=self.log, stderr=self.log)
        os.close(to_browser)
        os.close(from_browser)
        self._id = 0
        self._replies: dict[int, queue.Queue] = {}
        self._lock = threading.Lock()
        self.errors: list[str] = []
        self.requests: list[str] = []
        self.loaded = threading.Event()
        threading.Thread(target=self._reader, daemon=True).start()
        target = next(t for t in self.call("Target.getTargets")["targetInfos"]
                      if t["type"] == "page")
        self.session = self.call("Target.attachToTarget", targetId=target["targetId"],
                                 flatten=True)["sessionId"]
        for domain in ("Page", "Runtime", "Log", "Network"):
            self.page(f"{domain}.enable")
        self.page("Emulation.setDeviceMetricsOverride", width=width, height=height,
                  deviceScaleFactor=1, mobile=False)
        if offline:
            self.page("Network.emulateNetworkConditions", offline=True, latency=0,
                      downloadThroughput=-1, uploadThroughput=-1)

    # ------------------------------------------------------------------ protocol
    def _reader(self) -> None:
        buf = b""
        with os.fdopen(self._read, "rb", buffering=0) as fh:
            while True:
                chunk = fh.read(1 << 16)
                if not chunk:
                    return
                buf += chunk
                while b"\0" in buf:
                    raw, buf = buf.split(b"\0", 1)
                    self._dispatch(json.loads(raw))

    def _dispatch(self, msg: dict) -> None:
        if "id" in msg:
            with self._lock:
                q = self._replies.get(msg["id"])
            if q is not None:
                q.put(msg)
            return
        method, params = msg.get("method"), msg.get("params", {})
        if method == "Runtime.exceptionThrown":
            d = params["exceptionDetails"]
            self.errors.append(d.get("exception", {}).get("description") or d.get("text"))
        elif method == "Runtime.consoleAPICalled" and params["type"] in ("error", "assert"):
            self.errors.append(" ".join(str(a.get("value", a.get("description")))
                                        for a in params["args"]))
        elif method == "Log.entryAdded" and params["entry"]["level"] == "error":
            self.errors.append(params["entry"]["text"])
        elif method == "Network.requestWillBeSent":
            self.requests.append(params["request"]["url"])
        elif method == "Page.loadEventFired":
            self.loaded.set()

    def call(self, method: str, session: str | None = None, **params) -> dict:
        with self._lock:
            self._id += 1
            n = self._id
            self._replies[n] = queue.Queue()
        msg = {"id": n, "method": method, "params": params}
        if session:
            msg["sessionId"] = session
        os.write(self._write, json.dumps(msg).encode() + b"\0")
        try:
            reply = self._replies[n].get(timeout=self.timeout)
        except queue.Empty:
            raise TimeoutError(f"Chromium did not answer {method}") from None
        if "error" in reply:
            raise RuntimeError(f"{method}: {reply['error']}")
        return reply.get("result", {})

    def page(self, method: str, **params) -> dict:
        return self.call(method, self.session, **params)

    # ------------------------------------------------------------------ use
    def open(self, url: str) -> float:
        """Navigate and wait for the load event; returns the seconds it took."""
        self.loaded.clear()
        start = time.perf_counter()
        self.page("Page.navigate", url=url)
        if not self.loaded.wait(self.timeout):
            raise TimeoutError(f"{url} did not load")
        return time.perf_counter() - start

    def run(self, script: str):
        """The value of a script (an expression; a promise is awaited)."""
        r = self.page("Runtime.evaluate", expression=script, awaitPromise=True,
                      returnByValue=True)
        if "exceptionDetails" in r:
            raise RuntimeError(r["exceptionDetails"].get("exception", {}).get("description"))
        return r["result"].get("value")

    def wait_for(self, script: str, timeout_s: float | None = None) -> float:
        """Wait until ``script`` is true; the seconds it took."""
        start = time.perf_counter()
        while not self.run(script):
            if time.perf_counter() - start > (timeout_s or self.timeout):
                raise TimeoutError(f"never true: {script}")
            time.sleep(0.02)
        return time.perf_counter() - start

    def settle(self) -> None:
        """Two animation frames: what was drawn is on screen."""
        self.run("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")

    def screenshot(self, clip: dict | None = None):
        """The page (or ``clip``: x, y, width, height in CSS px) as an RGB array."""
        import numpy as np
        from PIL import Image

        params = {"format": "png"}
        if clip:
            params["clip"] = {**clip, "scale": 1}
        data = base64.b64decode(self.page("Page.captureScreenshot", **params)["data"])
        return np.asarray(Image.open(io.BytesIO(data)).convert("RGB"))

    def close(self) -> None:
        try:
            self.call("Browser.close")
        except (RuntimeError, TimeoutError, OSError):
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        os.close(self._write)
        self.log.close()
        shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
