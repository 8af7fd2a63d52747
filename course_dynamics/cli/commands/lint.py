"""``course-dynamics lint``: a URDF's physics checked link by link and joint by joint, with the fix for each finding."""
from __future__ import annotations

import dataclasses
import json

from ..options import UsageError, add_all, print_json
from . import COMMANDS

HELP = COMMANDS["lint"]
DESCRIPTION = ("Read each URDF as written (what the loader refuses too) and report its findings: class, link or "
               "joint, line, severity (error, warning, note) and the fix. --json prints one document (ok, fail_on, "
               "files with their findings); --sarif FILE also writes them as a SARIF 2.1.0 log for code scanning "
               "(--sarif - prints only the log). A file that is no URDF at all (missing, too large, not XML, no "
               "<robot>) is a not-a-urdf finding. Exit 0 when no finding is as severe as --fail-on (default error), "
               "1 when one is, 2 when no file could be read at all.")


def add_arguments(parser) -> None:
    parser.add_argument("urdf", nargs="*", help="URDF files or robot names (default: every shipped robot)")
    add_all(parser, "--fail-on", "--sarif", "--json")


def _start_lines(report):
    """The findings with the line where their element's start tag starts (the parser gives the line it ends on)."""
    from ...base.errors import InputError
    from ...base.files import read_small
    from ...core.urdf import MAX_URDF_BYTES
    from ...output.xml_spans import elements

    try:
        raw = read_small(report.path, MAX_URDF_BYTES, "URDF file")
        root = elements(raw, str(report.path), depth=1)
    except InputError:  # positions unknown to the span reader: keep the parser's lines
        return report

    def line(offset):
        return raw.count(b"\n", 0, offset) + 1

    starts = {line(e.start_end - 1): line(e.start) for e in [root, *root.children]}
    findings = tuple(dataclasses.replace(f, line=starts.get(f.line, f.line)) for f in report.findings)
    return dataclasses.replace(report, findings=findings)


def _report(target):
    """The lint report of one file, or (None, the error) when it is no URDF at all."""
    from ...base.errors import InputError, ModelError
    from ...core.robots import resolve
    from ...tools.lint import lint_urdf

    try:
        return _start_lines(lint_urdf(resolve(target))), None
    except (ModelError, InputError) as error:
        return None, error


def run(args) -> int:
    from ...core.robots import robot_names
    from ...output import io
    from ...tools.lint import not_a_urdf, sarif

    if args.sarif == "-" and args.json:
        raise UsageError("--sarif - and --json would both print to standard output; give --sarif a file")
    targets = args.urdf or list(robot_names())
    if args.sarif:
        io.check_writable(args.sarif)
    results = [_report(target) for target in targets]
    if all(report is None for report, _ in results) and len(results) == 1:
        raise results[0][1]   # nothing to lint: the one-line error, exit 2
    reports = [report or not_a_urdf(target, error) for target, (report, error) in zip(targets, results)]
    read = any(report is not None for report, _ in results)
    ok = not any(report.fails(args.fail_on) for report in reports)
    status = 0 if ok else 1 if read else 2
    if args.sarif:
        io.write_text(args.sarif, json.dumps(sarif(reports), indent=1) + "\n")
        if args.sarif == "-":
            return status
    if args.json:
        print_json(dict(ok=ok, fail_on=args.fail_on, files=[report.as_dict() for report in reports]))
        return status
    for report in reports:
        for f in report.findings:
            print(f"{report.path}:{f.line or 0}: {f.severity} [{f.rule}] {f.message}")
            print(f"    fix: {f.fix}")
        counts = ", ".join(f"{report.count(s)} {s}{'' if report.count(s) == 1 else 's'}"
                           for s in ("error", "warning", "note"))
        unread = [f.rule for f in report.findings] == ["not-a-urdf"]
        print(f"{report.path}: {'not a URDF' if unread else f'robot {report.robot!r}'}: {counts}")
    return status
