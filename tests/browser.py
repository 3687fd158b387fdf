"""A headless Chromium driven over the DevTools protocol, for the tests of HTML figures.

The browser is Debian's ``chromium`` (or any Chromium or Chrome on the PATH), started with
``--remote-debugging-pipe``: the protocol's JSON messages go over two pipes (the browser reads
file descriptor 3 and writes 4, each message ending in a NUL byte), so that nothing beyond the
standard library is needed and no port is opened. WebGL runs on the CPU (SwiftShader through
ANGLE: ``--use-angle=swiftshader --enable-unsafe-swiftshader``), so the machine needs no GPU.

    with Chromium() as browser:
        browser.open("file:///tmp/scene.html", width=1000, height=750)
        browser.wait_for("document.readyState === 'complete'")
        image = browser.screenshot()  # (height, width, 3) uint8
"""

from __future__ import annotations

import base64
import io
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from typing import Any

import numpy as np

#: The names Chromium goes by on the PATH, Debian's first.
BINARIES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")

#: Software WebGL in a headless browser (no GPU, no display), no sandbox (CI runs as root).
FLAGS = (
    "--headless",
    "--no-sandbox",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--hide-scrollbars",
    "--disable-dev-shm-usage",
    "--no-first-run",
    "--no-default-browser-check",
    "--disable-extensions",
    "--mute-audio",
)


#: Run by ``python -c`` with the pipes' two fds, then the browser's command line: moves the
#: pipes to fds 3 and 4 and becomes the browser.
_AS_3_AND_4 = """
import fcntl, os, sys
given = (int(sys.argv[1]), int(sys.argv[2]))
high = [fcntl.fcntl(fd, fcntl.F_DUPFD, 10) for fd in given]  # apart from 3 and 4
for fd in given:
    os.close(fd)
for fd, target in zip(high, (3, 4)):
    os.dup2(fd, target)
    os.set_inheritable(target, True)
    os.close(fd)
os.execv(sys.argv[3], sys.argv[3:])
"""


def find_chromium() -> str | None:
    """The path of a Chromium binary on the PATH, or None."""
    for name in BINARIES:
        path = shutil.which(name)
        if path:
            return path
    return None


class BrowserError(RuntimeError):
    """The browser closed, timed out, or a page's script raised."""


class Chromium:
    """One headless browser with one page (a context manager: closed on exit)."""

    def __init__(self, binary: str | None = None, timeout: float = 30.0) -> None:
        binary = binary or find_chromium()
        if binary is None:
            raise BrowserError(f"No Chromium on the PATH (looked for {', '.join(BINARIES)}).")
        self.timeout = timeout
        self._profile = tempfile.TemporaryDirectory(prefix="polhode-chromium-")
        self._log = open(os.path.join(self._profile.name, "chromium.log"), "wb")  # noqa: SIM115
        commands, self._commands = os.pipe()  # the browser reads fd 3
        self._replies, replies = os.pipe()  # the browser writes fd 4
        # The pipes become fds 3 and 4 in a small Python process that then becomes the browser
        # (exec): no preexec_fn, which is unsafe in a process with threads (rayon's, here).
        self._process = subprocess.Popen(
            [
                sys.executable,
                "-c",
                _AS_3_AND_4,
                str(commands),
                str(replies),
                binary,
                *FLAGS,
                "--remote-debugging-pipe",
                f"--user-data-dir={self._profile.name}",
                "about:blank",
            ],
            stdin=subprocess.DEVNULL,
            stdout=self._log,
            stderr=self._log,
            pass_fds=(commands, replies),
        )
        os.close(commands)
        os.close(replies)
        self._buffer = b""
        self._next_id = 0
        self._session: str | None = None

    # --- the protocol ---------------------------------------------------------------------

    def _read_message(self, deadline: float) -> dict[str, Any]:
        import select

        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise BrowserError("The browser did not answer in time.")
            ready, _, _ = select.select([self._replies], [], [], left)
            if not ready:
                continue
            chunk = os.read(self._replies, 1 << 20)
            if not chunk:
                raise BrowserError(f"The browser closed: {self.log()[-2000:]}")
            self._buffer += chunk
        raw, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(raw)

    def send(self, method: str, params: dict[str, Any] | None = None, page: bool = True) -> Any:
        """Send one command (to the page's session unless ``page=False``) and return its
        result."""
        self._next_id += 1
        message: dict[str, Any] = {"id": self._next_id, "method": method, "params": params or {}}
        if page:
            if self._session is None:
                raise BrowserError("No page open: call open() first.")
            message["sessionId"] = self._session
        os.write(self._commands, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + self.timeout
        while True:
            reply = self._read_message(deadline)
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise BrowserError(f"{method}: {reply['error']}")
                return reply.get("result", {})

    # --- the page -------------------------------------------------------------------------

    def open(self, url: str, width: int = 1000, height: int = 750) -> None:
        """Open ``url`` in a new page of this size (CSS pixels, at device scale 1)."""
        target = self.send("Target.createTarget", {"url": "about:blank"}, page=False)
        attached = self.send(
            "Target.attachToTarget", {"targetId": target["targetId"], "flatten": True}, page=False
        )
        self._session = attached["sessionId"]
        self.send(
            "Emulation.setDeviceMetricsOverride",
            {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False},
        )
        self.send("Page.enable")
        self.send("Page.navigate", {"url": url})

    def evaluate(self, expression: str, await_promise: bool = False) -> Any:
        """The value of a JavaScript expression in the page (a promise awaited if asked)."""
        result = self.send(
            "Runtime.evaluate",
            {"expression": expression, "returnByValue": True, "awaitPromise": await_promise},
        )
        if "exceptionDetails" in result:
            details = result["exceptionDetails"]
            text = details.get("exception", {}).get("description") or details.get("text")
            raise BrowserError(f"The page's script raised: {text}")
        return result["result"].get("value")

    def wait_for(self, expression: str, timeout: float | None = None) -> Any:
        """Evaluate ``expression`` until it is truthy; its value."""
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        while True:
            value = self.evaluate(expression)
            if value:
                return value
            if time.monotonic() > deadline:
                raise BrowserError(f"Timed out waiting for: {expression}")
            time.sleep(0.05)

    def screenshot(self) -> np.ndarray:
        """The page as an RGB image, (height, width, 3) uint8."""
        from PIL import Image

        data = self.send("Page.captureScreenshot", {"format": "png"})["data"]
        return np.asarray(Image.open(io.BytesIO(base64.b64decode(data))).convert("RGB"))

    # --- the end --------------------------------------------------------------------------

    def log(self) -> str:
        self._log.flush()
        with open(self._log.name, "rb") as file:
            return file.read().decode(errors="replace")

    def close(self) -> None:
        if self._process.poll() is None:
            try:
                self.send("Browser.close", page=False)
                self._process.wait(timeout=10)
            except (BrowserError, OSError, subprocess.TimeoutExpired):
                self._process.kill()
                self._process.wait()
        for fd in (self._commands, self._replies):
            try:
                os.close(fd)
            except OSError:
                pass
        self._log.close()
        self._profile.cleanup()

    def __enter__(self) -> Chromium:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
