"""The package as a whole: course_dynamics never imports Pinocchio, and its docstring examples run."""
from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import course_dynamics

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
