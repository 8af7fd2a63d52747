"""course_dynamics/output/page.py: the one page builder, its escaping, its stylesheet and its offline mathematics.

Every kind of page is built here by its real caller (a published notebook and the course index, a
student's feedback and the class summary, the torques page, the offline animation, the comparison
report) and checked for the same things: the one stylesheet, nothing fetched from the network, no
MathJax or KaTeX.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from html.parser import HTMLParser

import numpy as np
import pytest
from markupsafe import Markup

from course_dynamics import load_robot, robot_path
from course_dynamics.output import page
from course_dynamics.teaching.course import (
    index_page,
    notebook_page,
    notebook_paths,
    read_notebook,
    solution_version,
)

HOSTILE = '<script>alert(1)</script>"><img src=x onerror=alert(2)>'
CRAIG_6_48 = r"\dot{v}_{C_1} = \dot\omega_1 \times P_{C_1} + \omega_1 \times (\omega_1 \times P_{C_1}) + \dot v_1"


class Parsed(HTMLParser):
    """Every element's tag and attributes, and the text outside code, preformatted blocks, maths and scripts."""

    SKIP = frozenset({"pre", "code", "math", "script", "style", "title"})

    def __init__(self, text: str):
        super().__init__(convert_charrefs=True)
        self.elements, self.text, self.open = [], [], []
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        self.elements.append((tag, dict(attrs)))
        if tag in self.SKIP:
            self.open.append(tag)

    def handle_endtag(self, tag):
        if tag in self.open:
            self.open.remove(tag)

    def handle_data(self, data):
        if not self.open:
            self.text.append(data)


def assert_offline_with_the_one_stylesheet(text: str) -> None:
    styles = re.findall(r"<style>\n?(.*?)</style>", text, re.DOTALL)
    assert styles == [page.STYLESHEET], "one <style>, and it is the one stylesheet"
    elements = Parsed(text).elements
    assert not [e for e in elements if e[0] == "link"]
    assert not [e for e in elements if e[0] == "script" and "src" in e[1]]
    assert not [e for e in elements if re.match(r"\s*(https?:)?//", e[1].get("src") or "")]
    assert "@import" not in page.STYLESHEET and "url(" not in page.STYLESHEET
    assert not re.search(r"<(script|link)[^>]*(src|href)\s*=\s*[\"']?\s*(https?:)?//", text, re.IGNORECASE)
    assert "mathjax" not in text.lower() and "katex" not in text.lower()


# ---------------------------------------------------------------------------- escaping


def test_hostile_text_is_escaped_in_the_title_and_the_body():
    text = page.page(HOSTILE, [page.heading(HOSTILE), page.paragraph(HOSTILE), HOSTILE,
                               page.table([[HOSTILE, 1.5]], header=[HOSTILE, "n"]), page.pre(HOSTILE),
                               page.bullet_list([HOSTILE]), page.section(HOSTILE, HOSTILE, css="bad"),
                               page.figure(page.code(HOSTILE), HOSTILE), page.link("a b.html", HOSTILE)])
    assert "<script>" not in text and "<img" not in text
    assert text.count("&lt;script&gt;alert(1)&lt;/script&gt;") == 13
    assert [tag for tag, _ in Parsed(text).elements if tag in ("script", "img")] == []


def test_attribute_values_cannot_open_an_attribute_of_their_own():
    cell = page.element("td", "x", class_='" onclick="alert(1)', title="a'b")
    assert Parsed(cell).elements == [("td", {"class": '" onclick="alert(1)', "title": "a'b"})]
    assert page.heading("x", 2, css='ok"><script>') == Markup('<h2 class="ok&quot;&gt;&lt;script&gt;">x</h2>')
    for name in ("onclick", "on_load", "x y"):
        with pytest.raises(ValueError):
            page.element("p", "x", **{name: "alert(1)"})
    with pytest.raises(ValueError):
        page.element("p onclick=alert(1)", "x")


def test_no_script_link_and_only_markup_in_the_head():
    for href in ("javascript:alert(1)", " JavaScript:alert(1)", "data:text/html,<script>alert(1)</script>"):
        with pytest.raises(ValueError):
            page.link(href, "x")
    assert Parsed(page.link("bob%3Ax.html", "bob")).elements == [("a", {"href": "bob%3Ax.html"})]
    with pytest.raises(TypeError):
        page.page("t", "b", head_extra="<script>alert(1)</script>")
    text = page.page("t", "b", scripts=['var s = "</script><script>alert(1)//";'])
    assert text.count("</script>") == 1 and "<\\/script><script>alert(1)" in text
    assert [tag for tag, _ in Parsed(text).elements if tag == "script"] == ["script"]


