"""Sphinx configuration of the course-dynamics site: MyST Markdown pages, the API reference from the numpydoc
docstrings (autodoc + napoleon), the CLI reference from the argparse parsers (``_ext/course_dynamics_docs.py``).

Built offline (no intersphinx, nothing fetched) with warnings as errors:
``python3 -m sphinx -W --keep-going -b html docs docs/_build/html``. The pages open from disk.
"""
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))

project = "course-dynamics"
author = "the course-dynamics authors"
copyright = "the course-dynamics authors"

extensions = ["sphinx.ext.autodoc", "sphinx.ext.napoleon", "myst_parser", "course_dynamics_docs"]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "pictures/*.py", "**/__pycache__"]
root_doc = "index"

# Every cross-reference must resolve; names of other libraries (numpy, sympy, the standard library) are not
# documented here and no inventory is fetched, so they are plain text.
nitpicky = True
nitpick_ignore_regex = [
    (r"py:.*", r"(numpy|np|sympy|sp|scipy|pathlib|typing|collections|collections\.abc|os|io|argparse|subprocess|"
               r"threading|concurrent\.futures|types|enum|dataclasses|datetime|matplotlib|trimesh|meshcat|yourdfpy|"
               r"rosbags|cvxpy|jinja2|markupsafe|nbformat|nbclient|importlib|tqdm|warnings|re|json|tempfile|zipfile|tarfile|csv|ast|"
               r"contextlib|functools|itertools|logging|signal|socket|http|urllib)(\..*)?"),
    (r"py:.*", r"(int|float|str|bytes|bool|dict|list|tuple|set|frozenset|object|type|None|callable|Callable|"
               r"Iterable|Iterator|Sequence|Mapping|Any|Path|array|ndarray|array_like|optional|default|"
               r"Exception|ValueError|TypeError|OSError|KeyError|RuntimeError|Warning|UserWarning|"
               r"BaseException|MemoryError|KeyboardInterrupt|TimeoutError|FileNotFoundError|PermissionError)"),
]

autodoc_default_options = {}
autodoc_member_order = "bysource"
# Types are in each docstring's Parameters and Returns, with shapes and units; signatures show names and defaults.
autodoc_typehints = "none"
autodoc_preserve_defaults = True
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
# Parameters as one field of their own, their types as written: "numpy.ndarray, shape (N, n)" is a description,
# not a list of names to cross-reference.
napoleon_use_param = False
napoleon_use_ivar = True

myst_heading_anchors = 4
myst_enable_extensions = ["colon_fence", "deflist"]

html_theme = "furo"
html_title = "course-dynamics"
html_static_path = ["_static"]
html_show_sourcelink = False
html_copy_source = False
html_last_updated_fmt = None
# A search result's summary is fetched from its page, which a browser refuses for pages opened from disk.
html_show_search_summary = False

# Flags stay as typed: "--json" must not become an en dash.
smartquotes = False
