"""``course-dynamics``: the command line, a thin layer over the library.

Every command reads a URDF (or the name of a shipped robot), calls
course_dynamics, and prints a table or, with ``--json``, one JSON document.
Bad input of any kind ends with one line ``error: …`` on stderr and exit code 2;
no output file is left behind half-written.
"""
from __future__ import annotations

import argparse
import csv
import io
import json
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

from .dynamics import dynamics_terms
from .model import ModelError
from .newton_euler import inverse_dynamics
from .robots import resolve, robot_names
from .state import StateError
from .urdf import load_urdf

VALUE_OPTIONS = ("--q", "--qd", "--qdd", "--gravity", "--q0", "--qd0", "--torque", "--viscous", "--coulomb")


class UsageError(ValueError):
    """Bad command-line input (reported as ``error: …``, exit 2)."""


class Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2, as for every other bad input
        raise UsageError(message)


def _values(text: str, option: str) -> np.ndarray:
    try:
        values = [float(v) for v in text.split(",") if v.strip() != ""]
    except ValueError:
        raise UsageError(f"{option} must be comma-separated numbers, got '{text}'") from None
    return np.array(values)


def _load(target: str, gravity=None):
    path = resolve(target)
    if not path.exists() and not path.suffix:
        raise UsageError(f"'{target}' is neither a URDF file nor a shipped robot ({', '.join(robot_names())})")
    return load_urdf(path) if gravity is None else load_urdf(path, gravity=gravity)


def _gravity(args):
    if args.gravity is None:
        return None
    g = _values(args.gravity, "--gravity")
    if g.shape != (3,) or not np.all(np.isfinite(g)):
        raise UsageError(f"--gravity needs three finite numbers gx,gy,gz, got '{args.gravity}'")
    return g


def _print_json(document) -> None:
    json.dump(document, sys.stdout, indent=2)
    sys.stdout.write("\n")


def cmd_info(args) -> int:
    model = _load(args.urdf)
    joints = [
        dict(index=j, name=b.joint, type=b.joint_type, axis=b.axis.tolist(),
             lower=None if not np.isfinite(b.lower) else b.lower, upper=None if not np.isfinite(b.upper) else b.upper,
             parent_link=b.parent_link,
             damping=b.damping, friction=b.friction)
        for j, b in enumerate(model.bodies)
    ]
    bodies = [dict(link=b.name, joint=b.joint, mass=float(b.mass), com=b.p_com.tolist()) for b in model.bodies]
    if args.json:
        _print_json(dict(robot=model.name, urdf=model.source, base_link=model.base_link, n=model.n,
                         gravity=model.gravity.tolist(), joints=joints, bodies=bodies))
        return 0
    print(f"robot {model.name} ({model.source}): {model.n} joints, base link '{model.base_link}', gravity {model.gravity.tolist()} m/s²")
    print(f"{'#':>2}  {'joint':<24} {'type':<10} {'axis':<24} {'limits':<22} parent link")
    for j in joints:
        limits = "-" if j["lower"] is None else f"[{j['lower']:g}, {j['upper']:g}]"
        axis = "(" + ", ".join(f"{a:.4g}" for a in j["axis"]) + ")"
        print(f"{j['index']:>2}  {j['name']:<24} {j['type']:<10} {axis:<24} {limits:<22} {j['parent_link']}")
    print(f"\n{'moving body':<26} {'mass (kg)':>10}  COM in body frame (m)")
    for b in bodies:
        print(f"{b['link']:<26} {b['mass']:>10.4g}  (" + ", ".join(f"{c:.4g}" for c in b["com"]) + ")")
    return 0