def test_markdown_escapes_raw_html_and_drops_harmful_links():
    html = page.markdown(f"{HOSTILE}\n\n[x](javascript:alert(3)) and `$code$`; &lt;b&gt; stays text")
    assert "<script>" not in html and "<img" not in html and "javascript:" not in html
    assert "<code>$code$</code>" in html and "&lt;b&gt; stays text" in html and "&amp;lt;" not in html


# ---------------------------------------------------------------------------- mathematics


def test_craigs_formula_becomes_mathml():
    for shown in (page.math(CRAIG_6_48), page.math(CRAIG_6_48, display=True), page.markdown(f"$${CRAIG_6_48}$$"),
                  page.markdown(f"so ${CRAIG_6_48}$ (6.48)")):
        assert shown.count("<math") == 1 and "math-error" not in shown and "$" not in shown
        assert "<msub>" in shown and "<mover" in shown and "×" in shown
    assert 'display="block"' in page.math(CRAIG_6_48, display=True)
    aligned = page.markdown("$$\\begin{aligned} F &= m\\,\\dot v_C \\\\ N &= I\\dot\\omega \\end{aligned}$$")
    assert "<mtable" in aligned and "&amp;" not in aligned and "math-error" not in aligned


def test_latex_that_cannot_be_converted_is_shown_escaped_and_the_page_goes_on():
    broken = page.math(r"<b> \frac{1}{")
    assert Parsed(broken).elements == [("code", {"class": "math-error",
                                                 "title": "not converted to MathML (NoAvailableTokensError)"})]
    assert "&lt;b&gt;" in broken and "<b>" not in broken
    text = page.page("maths", page.markdown("good $x^2$, bad $\\frac{1}{$, good again $$y_1$$"))
    assert text.count("<math") == 2 and text.count('class="math-error"') == 1
    assert page.math(r"{}^{1}\dot v_{C}_{1}").startswith('<code class="math-error"')  # a double subscript


def test_latex_cannot_smuggle_markup_or_links_into_the_mathml():
    for latex in (r"\text{<script>alert(1)</script>}", r"\href{javascript:alert(1)}{x}", r"\style{color:red}{x}",
                  r'\color{red" onload="alert(1)}{x}', r"\mathrm{&lt;script&gt;}"):
        shown = page.math(latex)
        assert "<script" not in shown and "javascript:" not in shown and "style=" not in shown, latex
        assert {tag for tag, _ in Parsed(shown).elements} <= page.MATHML_TAGS | {"code"}, latex
        assert all("onload" not in attributes for _, attributes in Parsed(shown).elements), latex


# ---------------------------------------------------------------------------- the five kinds of page


def published(notebook) -> str:
    """A notebook as publish-notebooks writes it, with outputs of the kinds the course produces added to its cells."""
    import nbformat

    code = [c for c in notebook.cells if c.cell_type == "code"]
    code[0].outputs = [nbformat.v4.new_output("stream", name="stdout", text="price: $5 and $6\n"),
                       nbformat.v4.new_output("display_data", data={"text/markdown": f"$${CRAIG_6_48}$$ and ✅ **right**",
                                                                     "text/plain": "<IPython.core.display.Markdown>"}),
                       nbformat.v4.new_output("display_data", data={"text/latex": r"$\displaystyle \ddot\Theta$",
                                                                     "text/plain": "Θ̈"}),
                       nbformat.v4.new_output("display_data", data={"image/png": "iVBORw0KGgo=", "text/plain": "fig"})]
    return notebook_page(notebook)


@pytest.fixture(scope="module")
def notebook_pages():
    return {path.stem: published(solution_version(read_notebook(path), path.stem)) for path in notebook_paths()}


def test_published_notebooks_show_their_formulas_as_mathml(notebook_pages):
    for stem, text in notebook_pages.items():
        parsed = Parsed(text)
        prose = "".join(parsed.text)
        assert "$" not in prose, (stem, prose[max(0, prose.find("$") - 80):prose.find("$") + 80])
        assert 'class="math-error"' not in text, stem
        assert "price: $5 and $6" in text and "data:image/png;base64,iVBORw0KGgo=" in text and "✅" in text
    first = notebook_pages["01_acceleration"]
    assert first.count("<math") >= 15 and 'display="block"' in first  # (6.1), (6.10), (6.12), (6.15) and inline
    assert "<title>1. Acceleration of a rigid body" in first


