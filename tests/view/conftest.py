"""Headless Chromium for the page tests, driven over the DevTools protocol on a pipe (one browser per test module)."""

from __future__ import annotations

import base64
import contextlib
import io
import json
import os
import shutil
import subprocess
import time
from pathlib import Path

import pytest
from PIL import Image

BROWSERS = ("chromium-headless-shell", "chromium")  # Debian's packages (.ci/run installs the first)
WIDTH, HEIGHT = 1200, 800
LOAD_TIMEOUT_S = 60.0


class Browser:
    """One headless Chromium (WebGL through SwiftShader) with one page, over --remote-debugging-pipe: commands go
    to its fd 3, answers and events come from its fd 4, each a JSON text ended by a NUL."""

    def __init__(self, executable: str) -> None:
        to_chrome, self._to = os.pipe()
        self._from, from_chrome = os.pipe()

        def pipes() -> None:  # in the child, before exec: the pipe ends at the numbers Chromium reads and writes
            os.dup2(to_chrome, 3)
            os.dup2(from_chrome, 4)

        args = [
            executable,
            "--headless",
            "--remote-debugging-pipe",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--hide-scrollbars",
            f"--window-size={WIDTH},{HEIGHT}",
            "about:blank",
        ]
        if os.geteuid() == 0:  # Chromium's sandbox refuses root
            args.insert(1, "--no-sandbox")
        self.process = subprocess.Popen(
            args, pass_fds=(3, 4), preexec_fn=pipes, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
        )
        os.close(to_chrome)
        os.close(from_chrome)
        self._buffer = b""
        self._id = 0
        self.events: list[dict] = []
        target = self.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = self.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for method in ("Page.enable", "Runtime.enable", "Network.enable"):
            self.send(method, session=True)
        offline = {"offline": True, "latency": 0, "downloadThroughput": -1, "uploadThroughput": -1}
        self.send("Network.emulateNetworkConditions", offline, session=True)  # no network: the page must not need one
        metrics = {"width": WIDTH, "height": HEIGHT, "deviceScaleFactor": 1, "mobile": False}
        self.send("Emulation.setDeviceMetricsOverride", metrics, session=True)

    def _message(self) -> dict:
        while b"\0" not in self._buffer:
            chunk = os.read(self._from, 1 << 20)
            if not chunk:
                raise RuntimeError("the browser closed its pipe")
            self._buffer += chunk
        text, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(text)

    def send(self, method: str, params: dict | None = None, session: bool = False) -> dict:
        self._id += 1
        message = {"id": self._id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = self.session
        os.write(self._to, json.dumps(message).encode() + b"\0")
        while True:
            answer = self._message()
            if answer.get("id") == self._id:
                if "error" in answer:
                    raise RuntimeError(f"{method}: {answer['error']}")
                return answer["result"]
            self.events.append(answer)

    def evaluate(self, expression: str):
        """The expression's value in the page (promises awaited), as JSON gives it."""
        params = {"expression": expression, "returnByValue": True, "awaitPromise": True}
        result = self.send("Runtime.evaluate", params, session=True)
        if "exceptionDetails" in result:
            raise RuntimeError(f"{expression[:80]}: {result['exceptionDetails']}")
        return result["result"].get("value")

    def open(self, path: Path, fragment: str = "") -> None:
        """Load a page from disk with the network off and wait until its viewer says it is ready; AssertionError if
        the page asked for anything but its own file (a script, a style, an image, a font, an address)."""
        self.events.clear()
        url = path.resolve().as_uri()
        self.send("Page.navigate", {"url": url + fragment}, session=True)
        deadline = time.monotonic() + LOAD_TIMEOUT_S
        while not self.evaluate("!!(window.codegenView && window.codegenView.ready)"):
            if time.monotonic() > deadline:
                raise TimeoutError(f"{path.name}: not ready after {LOAD_TIMEOUT_S:g} s")
            time.sleep(0.05)
        requests = self.requests()
        assert url in requests, f"{path.name}: the browser did not report loading it"  # the record works
        asked = [u for u in requests if u != url and not u.startswith(("data:", "blob:"))]
        assert asked == [], f"{path.name} asked for more than its own file: {asked}"

    def requests(self) -> list[str]:
        """The addresses the page asked for since it was opened."""
        return [e["params"]["request"]["url"] for e in self.events if e.get("method") == "Network.requestWillBeSent"]

    def errors(self) -> list[str]:
        """What the page reported as an error: exceptions, console errors and the viewer's own list."""
        out = [str(e["params"]) for e in self.events if e.get("method") == "Runtime.exceptionThrown"]
        out += [
            str(e["params"].get("args"))
            for e in self.events
            if e.get("method") == "Runtime.consoleAPICalled" and e["params"].get("type") == "error"
        ]
        return out + list(self.evaluate("window.codegenView ? window.codegenView.errors : ['no viewer']"))

    def screenshot(self):
        """The page as drawn now (PIL image, RGB)."""
        data = self.send("Page.captureScreenshot", {"format": "png"}, session=True)["data"]
        return Image.open(io.BytesIO(base64.b64decode(data))).convert("RGB")

    def close(self) -> None:
        with contextlib.suppress(RuntimeError, OSError):
            self.send("Browser.close")
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        os.close(self._to)
        os.close(self._from)


def browser_executable() -> str | None:
    return next((path for name in BROWSERS if (path := shutil.which(name))), None)


@pytest.fixture(scope="module")
def browser():
    executable = browser_executable()
    if executable is None:
        pytest.skip("no headless Chromium (apt-get install chromium-headless-shell): the page tests need a browser")
    chrome = Browser(executable)
    yield chrome
    chrome.close()