def cmd_terms(args) -> int:
    gravity = _gravity(args)
    model = _load(args.urdf, gravity)
    q = _values(args.q, "--q")
    qd = _values(args.qd, "--qd") if args.qd is not None else np.zeros(model.n)
    qdd = _values(args.qdd, "--qdd") if args.qdd is not None else np.zeros(model.n)
    terms = dynamics_terms(model, q, qd, qdd)
    document = dict(joints=list(terms.joints), tau=terms.tau.tolist(), M=terms.M.tolist(), C=terms.C.tolist(),
                    V=terms.V.tolist(), G=terms.G.tolist())
    if args.json:
        _print_json(document)
        return 0
    width = max(len(name) for name in terms.joints)
    print(f"robot {model.name}: tau = M(q) qdd + V(q, qd) + G(q)   (N·m, or N for prismatic joints)")
    print(f"{'joint':<{width}}  {'tau':>12} {'V':>12} {'G':>12}")
    for name, tau, V, G in zip(terms.joints, terms.tau, terms.V, terms.G):
        print(f"{name:<{width}}  {tau:>12.6g} {V:>12.6g} {G:>12.6g}")
    for label, matrix in (("M(q)", terms.M), ("C(q, qd)", terms.C)):
        print(f"\n{label}:")
        for name, row in zip(terms.joints, matrix):
            print(f"{name:<{width}}  " + " ".join(f"{x:>12.6g}" for x in row))
    return 0


def read_columns(path: Path, required: list[str], optional: list[str] = ()) -> dict[str, np.ndarray]:
    """The named columns of a CSV file, checked: every required one present, no unknown one, all finite."""
    try:
        text = path.read_text()
    except OSError as exc:
        raise UsageError(f"{path}: cannot read: {exc.strerror}") from None
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        raise UsageError(f"{path}: empty file, expected a header row")
    header = [h.strip() for h in rows[0]]
    missing = [c for c in required if c not in header]
    extra = [c for c in header if c not in required and c not in optional]
    if missing:
        raise UsageError(f"{path}: missing columns: {', '.join(missing)}")
    if extra:
        raise UsageError(f"{path}: unexpected columns: {', '.join(extra)} (expected {', '.join(required)})")
    if len(rows) < 2:
        raise UsageError(f"{path}: no data rows")
    data = np.empty((len(rows) - 1, len(header)))
    for r, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise UsageError(f"{path}: line {r} has {len(row)} values, the header has {len(header)}")
        for c, value in enumerate(row):
            try:
                data[r - 2, c] = float(value)
            except ValueError:
                raise UsageError(f"{path}: line {r}, column '{header[c]}': '{value}' is not a number") from None
            if not np.isfinite(data[r - 2, c]):
                raise UsageError(f"{path}: line {r}, column '{header[c]}': value is {value} (must be finite)")
    return {name: data[:, header.index(name)] for name in header}


def _joint_columns(kinds, joints) -> list[str]:
    return [f"{kind}_{j}" for kind in kinds for j in joints]


def read_trajectory(path: Path, joints) -> dict[str, np.ndarray]:
    """Columns t, q_<joint>, qd_<joint>, qdd_<joint>; a simulate output's tau_<joint> and energy are allowed."""
    return read_columns(path, ["t"] + _joint_columns(("q", "qd", "qdd"), joints),
                        _joint_columns(("tau",), joints) + ["energy"])


