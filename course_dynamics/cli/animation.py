"""The animation options that ``animate`` and ``simulate`` share, and the HTML export behind them."""
from __future__ import annotations

import sys
import warnings

from ..output.viewer import GEOMETRIES


def add_animation_options(parser, html_required: bool) -> None:
    parser.add_argument("--html", required=html_required, help="write a self-contained HTML animation (opens offline)")
    parser.add_argument("--geometry", choices=GEOMETRIES, default="auto",
                        help="what to draw: URDF visual or collision meshes, or a stick model; auto picks the lightest "
                             "faithful one (default)")
    parser.add_argument("--torques", action="store_true", help="draw joint torques as bars along the joint axes")
    parser.add_argument("--path", dest="draw_path", action="store_true", help="draw the end-effector path")
    parser.add_argument("--allow-any-mesh-path", action="store_true",
                        help="read mesh files outside the URDF's folder and its packages (by default they are not "
                             "read, and the stick model is drawn: the HTML file would carry them to whoever opens it)")


def animation_document(model, urdf, t, q, tau, args) -> str:
    """The HTML animation as text (nothing written); mesh warnings become ``warning: …`` lines on stderr."""
    from ..output.viewer import MeshWarning, scene_document

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", MeshWarning)
        document, _ = scene_document(model, urdf, args.geometry, t, q, tau if args.torques else None,
                                     args.draw_path, args.allow_any_mesh_path)
    from ..output.render import one_line

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
