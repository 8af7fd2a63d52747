"""``course-dynamics publish-notebooks``: run the course and render it to static HTML pages with an index."""
from __future__ import annotations

import sys

from ..options import add_all, notebook_numbers, print_json, progress_bar
from . import COMMANDS

HELP = COMMANDS["publish_notebooks"]
DESCRIPTION = ("Execute the ten notebooks in fresh kernels and render each to OUTDIR/<notebook>.html (mathematics as "
               "MathML, readable offline), plus OUTDIR/index.html listing them. Student versions by default "
               "(exercises unanswered, checks saying 'not done yet'); --solutions publishes the worked answers. "
               "Animations are embedded and play offline. OUTDIR may hold other files: a run replaces only the pages "
               "an earlier run wrote there and nobody changed since (listed in OUTDIR/.course-dynamics-files.json), "
               "and refuses, before any notebook runs, when another file is in the way. --json: out, solutions, "
               "pages (the files written).")


def add_arguments(parser) -> None:
    parser.add_argument("out", metavar="OUTDIR", help="folder for the pages (made if missing)")
    add_all(parser, "--solutions", "--only", "--json", "--quiet")


def run(args) -> int:
    from ...teaching.course import notebook_paths, publish

    only = notebook_numbers(args)
    count = len([p for p in notebook_paths() if only is None or p.name[:2] in only])
    progress = progress_bar(args, total=count, unit="notebook", delay=0.0)
    written = publish(args.out, solutions=args.solutions, only=only, progress=progress.update)
    progress.close()
    if args.json:
        print_json(dict(out=str(args.out), solutions=args.solutions, pages=[str(p) for p in written]))
    pages = len(written) - 1
    print(f"wrote {pages} page{'s' if pages != 1 else ''} and {args.out}/index.html", file=sys.stderr)
    return 0
