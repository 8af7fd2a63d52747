"""Draw docs/animation.png: the engineer guide's `animate` example, photographed in headless Chromium at t = 1.5 s.

Run:  python docs/animation_screenshot.py     (needs Debian's chromium and the test extra's playwright)
"""
from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ARGS = ["--headless=new", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
        "--ignore-gpu-blocklist", "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--no-first-run", "--disable-quic"]


def main() -> None:
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory() as folder:
        html = Path(folder) / "ur5.html"
        subprocess.run([sys.executable, "-m", "course_dynamics.cli", "animate", "ur5", "--trajectory",
                        str(DOCS.parent / "examples" / "ur5_wave.csv"), "--html", str(html), "--torques", "--path"], check=True)
        with sync_playwright() as playwright:
            browser = playwright.chromium.launch(executable_path="/usr/bin/chromium", args=ARGS)
            page = browser.new_page(viewport={"width": 900, "height": 560})
            page.goto(html.as_uri())
            page.wait_for_function("window.sceneReady === true", timeout=60_000)
            page.evaluate("viewer.animator.pause(); viewer.animator.seek(1.5); viewer.render();")
            page.wait_for_timeout(300)
            page.screenshot(path=str(DOCS / "animation.png"))
            browser.close()
    print(f"wrote {DOCS / 'animation.png'}")


if __name__ == "__main__":
    main()
