"""The library's docstring examples run and show what they print (doctest over every module of course_dynamics)."""
from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import course_dynamics

MODULES = sorted(name for _, name, _ in pkgutil.walk_packages(course_dynamics.__path__, "course_dynamics.")
                 if not name.endswith("__main__")) + ["course_dynamics"]


def test_there_are_examples():
    found = sum(len(doctest.DocTestFinder().find(importlib.import_module(name))) for name in MODULES)
    assert found >= 3


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples in {name} failed"
