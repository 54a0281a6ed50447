"""Headless Chromium for the page's measurements and tests: Debian's browser driven by Playwright for Python (no
browser download), on SwiftShader (WebGL 2 on the CPU), nothing from the network, a fresh profile each time.

Public objects: ``CHROMIUM_FLAGS``, ``chromium``, ``browser_page``.
"""

from __future__ import annotations

import base64
import contextlib
import shutil
import tempfile
from collections.abc import Callable

__all__ = ["CHROMIUM_FLAGS", "browser_page", "chromium"]

CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]


def _missing(what: str):
    raise RuntimeError(f"{what} is missing: `make test` installs it (as root on Debian)")


@contextlib.contextmanager
def chromium(viewport=(1280, 900), missing: Callable[[str], None] = _missing):
    """The browser context, ``viewport`` wide; ``missing(what)`` is called where Playwright or Chromium is not
    installed (it raises here; the tests skip, or fail under ``CI=true``)."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        missing("Playwright for Python (the 'browser' extra)")
    executable = shutil.which("chromium") or shutil.which("chromium-browser")
    if executable is None:
        missing("Chromium (Debian chromium)")
    with sync_playwright() as playwright, tempfile.TemporaryDirectory() as profile:
        browser = playwright.chromium.launch_persistent_context(
            profile,
            executable_path=executable,
            args=CHROMIUM_FLAGS,
            headless=True,
            viewport={"width": viewport[0], "height": viewport[1]},
        )
        try:
            yield browser
        finally:
            browser.close()


def browser_page(browser):
    """(a new page, the list its console errors and page errors go to: (kind, text) pairs)."""
    page = browser.new_page()
    messages = []
    page.on("console", lambda message: messages.append((message.type, message.text)))
    page.on("pageerror", lambda error: messages.append(("pageerror", str(error))))
    return page, messages


def page_bytes(page, expression: str) -> bytes:
    """The bytes of what the JavaScript ``expression`` gives in ``page`` (awaited): a typed array's own bytes, an
    ArrayBuffer's, or an array of numbers 0-255 as one byte each, sent as base64 (Playwright's JSON took 10 s for
    the 1.6 million numbers of a 768 x 512 RGBA picture on SwiftShader; base64, a fraction of a second)."""
    encoded = page.evaluate(
        f"""async () => {{
            const value = await ({expression});
            const bytes = value instanceof ArrayBuffer ? new Uint8Array(value)
                : ArrayBuffer.isView(value) ? new Uint8Array(value.buffer, value.byteOffset, value.byteLength)
                : Uint8Array.from(value);
            let text = "";
            for (let start = 0; start < bytes.length; start += 0x8000) {{
                text += String.fromCharCode.apply(null, bytes.subarray(start, start + 0x8000));
            }}
            return btoa(text);
        }}"""
    )
    return base64.b64decode(encoded)
