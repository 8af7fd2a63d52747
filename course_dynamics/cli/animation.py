"""The animation options that ``animate`` and ``simulate`` share, and the HTML export behind them."""
from __future__ import annotations

import sys
import warnings

from ..viewer import GEOMETRIES


def add_animation_options(parser, html_required: bool) -> None:
    parser.add_argument("--html", required=html_required, help="write a self-contained HTML animation (opens offline)")
    parser.add_argument("--geometry", choices=GEOMETRIES, default="auto",
                        help="what to draw: URDF visual or collision meshes, or a stick model; auto picks the lightest "
                             "faithful one (default)")
    parser.add_argument("--torques", action="store_true", help="draw joint torques as bars along the joint axes")
    parser.add_argument("--path", dest="draw_path", action="store_true", help="draw the end-effector path")


def export_animation(path, model, urdf, t, q, tau, args) -> None:
    """Write the HTML animation; mesh warnings become ``warning: …`` lines on stderr."""
    from ..viewer import MeshWarning, export_html

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", MeshWarning)
        export_html(path, model, urdf, geometry=args.geometry, t=t, q=q, tau=tau if args.torques else None,
                    draw_path=args.draw_path)
    for warning in caught:
        print(f"warning: {warning.message}", file=sys.stderr)
