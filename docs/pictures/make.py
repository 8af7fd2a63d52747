"""Draw the documentation site's pictures from the real commands run on the repository's examples/.

Run:  python3 docs/pictures/make.py      (from any folder; needs Debian's /usr/bin/chromium, Playwright and Pillow)

examples/ is copied to a temporary folder and every command runs there (``python3 -m course_dynamics.cli``,
this checkout's package first on the path), so examples/ is never written. The pictures are written next
to this script, each atomically (a temporary file, then os.replace):

torques.png         the PNG that ``torques ur5 --log examples/ur5_log.csv --map examples/ur5_log_columns.toml
                    --out tau.csv --plot tau.png`` writes (exit 0 or 1: 1 only says a limit is exceeded)
residual.png        the PNG of ``torques ur5 --log examples/ur5_joint_states.mcap --plot r.png``: the log holds
                    measured torques, so each joint's panel draws them beside ours, with the residual's RMS and R²
detect.png          the PNG of ``detect ur5 --log examples/ur5_collision.csv`` with the log's friction (``--viscous
                    …``, ``--coulomb …``, ``--friction-width 0.01``) and ``--plot contact.png`` (exit 1: a contact is
                    found): the observer's r(t) per joint, its thresholds and the push shaded
feedback.png        the HTML feedback page (1100 px wide, its top 1400 px at most) of the student whose grading
                    names a mistake (a ``[slip-name]``), after ``grade examples/grading/assignment.toml alice.py bob.py
                    --out grades``
summary.png         grades/summary.html of the same run
identification.png  the HTML report of ``identify ur5 --log examples/ur5_joint_states.mcap --out identification``
identification_held_out.png  that report's figure, with its caption: measured torques on the held-out part of
                    the log against the URDF's and the identified model's
report.png          course-report/index.html of ``report two_link --samples 10 --out course-report``

Screenshots are taken by headless Chromium through Playwright, launched as tests/conftest.py's ``browser``
fixture does (tests/helpers.py's CHROMIUM and CHROMIUM_ARGS; Playwright's own browser download is never
used). Pages are opened from disk and every request that is not file:// is aborted, so nothing is fetched.
A page longer than 1400 px is cut below the last paragraph, heading, list item, table row or figure that
fits. A PNG over 250 KB is quantised to 256 colours, so each stays well under 400 KB.
"""
from __future__ import annotations

import io
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from helpers import CHROMIUM, CHROMIUM_ARGS  # noqa: E402  (the test suite's one definition of the browser)

WIDTH, HEIGHT = 1100, 1400  # screenshot viewport, px; a page is cropped to its top HEIGHT px
MAX_PLAIN_BYTES = 250_000  # above this a PNG is quantised to a palette
# Where to cut a page: its end when it is shorter than HEIGHT, else below the last block (a paragraph, a
# heading, a list item, a table row, a figure) that ends above HEIGHT, with a little of the white that follows it.
CUT = """height => {
  const body = document.body.getBoundingClientRect().bottom + parseFloat(getComputedStyle(document.body).marginBottom);
  if (body <= height) return Math.ceil(body);
  const blocks = [...document.body.querySelectorAll("p, h1, h2, h3, h4, li, tr, figure, pre, table, img, svg, dl")]
    .map(e => e.getBoundingClientRect()).filter(r => r.height > 0);
  const end = Math.max(0, ...blocks.filter(r => r.bottom <= height).map(r => r.bottom));
  const next = Math.min(height, ...blocks.filter(r => r.top >= end - 0.5 && r.bottom > end).map(r => r.top));
  return Math.ceil(Math.min(height, end + Math.max(1, Math.min(16, next - end))));
}"""
NAMED_MISTAKE = re.compile(r"^- \[[a-z][a-z0-9-]*\] ", re.MULTILINE)  # a feedback line naming a slip


