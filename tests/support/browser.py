"""A real headless browser for tests: Debian's chromium, driven over the DevTools
protocol (its own websocket; aiohttp's client speaks it). What a person would see is
read from the page itself: its text, its drawn elements, a screenshot."""

from __future__ import annotations

import asyncio
import base64
import itertools
import json
import re
import subprocess
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import aiohttp

from system_packages import browser, require


class Browser:
    """One headless chromium with one page."""

    def __init__(self, width: int = 1200, height: int = 700) -> None:
        require("chromium")
        chromium = browser()
        assert chromium is not None
        self._profile = tempfile.TemporaryDirectory()
        self._process = subprocess.Popen(
            [chromium, "--headless=new", "--no-sandbox", "--disable-gpu",
             "--remote-debugging-port=0", "--remote-debugging-address=127.0.0.1",
             f"--user-data-dir={self._profile.name}", f"--window-size={width},{height}",
             "--no-first-run", "--no-default-browser-check", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
        )  # fmt: skip
        self._ids = itertools.count(1)
        port = self._devtools_port()
        threading.Thread(target=self._drain, daemon=True).start()  # a full pipe stalls it
        deadline = time.monotonic() + 10
        while True:
            try:
                targets = asyncio.run(_get_json(f"http://127.0.0.1:{port}/json/list"))
                pages = [t for t in targets if t["type"] == "page"]
                if pages:
                    self._ws = pages[0]["webSocketDebuggerUrl"]
                    break
            except aiohttp.ClientError:
                pass
            assert time.monotonic() < deadline, "chromium's page never appeared"
            time.sleep(0.1)

    def _devtools_port(self) -> int:
        assert self._process.stderr is not None
        for line in self._process.stderr:
            if match := re.search(r"DevTools listening on ws://127\.0\.0\.1:(\d+)/", line):
                return int(match[1])
        raise AssertionError("chromium did not start its DevTools endpoint")

    def _drain(self) -> None:
        assert self._process.stderr is not None
        for _ in self._process.stderr:
            pass

    def send(self, method: str, **params: Any) -> dict[str, Any]:
        return asyncio.run(_command(self._ws, next(self._ids), method, params))

    def open(self, url: str) -> None:
        self.send("Page.navigate", url=url)

    def evaluate(self, expression: str) -> Any:
        reply = self.send("Runtime.evaluate", expression=expression, returnByValue=True)
        return reply["result"].get("value")

    def wait_for(self, expression: str, timeout: float = 10.0) -> Any:
        """The value of ``expression`` once truthy (the page updates as events arrive)."""
        deadline = time.monotonic() + timeout
        while not (value := self.evaluate(expression)):
            assert time.monotonic() < deadline, f"the page never showed: {expression}"
            time.sleep(0.1)
        return value

    def screenshot(self, path: Path) -> None:
        data = self.send("Page.captureScreenshot", format="png")["data"]
        path.write_bytes(base64.b64decode(data))

    def close(self) -> None:
        self._process.terminate()
        try:
            self._process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            self._process.kill()
            self._process.wait()
        if self._process.stderr is not None:
            self._process.stderr.close()
        self._profile.cleanup()


async def _get_json(url: str) -> Any:
    async with aiohttp.ClientSession() as session, session.get(url) as response:
        return await response.json()


async def _command(ws_url: str, ident: int, method: str, params: dict) -> dict[str, Any]:
    async with aiohttp.ClientSession() as session, session.ws_connect(ws_url, max_msg_size=0) as ws:
        await ws.send_str(json.dumps({"id": ident, "method": method, "params": params}))
        async for message in ws:
            reply = json.loads(message.data)
            if reply.get("id") == ident:
                assert "error" not in reply, reply["error"]
                return reply["result"]
    raise AssertionError(f"no reply to {method}")
