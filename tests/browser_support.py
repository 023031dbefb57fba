"""Headless Chromium for the page tests (on sys.path through tests/conftest.py): the page's DOM after
its scripts ran, as the teach tests read it (tests/viz/test_teach.py has the same recipe)."""
import os
import shutil
import subprocess
import tempfile

CHROMIUM = shutil.which("chromium") or ("/usr/bin/chromium" if os.path.exists("/usr/bin/chromium") else None)


def dump_dom(url: str, window: tuple[int, int] = (1000, 700), budget_ms: int = 20000, timeout: float = 240) -> str:
    """The DOM of ``url`` after ``budget_ms`` of the page's (virtual) time, in a ``window``-sized
    headless Chromium with a fresh profile and software WebGL."""
    with tempfile.TemporaryDirectory(ignore_cleanup_errors=True) as profile:
        out = subprocess.run(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
             "--use-angle=swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", f"--user-data-dir={profile}",
             f"--window-size={window[0]},{window[1]}", f"--virtual-time-budget={budget_ms}", "--dump-dom", url],
            capture_output=True, text=True, timeout=timeout)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout
