"""A submission that looks for installed packages the way a determined student would, and reports what it found.

It removes the harness's import guard (so a forbidden name is looked up for
real), puts the site folders beside the standard library and any folder a test
names on its path (unless told not to hunt), lists and opens them, imports what is installed there, and
prints one line ``PROBE {json}``; its G (zeros, through numpy) gives a status
of ``ok`` whenever it ran to the end.
"""
from __future__ import annotations

import json

NAMES = ("sympy", "scipy", "yourdfpy", "pinocchio", "course_dynamics")

PROBE = '''
import importlib, json, os, sys
import numpy as np

sys.meta_path[:] = [f for f in sys.meta_path if type(f).__name__ != "ImportGuard"]
stdlib = os.path.dirname(os.__file__)
folders = [os.path.join(stdlib, "site-packages"), os.path.join(stdlib, "dist-packages"), *FOLDERS] if HUNT else []
listed, opened, imported = {}, {}, {}
for folder in folders:
    try:
        listed[folder] = sorted(os.listdir(folder))
    except OSError as exc:
        listed[folder] = type(exc).__name__
    try:
        with open(os.path.join(folder, "README.txt"), "rb") as handle:
            opened[folder] = len(handle.read())
    except OSError as exc:
        opened[folder] = type(exc).__name__
    sys.path.append(folder)
for name in NAMES:
    try:
        importlib.import_module(name)
        imported[name] = "imported"
    except Exception as exc:
        imported[name] = type(exc).__name__
print("PROBE " + json.dumps({"listed": listed, "opened": opened, "imported": imported, "path": sys.path,
                             "numpy": float(np.ones(3).sum()), "dynload": "lib-dynload" in os.listdir(stdlib),
                             "zlib": __import__("zlib").crc32(b"x")}))


def G(q):
    return np.zeros(2)
'''


def probe(names=NAMES, folders=(), hunt: bool = True) -> str:
    """The probe's source, importing ``names`` after putting ``folders`` and the site folders beside the standard
    library on its path (with ``hunt``; without, it imports from the path it was given)."""
    return f"NAMES = {tuple(names)!r}\nFOLDERS = {[str(f) for f in folders]!r}\nHUNT = {hunt!r}\n" + PROBE


def found(stdout: str) -> dict:
    """What the probe printed, as a dict."""
    line = next(line for line in stdout.splitlines() if line.startswith("PROBE "))
    return json.loads(line[len("PROBE "):])


def nothing_found(report: dict, names=NAMES) -> list[str]:
    """What the probe reached that it should not have (empty when everything installed stayed out of sight)."""
    wrong = [f"imported {name}" for name in names if report["imported"][name] == "imported"]
    wrong += [f"listed {folder}: {entries[:5]}" for folder, entries in report["listed"].items()
              if isinstance(entries, list)]
    wrong += [f"opened {folder}/README.txt" for folder, size in report["opened"].items() if isinstance(size, int)]
    if report["numpy"] != 3.0 or not report["dynload"]:
        wrong.append("numpy or lib-dynload missing")
    return wrong
