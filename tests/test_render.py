"""course_dynamics/output/render.py: tables, the trace in three formats, typeset derivations, strict JSON."""
from __future__ import annotations

import json
import re

import pytest
from helpers import derivation

from course_dynamics import load_robot
from course_dynamics.output.render import (
    derivation_record,
    derivation_text,
    json_text,
    text_table,
    trace_latex,
    trace_record,
    trace_table,
)
from course_dynamics.tools.trace import trace


def test_trace_formats():
    t = trace(load_robot("rp_arm"), [0.3, 0.5], [1.0, -0.2], [0.1, 0.4])
    table = trace_table(t)
    assert "Outward iteration" in table and "(6.35)" in table and "tau_2" in table and "(6.44)" in table
    latex = trace_latex(t)
    assert latex.count(r"\begin{align*}") == 2 and r"{}^{2}\dot v_{C_{2}}" in latex and "}_{" not in latex
    record = trace_record(t)
    assert record["joints"] == ["theta1", "d2"] and set(record["links"][0]) >= {"omega", "v_dot_c", "f", "n", "tau"}
    json.loads(json_text(record))


def test_text_table_aligns_columns():
    lines = text_table([["joint", "tau"], ["theta1", "1.5"], ["d2", "-20"]]).splitlines()
    assert lines == ["joint   tau", "theta1  1.5", "d2      -20"]


def test_markdown_derivation_keeps_latex_inside_math():
    """Every backslash command of the Markdown text sits between $ delimiters, so it renders anywhere."""
    text = derivation_text(derivation("two_link", ("m1", "m2", "l1", "l2", "g")), "markdown")
    outside = re.sub(r"\$\$.*?\$\$|\$.*?\$", "", text, flags=re.S)
    assert "\\" not in outside, outside
    assert "$$ M(\\Theta)" in text


def test_derivation_record_is_strings():
    record = derivation_record(derivation("pendulum", ("m", "l", "g")))
    assert list(record) == ["joints", "tau", "M", "V", "G", "B", "C"]
    assert all(isinstance(x, str) for x in record["tau"])


def test_json_refuses_nan():
    with pytest.raises(ValueError):
        json_text({"x": float("nan")})


def test_bare_urls_in_a_students_text_never_become_links():
    """A renderer links a bare URL by itself; in inline code it stays text (the Markdown feedback quotes exceptions)."""
    from course_dynamics.output import page
    from course_dynamics.output.render import markdown_escape

    text = "RuntimeError: log in at http://evil.example/login?a=1|b or www.evil.example, mail a@evil.example"
    assert "<a " in page.markdown(text)  # the renderer would link it
    rendered = page.markdown(markdown_escape(text))
    assert "<a " not in rendered and "<code>http://evil.example/login?a=1%7Cb</code>" in rendered
    assert "<code>www.evil.example,</code>" in rendered and "<code>a@evil.example</code>" in rendered
    assert markdown_escape("x ``` http://a.example/```") == "x \\`\\`\\` ```` http://a.example/``` ````"
