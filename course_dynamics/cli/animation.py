"""The animation options that ``animate`` and ``simulate`` share, and the HTML export behind them."""
from __future__ import annotations

import sys
import warnings

from ..base.text import one_line
from .flags import add, add_all


def add_animation_options(parser, html_required: bool) -> None:
    add(parser, "--html", required=html_required)
    add_all(parser, "--geometry", "--torques", "--path", "--allow-any-mesh-path")


def animation_document(model, urdf, t, q, tau, args) -> str:
    """The HTML animation as text (nothing written); mesh warnings become ``warning: …`` lines on stderr."""
    from ..output.viewer import MeshWarning, scene_document

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", MeshWarning)
        document, _ = scene_document(model, urdf, args.geometry, t, q, tau if args.torques else None,
                                     args.draw_path, args.allow_any_mesh_path)
    for warning in caught:
        if issubclass(warning.category, MeshWarning):
            print(f"warning: {one_line(warning.message)}", file=sys.stderr)
        else:  # a library's own warning (pyzmq's deprecations on import): as Python would show it
            warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno)
    return document


def export_animation(path, model, urdf, t, q, tau, args) -> None:
    """Write the HTML animation to ``path``, whole or not at all."""
    from ..output import io

    io.write_text(path, animation_document(model, urdf, t, q, tau, args))
