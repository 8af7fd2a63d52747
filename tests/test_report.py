"""reference/report.py and `course-dynamics report`: the comparison report, its files, and the page in a real browser."""
from __future__ import annotations

import json

import pytest
from course_dynamics_reference.report import errata_count
from helpers import AWKWARD, ROOT

from course_dynamics.cli import main
from course_dynamics.output.folders import MANIFEST


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "site"
    code = main(["report", "two_link", str(AWKWARD), "--out", str(out), "--samples", "30", "--seed", "4", "--quiet"])
    return code, out


def test_report_files_and_json(report):
    code, out = report
    assert code == 0
    assert {p.name for p in out.iterdir()} == {"index.html", "report.md", "report.json", "figures", MANIFEST}
    document = json.loads((out / "report.json").read_text())
    assert [r["name"] for r in document["robots"]] == ["two_link", "awkward.urdf"]
    assert [r["urdf"] for r in document["robots"]] == ["two_link.urdf", "awkward.urdf"]  # a file name, never a path
    assert str(out.parent) not in (out / "report.json").read_text() and "site-packages" not in (out / "report.json").read_text()
    for robot in document["robots"]:
        assert set(robot["terms"]) == {"tau", "M", "C", "V", "G"}
        for term in robot["terms"].values():
            assert set(term) >= {"max", "median", "max_relative", "median_relative"}
            assert term["max_relative"] <= 1e-9 and term["agrees"]
        assert robot["trajectory"]["max_abs_difference"] <= 1e-9 * robot["trajectory"]["max_abs_tau"]
    assert document["robots"][0]["textbook"]["M"] <= 1e-12 and document["robots"][1]["textbook"] is None
    assert set(document["environment"]) >= {"python", "numpy", "pinocchio", "course-dynamics", "seed", "date"}
    assert document["environment"]["seed"] == 4 and document["misprints_in_the_notes"] == errata_count() >= 19


def test_markdown_links_its_figures(report):
    _, out = report
    text = (out / "report.md").read_text()
    for line in text.splitlines():
        if line.startswith("!["):
            assert (out / line.split("(")[1].rstrip(")")).is_file()
    assert "## two" in text and "| τ (inverse dynamics) |" in text


def test_page_draws_every_figure_offline_without_errors(report, browser):
    _, out = report
    page = browser.new_page(viewport={"width": 1000, "height": 800})
    requests, errors = [], []
    page.on("request", lambda request: requests.append(request.url))
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.on("console", lambda message: message.type == "error" and errors.append(message.text))
    page.goto((out / "index.html").as_uri())
    page.wait_for_load_state("load")
    figures = page.evaluate("""() => Array.from(document.querySelectorAll('figure svg')).map(svg => {
        const box = svg.getBoundingClientRect();
        return {width: box.width, height: box.height, paths: svg.querySelectorAll('path').length};
    })""")
    page.close()
    assert len(figures) == 4
    assert all(f["width"] > 300 and f["height"] > 100 and f["paths"] > 20 for f in figures), figures
    assert errors == []
    assert all(url.startswith("file:") for url in requests), requests


def test_names_from_a_urdf_are_escaped(tmp_path):
    hostile = AWKWARD.read_text().replace('<robot name="awkward">', '<robot name="&lt;script&gt;alert(1)&lt;/script&gt;">')
    hostile = hostile.replace('name="shoulder"', 'name="&lt;img src=x onerror=alert(2)&gt;"')
    (tmp_path / "hostile.urdf").write_text(hostile)
    assert main(["report", str(tmp_path / "hostile.urdf"), "--out", str(tmp_path / "out"), "--samples", "3", "--quiet"]) == 0
    page = (tmp_path / "out" / "index.html").read_text()
    markdown = (tmp_path / "out" / "report.md").read_text()
    for text in (page, markdown):
        assert "<script>" not in text and "<img" not in text
    assert "&lt;img src=x onerror=alert(2)&gt;" in page


@pytest.mark.parametrize("argv, message", [
    (["report", "r2d2", "--out", "o"], "'r2d2' is neither a URDF file nor a shipped robot"),
    (["report", "two_link", "--out", "o", "--samples", "0"], "--samples must be between 1 and"),
    (["report", "two_link"], "the following arguments are required: --out"),
])
def test_bad_report_arguments(tmp_path, monkeypatch, capsys, argv, message):
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and message in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


def test_errata_count_matches_the_document():
    text = (ROOT / "reference" / "errata.md").read_text()
    table = text.split("## Misprints")[1].split("## Found correct")[0]
    rows = [line for line in table.splitlines() if line.startswith("| ") and not line.startswith("| where")]
    assert errata_count() == len(rows)


def test_a_report_folder_is_rewritten_but_files_it_did_not_write_are_never_touched(tmp_path, capsys):
    out = tmp_path / "site"
    argv = ["report", "pendulum", "--samples", "2", "--out", str(out), "--quiet"]
    assert main(argv) == 0
    (out / "notes.md").write_text("the instructor's notes")
    (out / "figures" / "logo.svg").write_text("<svg/>")
    assert main(argv) == 0  # its own files, unchanged since: replaced
    assert (out / "notes.md").read_text() == "the instructor's notes" and (out / "figures" / "logo.svg").exists()
    listed = json.loads((out / MANIFEST).read_text())["files"]
    assert sorted(listed) == ["figures/robot0_errors.svg", "figures/robot0_trajectory.svg", "index.html",
                              "report.json", "report.md"]
    capsys.readouterr()
    (out / "report.md").write_text("edited by hand")
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "report.md: was changed since course-dynamics report wrote it" in err
    assert "nothing was written" in err
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before


def test_a_report_refuses_an_index_it_did_not_write_before_computing(tmp_path, capsys):
    out = tmp_path / "site"
    out.mkdir()
    (out / "index.html").write_text("the course's page")
    assert main(["report", "two_link", "--out", str(out), "--quiet"]) == 2  # 200 samples: refused before they run
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "index.html: exists and was not written by course-dynamics" in err
    assert sorted(p.name for p in out.iterdir()) == ["index.html"]


def test_a_report_whose_samples_do_not_fit_is_refused_before_computing(tmp_path, capsys, monkeypatch):
    import course_dynamics_reference.report as report_module
    from helpers import assert_one_line_error, run

    monkeypatch.setenv("COURSE_DYNAMICS_MEMORY_BUDGET", "330M")
    monkeypatch.setattr(report_module, "build_report", lambda *a, **k: pytest.fail("computed before checking"))
    out = tmp_path / "site"
    code, _, err = run(capsys, "report", "two_link", "--samples", "100000", "--out", str(out))
    assert_one_line_error(code, err, "on --samples 100000 states", "take fewer --samples")
    assert not out.exists()