def write_csv_atomically(path: Path, header: list[str], data: np.ndarray) -> None:
    """Write the whole file or nothing: a temporary file renamed into place."""
    directory = path.parent if str(path.parent) else Path(".")
    if not directory.is_dir():
        raise UsageError(f"{path}: directory {directory} does not exist")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=directory)
    except OSError as exc:
        raise UsageError(f"{path}: cannot write: {exc.strerror}") from None
    try:
        with os.fdopen(fd, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(header)
            writer.writerows([[repr(float(x)) for x in row] for row in data])
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def cmd_torques(args) -> int:
    model = _load(args.urdf)
    columns = read_trajectory(Path(args.trajectory), model.joint_names)
    q, qd, qdd = (_stack(columns, kind, model.joint_names) for kind in ("q", "qd", "qdd"))
    tau = inverse_dynamics(model, q, qd, qdd)
    header = ["t"] + [f"tau_{j}" for j in model.joint_names]
    write_csv_atomically(Path(args.out), header, np.column_stack([columns["t"], tau]))
    print(f"wrote {len(tau)} rows of joint torques to {args.out}", file=sys.stderr)
    return 0


def _stack(columns: dict, kind: str, joints) -> np.ndarray:
    return np.column_stack([columns[f"{kind}_{j}"] for j in joints])


def _joint_values(text, option: str, model, default=None) -> np.ndarray:
    if text is None:
        return np.zeros(model.n) if default is None else default
    values = _values(text, option)
    if values.shape != (model.n,):
        raise UsageError(f"{option} has {len(values)} values but robot '{model.name}' has {model.n} joints ({', '.join(model.joint_names)})")
    if not np.all(np.isfinite(values)):
        raise UsageError(f"{option} must be finite, got '{text}'")
    return values


def cmd_simulate(args) -> int:
    from .friction import Friction
    from .simulation import TorqueTable, simulate

    model = _load(args.urdf)
    q0 = _joint_values(args.q0, "--q0", model)
    qd0 = _joint_values(args.qd0, "--qd0", model)
    torque = None
    if args.torque is not None:
        torque = _joint_values(args.torque, "--torque", model)
    elif args.torque_csv is not None:
        columns = read_columns(Path(args.torque_csv), ["t"] + _joint_columns(("tau",), model.joint_names),
                               _joint_columns(("q", "qd", "qdd"), model.joint_names) + ["energy"])
        torque = TorqueTable(columns["t"], _stack(columns, "tau", model.joint_names))
    friction = None
    if args.friction == "urdf" or args.viscous is not None or args.coulomb is not None:
        base = Friction.from_urdf(model) if args.friction == "urdf" else Friction.none(model)
        friction = Friction(viscous=_joint_values(args.viscous, "--viscous", model, base.viscous),
                            coulomb=_joint_values(args.coulomb, "--coulomb", model, base.coulomb),
                            smoothing=args.smoothing)
    out = Path(args.out)
    _check_writable(out)
    for extra in (args.plot, args.html):
        if extra:
            _check_writable(Path(extra))
    steps = int(np.ceil(args.duration / args.dt - 1e-9)) if args.dt > 0 and args.duration > 0 else 0
    progress = _progress_bar(total=steps, enabled=not args.quiet, delay=1.0)
    trajectory = simulate(model, q0, qd0, args.duration, args.dt, integrator=args.integrator, torque=torque,
                          friction=friction, limits=args.limits, progress=progress.update)
    progress.close()
    header, data = trajectory.table()
    write_csv_atomically(out, header, data)
    if args.plot:
        from .plotting import plot_trajectory

        plot_trajectory(trajectory, args.plot, title=f"{model.name}: {args.integrator}, dt = {args.dt:g} s")
    if args.html:
        _export_animation(Path(args.html), model, resolve(args.urdf), trajectory.t, trajectory.q, trajectory.tau, args)
    for event in trajectory.events:
        print(f"warning: {event}", file=sys.stderr)
    summary = dict(robot=model.name, joints=list(model.joint_names), integrator=args.integrator, dt=args.dt,
                   duration=args.duration, samples=len(trajectory.t), energy_start=float(trajectory.energy[0]),
                   energy_end=float(trajectory.energy[-1]), events=list(trajectory.events), out=str(out),
                   plot=args.plot)
    if args.json:
        _print_json(summary)
    else:
        print(f"simulated {model.name} for {args.duration:g} s ({len(trajectory.t)} samples, {args.integrator}, dt = {args.dt:g} s); "
              f"energy {summary['energy_start']:.6g} J -> {summary['energy_end']:.6g} J; wrote {out}")
    return 0


def cmd_cartesian(args) -> int:
    from .cartesian import cartesian_dynamics

    model = _load(args.urdf)
    q = _joint_values(args.q, "--q", model)
    qd = _joint_values(args.qd, "--qd", model)
    rows = args.rows.split(",") if args.rows else None
    terms = cartesian_dynamics(model, q, qd, args.frame, expressed_in=args.expressed_in, rows=rows,
                               max_condition=args.max_condition)
    document = dict(joints=list(model.joint_names), frame=terms.frame, rows=list(terms.rows), J=terms.J.tolist(),
                    J_dot=terms.J_dot.tolist(), Mx=terms.Mx.tolist(), Vx=terms.Vx.tolist(), Gx=terms.Gx.tolist(),
                    condition=terms.condition)
    if args.json:
        _print_json(document)
        return 0
    print(f"robot {model.name}, frame '{terms.frame}' ({args.expressed_in} coordinates), task rows {', '.join(terms.rows)}; "
          f"cond(J) = {terms.condition:.4g}")
    for label in ("J", "J_dot", "Mx"):
        print(f"\n{label}:")
        for row_name, row in zip(terms.rows, document[label]):
            print(f"{row_name:<3} " + " ".join(f"{x:>12.6g}" for x in row))
    print("\nVx: " + " ".join(f"{x:.6g}" for x in terms.Vx))
    print("Gx: " + " ".join(f"{x:.6g}" for x in terms.Gx))
    return 0


def _export_animation(path: Path, model, urdf, t, q, tau, args) -> None:
    import warnings

    from .viewer import MeshWarning, export_html

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", MeshWarning)
        export_html(path, model, urdf, geometry=args.geometry, t=t, q=q, tau=tau if args.torques else None,
                    trace_path=args.path)
    for warning in caught:
        print(f"warning: {warning.message}", file=sys.stderr)


def cmd_animate(args) -> int:
    model = _load(args.urdf)
    joints = model.joint_names
    html = Path(args.html)
    _check_writable(html)
    columns = read_columns(Path(args.trajectory), ["t"] + _joint_columns(("q",), joints),
                           _joint_columns(("qd", "qdd", "tau"), joints) + ["energy"])
    q = _stack(columns, "q", joints)
    tau = None
    if args.torques:
        if all(f"tau_{j}" in columns for j in joints):
            tau = _stack(columns, "tau", joints)
        elif all(f"{k}_{j}" in columns for k in ("qd", "qdd") for j in joints):
            tau = inverse_dynamics(model, q, _stack(columns, "qd", joints), _stack(columns, "qdd", joints))
        else:
            raise UsageError(f"{args.trajectory}: --torques needs tau_<joint> columns, or qd_<joint> and qdd_<joint> to compute them")
    if np.any(np.diff(columns["t"]) <= 0):
        raise UsageError(f"{args.trajectory}: times in column 't' must increase")
    _export_animation(html, model, resolve(args.urdf), columns["t"], q, tau, args)
    print(f"wrote {html} ({html.stat().st_size / 1e6:.2f} MB, {len(q)} samples); open it in any browser, offline", file=sys.stderr)
    return 0


def _add_animation_options(p, html_required: bool) -> None:
    p.add_argument("--html", required=html_required, help="write a self-contained HTML animation (opens offline)")
    p.add_argument("--geometry", choices=("auto", "visual", "collision", "stick"), default="auto",
                   help="what to draw: URDF visual or collision meshes, or a stick model; auto picks the lightest "
                        "faithful one (default)")
    p.add_argument("--torques", action="store_true", help="draw joint torques as bars along the joint axes")
    p.add_argument("--path", action="store_true", help="draw the end-effector path")


def _check_writable(path: Path) -> None:
    """Fail before long work if the output cannot be written."""
    directory = path.parent if str(path.parent) else Path(".")
    if not directory.is_dir():
        raise UsageError(f"{path}: directory {directory} does not exist")
    if not os.access(directory, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise UsageError(f"{path}: not writable")


def _symbol_names(text) -> tuple[str, ...]:
    return tuple(name.strip() for name in text.split(",") if name.strip()) if text else ()


def cmd_trace(args) -> int:
    from .trace import as_dict, as_latex, as_table, trace

    model = _load(args.urdf)
    if args.symbolic:
        result = trace(model, None, None, None, symbols=_symbol_names(args.symbols))
    else:
        if args.q is None:
            raise UsageError("--q is required unless --symbolic is given")
        result = trace(model, _joint_values(args.q, "--q", model), _joint_values(args.qd, "--qd", model),
                       _joint_values(args.qdd, "--qdd", model))
    if args.format == "json":
        _print_json(as_dict(result))
    else:
        print(as_latex(result) if args.format == "latex" else as_table(result))
    return 0


def cmd_derive(args) -> int:
    from .symbolic import derive
    from .trace import derivation_dict, derivation_text

    model = _load(args.urdf)
    derivation = derive(model, _symbol_names(args.symbols), method=args.method)
    if args.format == "json":
        _print_json(derivation_dict(derivation))
    else:
        print(derivation_text(derivation, args.format))
    return 0


def cmd_validate(args) -> int:
    if args.samples < 1:
        raise UsageError("--samples must be at least 1")
    # The oracle lives in reference/; it is imported only by this command, so the
    # library itself never loads Pinocchio.
    from reference.validate import bundled_targets, display_name, validate

    targets = args.urdf or bundled_targets()
    for target in targets:  # fail on bad input before any long work
        _load(target)
    progress = _progress_bar(total=len(targets) * args.samples, enabled=not args.json and sys.stderr.isatty())
    reports = [validate(target, samples=args.samples, seed=args.seed, tolerance=args.tolerance, progress=progress.update)
               for target in targets]
    progress.close()
    ok = all(r.ok for r in reports)
    if args.json:
        _print_json(dict(ok=ok, tolerance=args.tolerance, robots=[r.as_dict() for r in reports]))
        return 0 if ok else 1
    print(f"course_dynamics vs Pinocchio: max relative error over {args.samples} random states (seed {args.seed}), tolerance {args.tolerance:g}")
    print(f"{'robot':<30} {'n':>2} " + " ".join(f"{t:>9}" for t in ("tau", "M", "C", "V", "G")) + "  agree")
    for target, r in zip(targets, reports):
        errors = " ".join(f"{r.terms[t].max_rel:>9.1e}" for t in ("tau", "M", "C", "V", "G"))
        print(f"{display_name(target):<30} {len(r.joints):>2} {errors}  {'yes' if r.ok else 'NO'}")
    print("all robots agree" if ok else "DISAGREEMENT: see the rows marked NO")
    return 0 if ok else 1


def _progress_bar(total: int, enabled: bool, delay: float = 0.0):
    """A tqdm bar on stderr; with ``delay`` it appears only for work that lasts longer."""
    from tqdm import tqdm

    return tqdm(total=total, unit="step", disable=not enabled, file=sys.stderr, leave=False, delay=delay,
                mininterval=0.5)


def build_parser() -> Parser:
    robots = ", ".join(robot_names())
    parser = Parser(
        prog="course-dynamics",
        description="Manipulator dynamics in Craig's notation (Introduction to Robotics, ch. 6), "
                    "computed by hand-written Newton-Euler and checked against Pinocchio.",
        epilog=f"URDF arguments take a file path or the name of a shipped robot: {robots}. "
               "Joint values are comma-separated, in the joint order 'info' prints "
               "(rad, rad/s, rad/s^2 for revolute joints; m, m/s, m/s^2 for prismatic).",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)

    p = sub.add_parser("info", help="joints (order, type, axis, limits, parent) and moving bodies (mass, COM)")
    p.add_argument("urdf", help="URDF file or shipped robot name")
    p.add_argument("--json", action="store_true", help="print one JSON document")
    p.set_defaults(run=cmd_info)

    p = sub.add_parser("terms", help="tau, M, C, V, G at one state",
                       description="Evaluate tau = M(q) qdd + V(q, qd) + G(q) and the Coriolis matrix C (C qd = V).")
    p.add_argument("urdf", help="URDF file or shipped robot name")
    p.add_argument("--q", required=True, help="joint positions q1,q2,... (rad or m)")
    p.add_argument("--qd", help="joint velocities (default 0)")
    p.add_argument("--qdd", help="joint accelerations (default 0)")
    p.add_argument("--gravity", help="gx,gy,gz in the base frame, m/s^2 (default 0,0,-9.81)")
    p.add_argument("--json", action="store_true", help="print JSON with keys joints, tau, M, C, V, G")
    p.set_defaults(run=cmd_terms)

    p = sub.add_parser("torques", help="inverse dynamics along a trajectory CSV",
                       description="Read columns t, q_<joint>, qd_<joint>, qdd_<joint>; write t, tau_<joint>.")
    p.add_argument("urdf", help="URDF file or shipped robot name")
    p.add_argument("--trajectory", required=True, help="input CSV")
    p.add_argument("--out", required=True, help="output CSV (written whole or not at all)")
    p.set_defaults(run=cmd_torques)

    p = sub.add_parser("cartesian", help="Cartesian-space dynamics Mx, Vx, Gx (6.99) of a frame",
                       description="Jacobian J, its time derivative, and F = Mx Xdd + Vx + Gx (6.91) for a URDF link "
                                   "or frame. The selected task rows must make J square (as many rows as joints).")
    p.add_argument("urdf", help="URDF file or shipped robot name")
    p.add_argument("--frame", required=True, help="URDF link name of the task frame")
    p.add_argument("--q", required=True, help="joint positions")
    p.add_argument("--qd", help="joint velocities (default 0)")
    p.add_argument("--rows", help="task rows among x,y,z,rx,ry,rz (default all six)")
    p.add_argument("--expressed-in", choices=("base", "frame"), default="base",
                   help="coordinates of J and the task: the base frame, or the task frame itself as Craig's 3J (default base)")
    p.add_argument("--max-condition", type=float, default=1e8, help="cond(J) above which J counts as singular (default 1e8)")
    p.add_argument("--json", action="store_true", help="print JSON with keys joints, frame, rows, J, J_dot, Mx, Vx, Gx, condition")
    p.set_defaults(run=cmd_cartesian)

    p = sub.add_parser("simulate", help="forward dynamics in time (6.115)-(6.117), written as CSV",
                       description="Integrate qdd = M^-1 (tau - V - G - F) from q0, qd0. The output CSV has t, q_<joint>, "
                                   "qd_<joint>, qdd_<joint>, tau_<joint> and energy (kinetic + potential, J), and can be "
                                   "fed back to 'torques'.")
    p.add_argument("urdf", help="URDF file or shipped robot name")
    p.add_argument("--q0", required=True, help="initial joint positions")
    p.add_argument("--qd0", help="initial joint velocities (default 0)")
    p.add_argument("--duration", type=float, required=True, help="simulated time, s")
    p.add_argument("--dt", type=float, required=True, help="time step, s")
    p.add_argument("--integrator", choices=("euler", "semi-implicit", "rk4", "adaptive"), default="rk4",
                   help="euler is the notes' (6.116)-(6.117); default rk4")
    torque = p.add_mutually_exclusive_group()
    torque.add_argument("--torque", help="constant applied torques tau1,tau2,... (default 0)")
    torque.add_argument("--torque-csv", help="CSV with t and tau_<joint> columns, interpolated linearly in time")
    p.add_argument("--friction", choices=("none", "urdf"), default="none",
                   help="joint friction: none, or viscous = URDF damping and Coulomb = URDF friction (default none)")
    p.add_argument("--viscous", help="viscous coefficients v1,v2,... (N m s/rad), overriding --friction")
    p.add_argument("--coulomb", help="Coulomb coefficients c1,c2,... (N m), overriding --friction")
    p.add_argument("--smoothing", type=float, default=0.0, help="Coulomb sgn(qd) -> tanh(qd/smoothing) if > 0")
    p.add_argument("--limits", choices=("report", "stop"), default="report",
                   help="at a joint limit: report it and go on, or stop the joint there (default report)")
    p.add_argument("--out", required=True, help="output CSV (written whole or not at all)")
    p.add_argument("--plot", help="also draw q(t), qd(t) and energy(t) to this PNG file")
    _add_animation_options(p, html_required=False)
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(run=cmd_simulate)

    p = sub.add_parser("trace", help="the Newton-Euler iterations link by link (numeric or symbolic)",
                       description="Show omega, omega_dot, v_dot, v_dot_C, F, N (outward, 6.45-6.50) and f, n, tau "
                                   "(inward, 6.51-6.53) for every link, each in its own frame, as the notes' worked "
                                   "example lays them out.")
    p.add_argument("urdf", help="URDF file or shipped robot name")
    p.add_argument("--q", help="joint positions (numeric trace)")
    p.add_argument("--qd", help="joint velocities (default 0)")
    p.add_argument("--qdd", help="joint accelerations (default 0)")
    p.add_argument("--symbolic", action="store_true", help="symbolic trace in q_<joint>, qd_<joint>, qdd_<joint>")
    p.add_argument("--symbols", help="with --symbolic: parameters kept as symbols, e.g. m1,m2,l1,l2,g")
    p.add_argument("--format", choices=("table", "latex", "json"), default="table", help="output format (default table)")
    p.set_defaults(run=cmd_trace)

    p = sub.add_parser("derive", help="closed-form tau, M, V, G and Craig's B, C (symbolic)",
                       description="Derive the equations of motion symbolically by Newton-Euler or by Lagrange: "
                                   "tau = M(q) qdd + B(q)[qd qd] + C(q)[qd^2] + G(q) (6.63). Joint variables are "
                                   "q_<joint>, qd_<joint>, qdd_<joint>; parameters not named in --symbols are the "
                                   "URDF's numbers, made exact.")
    p.add_argument("urdf", help="URDF file or shipped robot name (at most 4 joints)")
    p.add_argument("--symbols", help="parameters kept symbolic: m<i>, l<i>, I<xx|yy|zz|xy|xz|yz><i>, g "
                                     "(a one-joint robot also takes m, l)")
    p.add_argument("--method", choices=("newton-euler", "lagrange"), default="newton-euler")
    p.add_argument("--format", choices=("markdown", "latex", "json"), default="markdown",
                   help="json has keys joints, tau, M, V, G, B, C; each entry a string sympy.sympify parses")
    p.set_defaults(run=cmd_derive)

    p = sub.add_parser("animate", help="animate a trajectory CSV as a self-contained HTML file (meshcat)",
                       description="Draw the robot (URDF meshes or a stick model) and animate a trajectory with "
                                   "columns t and q_<joint> (a simulate output works) as meshcat keyframes, in one "
                                   "HTML file that opens offline in any browser.")
    p.add_argument("urdf", help="URDF file or shipped robot name")
    p.add_argument("--trajectory", required=True, help="CSV with t, q_<joint> (qd_, qdd_, tau_, energy allowed)")
    _add_animation_options(p, html_required=True)
    p.set_defaults(run=cmd_animate)

    p = sub.add_parser("validate", help="compare every term with Pinocchio on random states",
                       description="Evaluate tau, M, C, V, G with course_dynamics and with Pinocchio on seeded random "
                                   "states within joint limits. Exit 0 when every term agrees to the tolerance "
                                   "(relative), 1 when one does not, 2 on bad input.")
    p.add_argument("urdf", nargs="*", help="URDF files or robot names (default: every shipped robot)")
    p.add_argument("--samples", type=int, default=200, help="random states per robot (default 200)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--tolerance", type=float, default=1e-9, help="relative tolerance (default 1e-9)")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    p.set_defaults(run=cmd_validate)
    return parser


def _join_value_options(argv: list[str]) -> list[str]:
    """``--q -0.1,0.2`` → ``--q=-0.1,0.2``, so negative first values are not taken for options."""
    out, i = [], 0
    while i < len(argv):
        if argv[i] in VALUE_OPTIONS and i + 1 < len(argv):
            out.append(f"{argv[i]}={argv[i + 1]}")
            i += 2
        else:
            out.append(argv[i])
            i += 1
    return out


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser()
    try:
        args = parser.parse_args(_join_value_options(argv))
        return args.run(args)
    except (UsageError, ModelError, StateError, KeyError, ValueError) as exc:
        message = exc.args[0] if exc.args else str(exc)
        print(f"error: {message}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
