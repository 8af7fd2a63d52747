"""Draw the package's layers as ``docs/_static/layers.svg``: one band per layer, its modules inside, from the
command line on top to the base at the bottom (a module imports only from its own layer and those below it,
which ``tests/test_layers.py`` holds). Run ``python3 docs/layers.py``; ``tests/test_docs.py`` checks that the
picture in the repository is the one this draws from the package as it is.
"""
from __future__ import annotations

import html
import os
import pkgutil
import tempfile
from pathlib import Path

LAYERS = [  # top to bottom
    ("cli", "the command line: one module per command, one grammar of flags"),
    ("teaching", "the course: exercises, checks, per-student robots, derivations"),
    ("grading", "students' code in a sandbox, diagnoses in Craig's terms, feedback, Gradescope"),
    ("output", "files, pages, plots, the identified URDF, the meshcat viewer"),
    ("tools", "simulation, logs and bags, limits, residuals, identification, excitation"),
    ("core", "the chapter: model, Newton–Euler, Lagrange, M, V, G, C, forward dynamics, compiled models"),
    ("base", "errors, files, text"),
]
WIDTH, PAD, LINE = 980, 14, 17
PER_LINE = 118  # characters of module names per line inside a band


def modules_of(layer: str) -> list[str]:
    import course_dynamics

    root = Path(course_dynamics.__file__).parent / layer
    return sorted(name for _, name, _ in pkgutil.walk_packages([str(root)]) if name != "__main__")


def wrap(names: list[str]) -> list[str]:
    lines, line = [], ""
    for name in names:
        if line and len(line) + 2 + len(name) > PER_LINE:
            lines.append(line + ",")
            line = name
        else:
            line = f"{line}, {name}" if line else name
    return lines + [line] if line else lines


def svg() -> str:
    """The picture, as SVG text (system fonts only: nothing is fetched)."""
    bands, y = [], PAD
    for layer, role in LAYERS:
        lines = wrap(modules_of(layer))
        height = PAD + LINE * (2 + len(lines)) + PAD // 2
        text = [f'<text x="{PAD * 2}" y="{y + PAD + LINE}" class="name">{html.escape(layer)}</text>',
                f'<text x="{PAD * 2 + 90}" y="{y + PAD + LINE}" class="role">{html.escape(role)}</text>']
        text += [f'<text x="{PAD * 2}" y="{y + PAD + LINE * (2 + i) + 2}" class="mods">{html.escape(line)}</text>'
                 for i, line in enumerate(lines)]
        bands.append(f'<rect x="{PAD}" y="{y}" width="{WIDTH - 3 * PAD - 40}" height="{height}" rx="6"/>'
                     + "".join(text))
        y += height + PAD
    arrow_x = WIDTH - PAD - 30
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{y}" viewBox="0 0 {WIDTH} {y}" '
            'font-family="sans-serif">\n'
            '<style>rect{fill:#f3f6fa;stroke:#5b7083;stroke-width:1.2} .name{font-weight:bold;font-size:15px} '
            '.role{font-size:13px;fill:#333} .mods{font-size:12px;fill:#2b5d8a;font-family:monospace} '
            '.note{font-size:12px;fill:#333}</style>\n'
            f'<line x1="{arrow_x}" y1="{PAD + 10}" x2="{arrow_x}" y2="{y - PAD - 12}" stroke="#5b7083" '
            'stroke-width="2"/>'
            f'<path d="M{arrow_x - 7},{y - PAD - 22} L{arrow_x},{y - PAD - 6} L{arrow_x + 7},{y - PAD - 22} z" '
            'fill="#5b7083"/>'
            f'<text x="{arrow_x + 14}" y="{y // 2}" class="note" transform="rotate(90 {arrow_x + 14} {y // 2})" '
            'text-anchor="middle">imports only downward</text>\n'
            + "\n".join(bands) + "\n</svg>\n")


def main() -> None:
    target = Path(__file__).resolve().parent / "_static" / "layers.svg"
    descriptor, temporary = tempfile.mkstemp(dir=target.parent, prefix=".layers-", suffix=".svg")
    try:
        with os.fdopen(descriptor, "w") as handle:
            handle.write(svg())
        os.chmod(temporary, 0o644)
        os.replace(temporary, target)
    except BaseException:
        os.unlink(temporary)
        raise
    print(target)


if __name__ == "__main__":
    main()
