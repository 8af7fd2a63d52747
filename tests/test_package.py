"""The package as a whole: course_dynamics never imports Pinocchio, and its docstring examples run."""
from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import course_dynamics
from helpers import venv_seeing_this_environment

PACKAGE = Path(course_dynamics.__file__).parent


def test_no_module_imports_pinocchio_statically():
    for path in PACKAGE.rglob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""]
            else:
                continue
            assert not any(n.split(".")[0] == "pinocchio" for n in names), f"{path.name} imports pinocchio"


def test_using_the_library_loads_no_pinocchio():
    """Import every module and compute everything; Pinocchio must not be in sys.modules."""
    modules = sorted(".".join(p.relative_to(PACKAGE).with_suffix("").parts) for p in PACKAGE.rglob("*.py")
                     if p.stem not in ("__init__", "__main__"))
    script = (
        "import sys, importlib\n"
        f"for m in {modules!r}: importlib.import_module('course_dynamics.' + m)\n"
        "import course_dynamics as cd\n"
        "arm = cd.load_robot('panda')\n"
        "q = [0.1] * arm.n\n"
        "cd.dynamics_terms(arm, q, q, q)\n"
        "from course_dynamics.cli import main\n"
        "main(['terms', 'ur5', '--q', '0,0,0,0,0,0', '--json'])\n"
        "assert 'pinocchio' not in sys.modules, 'pinocchio was imported'\n"
        "print('clean')\n"
    )
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip().endswith("clean")


def test_a_users_own_reference_folder_does_not_shadow_the_oracle(tmp_path):
    """The oracle installs as course_dynamics_reference, so a reference/ package in the working folder is never imported."""
    (tmp_path / "reference").mkdir()
    (tmp_path / "reference" / "__init__.py").write_text("raise RuntimeError('the user reference package was imported')\n")
    (tmp_path / "reference" / "validate.py").write_text("raise RuntimeError('the user reference package was imported')\n")
    result = subprocess.run([sys.executable, "-m", "course_dynamics.cli", "validate", "two_link", "--samples", "3"],
                            cwd=tmp_path, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert "all robots agree" in result.stdout


def test_a_non_editable_install_runs_from_any_folder(tmp_path):
    """``pip install .`` (not editable) ships the robots, the errata and the notebooks as package data."""
    import shutil

    root = Path(__file__).resolve().parent.parent
    source = tmp_path / "source"
    shutil.copytree(root, source, ignore=shutil.ignore_patterns(".git", "__pycache__", "build", "*.egg-info",
                                                                ".pytest_cache", ".ruff_cache"))
    venv = tmp_path / "venv"
    python = venv_seeing_this_environment(venv, pip=True)
    install = subprocess.run([python, "-m", "pip", "install", "-q", "--no-deps", str(source)],
                             capture_output=True, text=True)
    assert install.returncode == 0, install.stderr
    shutil.rmtree(source)  # nothing may be read from the checkout
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    check = subprocess.run(
        [python, "-c", "import course_dynamics, course_dynamics_robots as r, course_dynamics_reference.report as rep\n"
                       "from course_dynamics.teaching.course import notebook_paths\n"
                       "from course_dynamics.core.robots import ROBOTS_DIR\n"
                       "print(course_dynamics.__file__, ROBOTS_DIR, rep.errata_count(), len(notebook_paths()))"],
        cwd=elsewhere, capture_output=True, text=True)
    assert check.returncode == 0, check.stderr
    module, robots, errata, notebooks = check.stdout.split()
    assert module.startswith(str(venv)) and robots.startswith(str(venv)), check.stdout
    assert int(errata) > 0 and int(notebooks) == 10
    for argv in (["validate", "two_link", "--samples", "3"], ["info", "rp_arm"], ["terms", "pendulum", "--q", "0.3"]):
        result = subprocess.run([venv / "bin" / "course-dynamics", *argv], cwd=elsewhere, capture_output=True, text=True)
        assert result.returncode == 0, (argv, result.stderr)
    assert "all robots agree" in subprocess.run([venv / "bin" / "course-dynamics", "validate", "two_link", "--samples",
                                                 "3"], cwd=elsewhere, capture_output=True, text=True).stdout