@dataclass
class Diagnosed:
    """What the feedback pages read of a grader's diagnosis (its scoring is tested in test_grading.py)."""

    term: str
    points: float
    correct: bool
    lines: str
    tags: tuple[str, ...] = ()

    def text(self) -> str:
        return self.lines


def every_kind_of_page(tmp_path) -> dict[str, str]:
    """One page of each kind, built by the function that writes it."""
    from course_dynamics_reference.report import build_report, report_html

    from course_dynamics.grading import load_assignment
    from course_dynamics.grading.feedback import feedback_html, summary_html
    from course_dynamics.grading.grade import SubmissionGrade
    from course_dynamics.output.plotting import torques_page
    from course_dynamics.output.viewer import scene_document
    from course_dynamics.tools.logs import torques_from_log

    (tmp_path / "assignment.toml").write_text('robot = "two_link"\nsamples = 4\n[points]\nG = 10\nM = 10\n')
    assignment = load_assignment(tmp_path / "assignment.toml")
    diagnoses = [Diagnosed("G", 0.0, False, f"G: 0 / 10 points\n- {HOSTILE}", ("opposite sign",)),
                 Diagnosed("M", 10.0, True, "M: 10 / 10 points")]
    grade = SubmissionGrade(HOSTILE, tmp_path / "x.py", "ok", diagnoses=diagnoses, max_total=20.0, stdout=HOSTILE)
    arm = load_robot("two_link")
    t = np.linspace(0.0, 1.0, 101)
    table = {"t": t, **{f"q_{j}": np.sin(t + i) for i, j in enumerate(arm.joint_names)}}
    pendulum = load_robot("pendulum")
    scene, _ = scene_document(pendulum, robot_path("pendulum"), t=t[:11], q=np.sin(t[:11])[:, None])
    notebook = read_notebook(notebook_paths()[0])
    return {"notebook": published(notebook), "index": index_page([("01_acceleration", HOSTILE)]),
            "feedback": feedback_html(grade, assignment), "summary": summary_html([grade], assignment),
            "torques": torques_page(torques_from_log(arm, table), title=HOSTILE), "animation": scene,
            "report": report_html(build_report(["pendulum"], samples=3))}


def test_every_kind_of_page_shares_the_one_stylesheet_and_fetches_nothing(tmp_path):
    pages = every_kind_of_page(tmp_path)
    for kind, text in pages.items():
        assert text.startswith("<!DOCTYPE html>\n<html lang=\"en\">"), kind
        assert_offline_with_the_one_stylesheet(text)
        if kind != "animation":  # the viewer's own script, inlined, is the only script of any page
            assert "<script" not in text, kind
        assert "<img src=x" not in text and "<script>alert" not in text, kind
    assert pages["animation"].count("<script>") == 2 and 'class="viewer"' in pages["animation"]
    assert "<math" in pages["report"] and "<svg" in pages["report"] and "<svg" in pages["summary"]
    assert '<h2 class="bad">' in pages["feedback"] and '<h2 class="ok">' in pages["feedback"]


def test_a_published_page_typesets_its_mathml_offline(notebook_pages, tmp_path, browser):
    path = tmp_path / "01.html"
    path.write_text(notebook_pages["01_acceleration"])
    tab = browser.new_page(viewport={"width": 1000, "height": 800})
    requests = []
    tab.on("request", lambda request: requests.append(request.url))
    tab.goto(path.as_uri())
    tab.wait_for_load_state("load")
    boxes = tab.evaluate("""() => Array.from(document.querySelectorAll('math')).map(m => {
        const box = m.getBoundingClientRect(); return {width: box.width, height: box.height, ns: m.namespaceURI};
    })""")
    tab.close()
    assert len(boxes) >= 15 and all(b["ns"] == "http://www.w3.org/1998/Math/MathML" for b in boxes)
    assert all(b["width"] > 0 and b["height"] > 0 for b in boxes), boxes
    assert all(url.startswith(("file:", "data:")) for url in requests), requests


def test_a_figure_gives_the_same_bytes_every_time():
    # An SVG page published twice must not differ: no date in it, and element ids from a fixed salt.
    from course_dynamics.output import plotting

    def drawn(fmt):
        figure, axis = plotting.pyplot().subplots()
        axis.plot([0, 1, 2], [1, 0, 1])
        axis.set_title("τ(t)")
        return plotting.figure_bytes(figure, fmt)

    first = drawn("svg")
    assert first == drawn("svg") and b"<dc:date>" not in first
    assert drawn("png") == drawn("png")
