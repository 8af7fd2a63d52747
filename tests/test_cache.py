"""course_dynamics/core/compiled/cache.py: the folder and files the cache makes have the modes its own trust
rule asks for whatever the umask, and a parent its group can write (``~/.cache`` under ``umask 002``) is fine."""
from __future__ import annotations

import os
import stat
import subprocess
import sys

import pytest

from course_dynamics import load_robot
from course_dynamics.core.compiled import CacheWarning, compile_model

RUN = """
import warnings
warnings.simplefilter("always")
from course_dynamics import load_robot
from course_dynamics.core.compiled import compile_model
print(compile_model(load_robot("two_link"), native_code=False).from_cache)
"""


def mode(path) -> int:
    return stat.S_IMODE(os.lstat(path).st_mode)


@pytest.mark.parametrize("parent", ["made by the cache", "group-writable, made by the user"])
def test_under_umask_002_the_cache_is_made_private_and_reused(tmp_path, parent):
    home, xdg = tmp_path / "home", tmp_path / "xdg"
    home.mkdir()
    if parent != "made by the cache":
        xdg.mkdir()
        xdg.chmod(0o775)  # what mkdir makes under umask 002
    environment = {k: v for k, v in os.environ.items() if k != "COURSE_DYNAMICS_CACHE"}
    environment.update(HOME=str(home), XDG_CACHE_HOME=str(xdg))
    outputs = [subprocess.run([sys.executable, "-c", RUN], env=environment, capture_output=True, text=True,
                              umask=0o002, timeout=120) for _ in range(2)]
    for done in outputs:
        assert done.returncode == 0 and "warning" not in done.stderr.lower(), done.stderr
    assert [done.stdout.strip() for done in outputs] == ["False", "True"]  # the second run used the cache
    folder = xdg / "course-dynamics"
    assert mode(folder) == 0o700 and mode(xdg) == (0o700 if parent == "made by the cache" else 0o775)
    assert {mode(path) for path in folder.iterdir()} == {0o600}  # the secret and the entry


def test_files_keep_their_modes_whatever_the_umask(tmp_path, monkeypatch):
    """A umask that would leave the user no access still gives a cache the user can read back."""
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "deep" / "cache"))
    old = os.umask(0o377)
    try:
        compile_model(load_robot("pendulum"), native_code=False)
    finally:
        os.umask(old)
    assert mode(tmp_path / "deep") == mode(tmp_path / "deep" / "cache") == 0o700
    assert {mode(p) for p in (tmp_path / "deep" / "cache").iterdir()} == {0o600}
    assert compile_model(load_robot("pendulum"), native_code=False).from_cache


def test_a_parent_anyone_can_write_is_refused_with_its_fix(tmp_path, monkeypatch):
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777)  # not sticky: anyone could replace what is in it
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(shared / "cache"))
    with pytest.warns(CacheWarning, match=f"other users can write to the folder {shared} above it "
                                          rf"\(mode 777; chmod o-w {shared}\)"):
        assert compile_model(load_robot("pendulum"), native_code=False).path is None
