"""The animation options that ``animate`` and ``simulate`` share, and the HTML export behind them."""
from __future__ import annotations

from .flags import add, add_all


def add_animation_options(parser, html_required: bool) -> None:
    add(parser, "--html", required=html_required)
    add_all(parser, "--geometry", "--torques", "--path", "--allow-any-mesh-path")


def animation_document(model, urdf, t, q, tau, args) -> str:
    """The HTML animation as text (nothing written); a mesh not drawn is a ``MeshWarning`` (a ``warning: …`` line)."""
    from ..output.viewer import scene_document

    document, _ = scene_document(model, urdf, args.geometry, t, q, tau if args.torques else None,
                                 args.draw_path, args.allow_any_mesh_path)
    return document


def export_animation(path, model, urdf, t, q, tau, args) -> None:
    """Write the HTML animation to ``path``, whole or not at all."""
    from ..output import io

    io.write_text(path, animation_document(model, urdf, t, q, tau, args))
