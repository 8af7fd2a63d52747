"""The shared libraries a sandboxed Python needs, found from ELF headers as the dynamic loader finds them."""
from __future__ import annotations

import shutil
import sysconfig
from pathlib import Path

import numpy as np

from course_dynamics.grading.environment import base_interpreter, submission_environment, system_folders
from course_dynamics.grading.libraries import dynamic_section, elf_files, shared_libraries

NUMPY = Path(np.__file__).resolve().parent


def numpy_module_with_libraries() -> tuple[Path, list[str]]:
    """A compiled module of numpy's that loads libraries of numpy's own (its OpenBLAS), and their names."""
    for module in elf_files(NUMPY):
        needed, run_path = dynamic_section(module)
        own = [name for name in needed if (NUMPY.parent / "numpy.libs" / name).is_file()]
        if own:
            return module, own
    raise AssertionError("no numpy module loads a library of numpy.libs")


def test_the_interpreter_needs_the_c_library_and_text_is_no_elf(tmp_path):
    needed, _ = dynamic_section(base_interpreter())
    assert "libc.so.6" in needed
    (tmp_path / "fake.so").write_bytes(b"\x7fELF" + b"\x02\x01" + b"\0" * 10)  # a header and nothing after it
    (tmp_path / "text.so").write_text("not a library\n")
    assert dynamic_section(tmp_path / "fake.so") is None and dynamic_section(tmp_path / "text.so") is None
    assert dynamic_section(tmp_path / "missing.so") is None


def test_a_wheels_bundled_libraries_are_found_beside_it_and_are_the_packages_own():
    module, own = numpy_module_with_libraries()
    everything = shared_libraries([module], shown=system_folders())
    assert {p.name for p in everything} >= set(own)
    assert all(p.resolve().is_relative_to(NUMPY.parent / "numpy.libs") for p in everything)
    assert shared_libraries([module], shown=[*system_folders(), NUMPY, NUMPY.parent / "numpy.libs"]) == ()


def test_conda_libraries_are_found_in_its_lib_one_by_one(tmp_path):
    """conda's numpy finds libcblas in PREFIX/lib (through the interpreter's LIBDIR); only what it loads is taken."""
    module, own = numpy_module_with_libraries()
    prefix = tmp_path / "miniforge3"
    package = prefix / "lib" / "python3.11" / "site-packages" / "numpy" / "_core"
    package.mkdir(parents=True)
    shutil.copy2(module, package / module.name)
    for library in (NUMPY.parent / "numpy.libs").iterdir():
        shutil.copy2(library, prefix / "lib" / library.name)
    (prefix / "lib" / "libpinocchio_default.so").write_bytes((NUMPY.parent / "numpy.libs" / own[0]).read_bytes())
    found = shared_libraries([package / module.name], search=[prefix / "lib"], shown=system_folders())
    assert {p.name for p in found} >= set(own) and all(p.parent == prefix / "lib" for p in found)
    assert "libpinocchio_default.so" not in {p.name for p in found}


def test_this_pythons_environment_names_its_shared_library_and_nothing_in_a_packages_folder():
    environment = submission_environment()
    for library in environment.libraries:
        assert library.is_file() and not any(part in ("site-packages", "dist-packages") for part in library.parts)
    if sysconfig.get_config_var("Py_ENABLE_SHARED"):  # pyenv's and uv's builds: libpython3.X.so beside the stdlib
        assert sysconfig.get_config_var("INSTSONAME") in {p.name for p in environment.libraries}
        assert sysconfig.get_config_var("LIBDIR") in environment.library_path.split(":")