def run(work: Path, *args: str, ok: tuple[int, ...] = (0,)) -> None:
    """``python3 -m course_dynamics.cli ARGS`` in WORK, this checkout's package first; stop unless it exits with OK."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))
    print("$ course-dynamics", " ".join(args), flush=True)
    status = subprocess.run([sys.executable, "-m", "course_dynamics.cli", *args], cwd=work, env=env).returncode
    if status not in ok:
        sys.exit(f"course-dynamics {args[0]} exited with {status}, expected {' or '.join(map(str, ok))}")


def save(png: bytes, name: str, trim: bool = False) -> None:
    """Write PNG bytes to HERE/NAME atomically, re-encoded optimised (and quantised when large); TRIM: cut the
    white around the content, keeping a 12 px margin."""
    from PIL import Image, ImageChops, ImageOps

    image = Image.open(io.BytesIO(png))
    image.load()
    image = image.convert("RGB")
    box = ImageChops.difference(image, Image.new("RGB", image.size, "white")).getbbox() if trim else None
    if box:
        image = ImageOps.expand(image.crop(box), border=12, fill="white")
    out = io.BytesIO()
    image.save(out, "PNG", optimize=True)
    if out.tell() > MAX_PLAIN_BYTES:
        out = io.BytesIO()
        image.quantize(256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE).save(out, "PNG", optimize=True)
    target = HERE / name
    fd, temp = tempfile.mkstemp(prefix=f".{name}.", suffix=".tmp", dir=HERE)
    try:
        with os.fdopen(fd, "wb") as file:
            file.write(out.getvalue())
        os.chmod(temp, 0o644)  # mkstemp's 0600 would hide the picture from a web server
        os.replace(temp, target)
    except BaseException:
        os.unlink(temp)
        raise
    print(f"wrote {target.relative_to(ROOT)} ({image.width}x{image.height}, {out.tell() // 1024} KB)", flush=True)


def student_with_named_mistake(grades: Path) -> str:
    """The first student (by name) whose feedback names a mistake; their results JSON says so."""
    for result in sorted(grades.glob("*.json")):
        if result.name.startswith("."):
            continue
        tests = json.loads(result.read_text()).get("tests", [])
        if any(NAMED_MISTAKE.search(test.get("output", "")) for test in tests if test.get("visibility") != "hidden"):
            return result.stem
    sys.exit(f"no feedback in {grades} names a mistake")


def screenshots(pages: dict[str, Path], figures: dict[str, Path]) -> None:
    """Photograph each HTML page (from disk, nothing fetched) into HERE/<name>: its top, cut by CUT; and the
    first <figure> (with its caption) of each page of FIGURES."""
    from playwright.sync_api import sync_playwright

    if not Path(CHROMIUM).exists():
        sys.exit(f"{CHROMIUM} is missing: install Debian's chromium (see the README's test command)")
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            context = browser.new_context(viewport={"width": WIDTH, "height": HEIGHT}, device_scale_factor=1)
            blocked: list[str] = []

            def only_files(route) -> None:
                if route.request.url.startswith("file://"):
                    route.continue_()
                else:
                    blocked.append(route.request.url)
                    route.abort()

            context.route("**/*", only_files)
            for name, html in pages.items():
                page = context.new_page()
                page.goto(html.as_uri(), wait_until="load")
                page.wait_for_timeout(300)
                height = min(HEIGHT, page.evaluate(CUT, HEIGHT))
                save(page.screenshot(clip={"x": 0, "y": 0, "width": WIDTH, "height": height}), name)
                page.close()
            for name, html in figures.items():
                page = context.new_page()
                page.goto(html.as_uri(), wait_until="load")
                page.wait_for_timeout(300)
                save(page.locator("figure").first.screenshot(), name, trim=True)
                page.close()
            if blocked:
                print(f"blocked {len(blocked)} non-file requests, e.g. {blocked[0]}", flush=True)
        finally:
            browser.close()


def main() -> None:
    with tempfile.TemporaryDirectory(prefix="course-dynamics-pictures-") as folder:
        work = Path(folder)
        shutil.copytree(ROOT / "examples", work / "examples")

        run(work, "torques", "ur5", "--log", "examples/ur5_log.csv", "--map", "examples/ur5_log_columns.toml",
            "--out", "tau.csv", "--plot", "tau.png", ok=(0, 1))
        save((work / "tau.png").read_bytes(), "torques.png")

        run(work, "torques", "ur5", "--log", "examples/ur5_joint_states.mcap", "--plot", "r.png")
        save((work / "r.png").read_bytes(), "residual.png")

        run(work, "detect", "ur5", "--log", "examples/ur5_collision.csv", "--viscous", "2,2,1,0.5,0.5,0.5",
            "--coulomb", "3,3,2,1,1,1", "--friction-width", "0.01", "--plot", "contact.png", ok=(1,))
        save((work / "contact.png").read_bytes(), "detect.png")

        run(work, "grade", "examples/grading/assignment.toml", "examples/grading/submissions/alice.py",
            "examples/grading/submissions/bob.py", "--out", "grades")
        grades = work / "grades"
        student = student_with_named_mistake(grades)
        print(f"feedback: {student}'s page names a mistake", flush=True)

        run(work, "identify", "ur5", "--log", "examples/ur5_joint_states.mcap", "--out", "identification")
        (identification,) = sorted((work / "identification").glob("*.html"))

        run(work, "report", "two_link", "--samples", "10", "--out", "course-report")

        screenshots({"feedback.png": grades / f"{student}.html", "summary.png": grades / "summary.html",
                     "identification.png": identification, "report.png": work / "course-report" / "index.html"},
                    {"identification_held_out.png": identification})


if __name__ == "__main__":
    main()
