"""course_dynamics/cli/commands/identify.py: a log with measured torques in, an identified URDF and a report out."""
from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers import ROOT, assert_one_line_error, run
from logmakers import write_csv
from test_identification import log_columns, true_robot   # the perturbed UR5 and its noisy logs

from course_dynamics import load_robot, load_urdf
from course_dynamics.cli import main
from course_dynamics.core.regressor import parameter_names, parameters

SECONDS = 15.0   # of the fitted log: enough for every assertion here (tests/test_identification.py: 60 s)


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """Two CSV logs of the true UR5 with tau_meas_ columns: one to identify from, one of another motion."""
    folder = tmp_path_factory.mktemp("logs")
    ur5 = load_robot("ur5")
    true, friction = true_robot(ur5)
    paths = []
    for name, seed, seconds in (("train.csv", 1, SECONDS), ("other.csv", 7, 8.0)):
        columns, _ = log_columns(ur5, true, friction, duration=seconds, seed=seed)
        write_csv(folder / name, list(columns), list(columns.values()))
        paths.append(folder / name)
    return paths


def residuals(capsys, urdf, log, *extra) -> list[float]:
    code, out, _ = run(capsys, "torques", str(urdf), "--log", str(log), "--json", *extra)
    assert code == 0
    return [j["rms"] for j in json.loads(out)["residuals"]["joints"]]


def test_identified_urdf_gives_torques_closer_to_the_robot(capsys, tmp_path, logs):
    train, other = logs
    report = tmp_path / "report"
    urdf = report / "identified.urdf"
    code, out, err = run(capsys, "identify", "ur5", "--log", str(train), "--out", str(report))
    assert code == 0, err
    assert "RMS held out, identified" in out and "solver clarabel" in out
    assert f"wrote the identified URDF to {urdf}" in err
    before = residuals(capsys, "ur5", other)
    after = residuals(capsys, urdf, other, "--friction", "urdf")
    assert all(a < b / 5 for a, b in zip(after, before)), (after, before)   # measured: 10–100× smaller
    assert sorted(p.name for p in report.iterdir()) == [".course-dynamics-files.json", "held_out.svg", "identified.urdf",
                                                         "report.html", "report.json", "report.md"]
    document = json.loads((report / "report.json").read_text())
    assert document["urdf"] == "ur5" and document["friction_model"] == "both" and len(document["parameters"]) == 72
    html = (report / "report.html").read_text()
    assert "<svg" in html and "shoulder_pan_joint" in html and "Base parameters" in html
    assert "shoulder\\_pan\\_joint" in (report / "report.md").read_text()    # names escaped for Markdown
    code, _, err = run(capsys, "identify", "ur5", "--log", str(train), "--out", str(report))
    assert code == 0, err   # a report identify wrote is replaced, and its URDF with it
    urdf.write_text(urdf.read_text() + "<!-- mine -->")
    code, _, err = run(capsys, "identify", "ur5", "--log", str(train), "--out", str(report))
    assert_one_line_error(code, err, "identified.urdf", "changed since")   # but not one changed since
    assert urdf.read_text().endswith("<!-- mine -->")


def test_the_old_report_option_still_writes_the_report_beside_the_urdf(capsys, tmp_path, logs):
    urdf, report = tmp_path / "identified.urdf", tmp_path / "report"
    code, _, err = run(capsys, "identify", "ur5", "--log", str(logs[0]), "--out", str(urdf), "--report", str(report),
                       "--friction", "viscous", "--quiet")
    assert code == 0, err
    assert [line for line in err.splitlines() if line.startswith("warning: --")] == [
        "warning: --report is now --out DIR (the folder then holds the identified URDF too); the old spelling goes in "
        "the next release",
        "warning: --friction is now --friction-fit; the old spelling goes in the next release"]
    assert json.loads((report / "report.json").read_text())["friction_model"] == "viscous" and urdf.is_file()
    code, _, err = run(capsys, "identify", "ur5", "--log", str(logs[0]), "--out", str(tmp_path / "folder"), "--report",
                       str(report))
    warning, error = err.splitlines()
    assert code == 2 and warning.startswith("warning: --report is now --out DIR")
    assert error.startswith("error: --out ") and "is a folder" in error and "--report is not needed" in error


def test_json_and_friction_choice(capsys, tmp_path, logs):
    urdf = tmp_path / "viscous.urdf"
    code, out, _ = run(capsys, "identify", "ur5", "--log", str(logs[0]), "--out", str(urdf), "--friction-fit", "viscous",
                       "--holdout", "0.3", "--json", "--quiet")
    assert code == 0
    document = json.loads(out)
    assert document["friction_model"] == "viscous" and document["out"] == str(urdf)
    assert document["samples"]["held_out"] == pytest.approx(0.3 * (SECONDS * 100 + 1), abs=2)
    assert set(document["held_out_rms"]) == {"urdf", "identified"}
    assert urdf.read_text().count('friction="0.0"') == 6        # Coulomb: the URDF's, kept


def test_the_urdf_can_go_to_standard_output(capsys, logs):
    code, out, err = run(capsys, "identify", "ur5", "--log", str(logs[0]), "--out", "-", "--quiet")
    assert code == 0 and out.startswith("<?xml") and out.rstrip().endswith("</robot>")
    assert "RMS held out" in err


LOG = ROOT / "examples" / "ur5_log.csv"
MAP = ROOT / "examples" / "ur5_log_columns.toml"


@pytest.mark.parametrize("argv, fragments", [
    (["--log", str(LOG), "--map", str(MAP)], ["holds no measured torques", "tau_meas_shoulder_pan_joint",
                                             "current_<joint>"]),
    (["--log", "TRAIN", "--holdout", "1.5"], ["--holdout must be at least 0 and less than 1"]),
    (["--log", "TRAIN", "--friction-fit", "dry"], ["invalid choice: 'dry'"]),
    (["--log", "TRAIN", "--torque-constant", "1,2"], ["--torque-constant has 2 values"]),
    (["--log", "TRAIN", "--map", "q_elbow_joint=nothing"], ["no column 'nothing'"]),
])
def test_bad_input_is_one_line_and_writes_nothing(capsys, tmp_path, logs, argv, fragments):
    out = tmp_path / "identified.urdf"
    argv = [str(logs[0]) if a == "TRAIN" else a for a in argv]
    code, _, err = run(capsys, "identify", "ur5", *argv, "--out", str(out))
    assert_one_line_error(code, err, *fragments)
    assert not out.exists()


def test_outputs_are_checked_before_the_work(capsys, tmp_path, logs):
    train = str(logs[0])
    code, _, err = run(capsys, "identify", "ur5", "--log", train, "--out", train)
    assert_one_line_error(code, err, "would overwrite the input")
    code, _, err = run(capsys, "identify", "ur5", "--log", train, "--out", "-", "--json")
    assert_one_line_error(code, err, "--out - and --json")
    code, _, err = run(capsys, "identify", "ur5", "--log", train)
    assert_one_line_error(code, err, "--out")
    report = tmp_path / "report"
    report.mkdir()
    (report / "report.html").write_text("mine")
    code, _, err = run(capsys, "identify", "ur5", "--log", train, "--out", str(report))
    assert_one_line_error(code, err, "report.html: exists and was not written by course-dynamics")
    assert sorted(p.name for p in report.iterdir()) == ["report.html"] and (report / "report.html").read_text() == "mine"


def test_without_cvxpy_it_says_what_to_install(capsys, tmp_path, logs, monkeypatch):
    monkeypatch.setitem(sys.modules, "cvxpy", None)
    out = tmp_path / "identified.urdf"
    code, _, err = run(capsys, "identify", "ur5", "--log", str(logs[0]), "--out", str(out))
    assert_one_line_error(code, err, "install course-dynamics[identify]")
    assert not out.exists()


def test_help_explains(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["identify", "--help"])
    text = re.sub(r"(\w)- (\w)", r"\1-\2", " ".join(capsys.readouterr().out.split()))   # argparse's line breaks undone
    assert exit_info.value.code == 0
    for words in ("--log LOG", "tau_meas_<joint>", "pseudo-inertia", "--holdout", "--out DIR", "--torque-constant",
                  "--split-gaps", "course-dynamics[identify]", "read back before it is written"):
        assert words in text, words
    with pytest.raises(SystemExit):
        main(["--help"])
    assert "identify" in capsys.readouterr().out


def test_the_commands_friction_choices_are_the_librarys():
    import argparse

    from course_dynamics.cli import flags
    from course_dynamics.tools import identification

    parser = argparse.ArgumentParser()
    assert flags.add(parser, "--friction-fit").choices == identification.FRICTION_MODELS


def hostile_ur5(folder, replacements) -> Path:
    """The UR5's URDF with ``replacements`` (old → new text, each where it first appears) made."""
    text = Path(load_robot("ur5").source).read_text()
    for old, new in replacements.items():
        assert old in text, old
        text = text.replace(old, new, 1)
    path = folder / "ur5_hostile.urdf"
    path.write_text(text)
    return path


def test_the_written_urdf_reads_back_as_reported_whatever_text_looks_like_dynamics(capsys, tmp_path, logs):
    """A damping inside another attribute's value, a comment, CDATA, a processing instruction and a joint's
    <inertial> are left alone; every identified value of the report (masses, first moments, inertias, F_v, F_c)
    is what our loader reads from the written URDF."""
    pan = '<joint name="shoulder_pan_joint" type="revolute">'
    elbow = '<joint name="elbow_joint" type="revolute">'
    urdf = hostile_ur5(tmp_path, {
        pan: pan + """\n    <!-- <dynamics damping="9"/> --><![CDATA[ <dynamics damping="9"/> ]]><?note damping="9"?>""",
        '<dynamics damping="0.0" friction="0.0"/>': """<dynamics note=' damping="0.0" friction="0.0"'/>""",
        elbow: """<joint name="elbow_joint" type="revolute" note='damping="0.1"'>\n    <inertial><mass value="1"/></inertial>""",
    })
    out = tmp_path / "identified.urdf"
    code, stdout, err = run(capsys, "identify", str(urdf), "--log", str(logs[0]), "--out", str(out), "--json", "--quiet")
    assert code == 0, err
    reported = {p["name"]: p["identified"] for p in json.loads(stdout)["parameters"]}
    back = load_urdf(out)
    np.testing.assert_array_equal([b.damping for b in back.bodies], [reported[f"Fv_{j}"] for j in back.joint_names])
    np.testing.assert_array_equal([b.friction for b in back.bodies], [reported[f"Fc_{j}"] for j in back.joint_names])
    assert min(reported[f"Fv_{j}"] for j in back.joint_names) > 0      # the log's friction, not the URDF's zeros
    np.testing.assert_allclose(parameters(back), [reported[n] for n in parameter_names(back)], rtol=1e-12, atol=1e-15)
    text = out.read_text()
    for decoy in ('<!-- <dynamics damping="9"/> -->', '<![CDATA[ <dynamics damping="9"/> ]]>', '<?note damping="9"?>',
                  """note='damping="0.1"'>""", """<dynamics note=' damping="0.0" friction="0.0"' damping=""",
                  '<inertial><mass value="1"/></inertial>'):
        assert text.count(decoy) == 1, decoy


def test_a_urdf_readers_disagree_on_is_refused_in_one_line_and_nothing_is_written(capsys, tmp_path, logs):
    """A <dynamics> put in a namespace by a default xmlns: our loader skips it, urdfdom (Pinocchio) reads it."""
    urdf = hostile_ur5(tmp_path, {'<dynamics damping="0.0" friction="0.0"/>':
                                  '<dynamics xmlns="urn:x" damping="0.0" friction="0.0"/>'})
    report = tmp_path / "report"
    code, _, err = run(capsys, "identify", str(urdf), "--log", str(logs[0]), "--out", str(report), "--quiet")
    assert_one_line_error(code, err, str(urdf), "joint 'shoulder_pan_joint'", "default XML namespace")
    assert not report.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ur5_hostile.urdf"]


def test_an_identification_too_large_for_the_budget_is_refused_before_the_work(capsys, tmp_path, logs, monkeypatch):
    """The factors R (m, r, P + 1), their QRs and a block's regressor are checked against the budget first."""
    import course_dynamics.tools.identification as identification

    monkeypatch.setenv("COURSE_DYNAMICS_MEMORY_BUDGET", "4M")
    monkeypatch.setattr(identification, "_factors", lambda *a: pytest.fail("factored before checking"))
    out = tmp_path / "x.urdf"
    code, _, err = run(capsys, "identify", "ur5", "--log", str(logs[0]), "--out", str(out))
    assert_one_line_error(code, err, str(logs[0]), "identifying robot 'ur5' (6 joints, 72 parameters)", "of memory",
                          "the 4 MiB that COURSE_DYNAMICS_MEMORY_BUDGET allows", "--friction-fit")
    assert not out.exists()


def test_the_solvers_warnings_are_one_warning_line_of_ours(capsys, tmp_path, logs, monkeypatch):
    """cvxpy's UserWarning ("Solution may be inaccurate") comes out as one ``warning:`` line, not Python's two."""
    import warnings

    import cvxpy

    solve = cvxpy.Problem.solve

    def inaccurate(self, *args, **kwargs):
        warnings.warn("Solution may be inaccurate. Try another solver.", UserWarning)
        return solve(self, *args, **kwargs)

    monkeypatch.setattr(cvxpy.Problem, "solve", inaccurate)
    code, _, err = run(capsys, "identify", "ur5", "--log", str(logs[0]), "--out", str(tmp_path / "x.urdf"))
    assert code == 0, err
    assert set(line for line in err.splitlines() if "inaccurate" in line) == {   # once per problem solved
        "warning: robot 'ur5', the physically consistent fit (clarabel): Solution may be inaccurate. Try another solver."}
    assert "UserWarning" not in err and "warnings.warn" not in err


def test_a_joint_set_constant_is_a_fixed_joint_its_body_untouched(capsys, tmp_path):
    """UR5 logged with wrist 3 held at 0.3 rad and no column for it: ``--set q_wrist_3_joint=0.3`` makes it a fixed
    joint; the written URDF's wrist_3_link is the URDF's, nothing warns about it, the condition number is sane."""
    from logmakers import multisine, noisy, write_csv
    from test_identification import NOISE_QD, NOISE_TAU, true_torques

    ur5 = load_robot("ur5")
    true, friction = true_robot(ur5)
    motion = multisine(ur5, duration=10.0, rate=100.0, seed=1)
    for signal, value in ((motion.q, 0.3), (motion.qd, 0.0), (motion.qdd, 0.0)):
        signal[:, 5] = value
    tau = true_torques(true, friction, motion)
    measured = noisy(tau, NOISE_TAU * np.sqrt(np.mean(tau**2, axis=0)), 2)
    qd = noisy(motion.qd, NOISE_QD, 4)
    columns = {"t": motion.t}
    for j, joint in enumerate(ur5.joint_names[:5]):
        columns |= {f"q_{joint}": motion.q[:, j], f"qd_{joint}": qd[:, j], f"tau_meas_{joint}": measured[:, j]}
    write_csv(tmp_path / "held.csv", list(columns), list(columns.values()))
    out = tmp_path / "identified.urdf"
    code, stdout, err = run(capsys, "identify", "ur5", "--log", str(tmp_path / "held.csv"), "--set",
                            "q_wrist_3_joint=0.3", "--out", str(out), "--json")
    assert code == 0, err
    document = json.loads(stdout)
    assert document["held"] == ["wrist_3_joint"] and document["condition_number"] < 1e3
    assert not any("_6" in u["combination"] for u in document["unexcited"]) and document["far"] == []
    back, urdf = load_urdf(out).bodies[5], ur5.bodies[5]
    assert back.mass == urdf.mass and np.array_equal(back.p_com, urdf.p_com) and np.array_equal(back.I_com, urdf.I_com)
    assert (back.damping, back.friction) == (urdf.damping, urdf.friction)



def test_a_log_without_friction_of_a_robot_whose_urdf_has_some_is_identified(capsys, tmp_path):
    """Panda's own excitation, noise-free (its τ without friction; the URDF's damping 0.003 per arm joint, 0.3 per
    finger, the mimic finger's folded into its leader's): the fitted coefficients are of round-off size, and as a
    scale alone they made the consistent fit count friction unseen, hold it at the URDF's and find no solution."""
    code, _, err = run(capsys, "excite", "panda", "--duration", "2", "--dt", "0.01", "--max-iterations", "5",
                       "--out", str(tmp_path / "excitation.csv"))
    assert code == 0, err
    header, rest = (tmp_path / "excitation.csv").read_text().split("\n", 1)
    (tmp_path / "measured.csv").write_text(header.replace("tau_", "tau_meas_") + "\n" + rest)
    code, stdout, err = run(capsys, "identify", "panda", "--log", str(tmp_path / "measured.csv"), "--out",
                            str(tmp_path / "identified.urdf"), "--json")
    assert code == 0, err
    document = json.loads(stdout)
    friction = {p["name"]: p for p in document["parameters"] if p["name"].startswith(("Fv_", "Fc_"))}
    assert friction["Fv_panda_finger_joint1"]["urdf"] == pytest.approx(0.6)   # 0.3 + 1² · 0.3
    assert all(abs(p["identified"]) < 1e-6 for p in friction.values()), friction


def test_a_real_log_is_identified_with_one_option(capsys, tmp_path, logs):
    """The true UR5 logged on a real clock (every step within ±20 %, a 40-period gap, a lone sample between two gaps,
    two dropped rows; logmakers.real_clock): refused in one line naming all of it, identified with ``--repair`` alone,
    its notes in --json's log_notes, and the model found predicts another motion as well as from an even log."""
    from logmakers import noisy, real_clock, sampled_at
    from test_identification import NOISE_Q, NOISE_QD, NOISE_TAU, true_torques

    ur5 = load_robot("ur5")
    true, friction = true_robot(ur5)
    motion = sampled_at(ur5, real_clock(100.0, SECONDS, seed=4), seed=1)
    tau = true_torques(true, friction, motion)
    measured = noisy(tau, NOISE_TAU * np.sqrt(np.mean(tau**2, axis=0)), 2)
    q, qd = noisy(motion.q, NOISE_Q, 3), noisy(motion.qd, NOISE_QD, 4)
    columns = {"t": motion.t}
    for j, joint in enumerate(ur5.joint_names):
        columns |= {f"q_{joint}": q[:, j], f"qd_{joint}": qd[:, j], f"tau_meas_{joint}": measured[:, j]}
    path = tmp_path / "real.csv"
    write_csv(path, list(columns), list(columns.values()), fmt="{:.17g}")
    urdf = tmp_path / "identified.urdf"
    code, _, err = run(capsys, "identify", "ur5", "--log", str(path), "--out", str(urdf))
    assert_one_line_error(code, err, "the samples are not on one clock", "and it has 3 gaps", "and 1 lone sample",
                          "--repair resamples on the median period, splits at the gaps and drops the lone sample")
    assert not urdf.exists()
    report = tmp_path / "report"
    code, out, err = run(capsys, "identify", "ur5", "--log", str(path), "--out", str(report), "--repair", "--json")
    assert code == 0, err
    notes = json.loads(out)["log_notes"]
    assert [n.split(" ")[0] for n in notes[:3]] == ["resampled", "split", "dropped"], notes
    assert json.loads((report / "report.json").read_text())["log_notes"] == notes      # and the report says so
    assert f"the log: {notes[2]}" in (report / "report.html").read_text()
    before = residuals(capsys, "ur5", logs[1])
    after = residuals(capsys, report / "identified.urdf", logs[1], "--friction", "urdf")
    assert all(a < b / 5 for a, b in zip(after, before)), (after, before)   # measured 10–75× smaller, as if even


def test_a_flange_is_for_a_payloads_identification_and_a_payload_needs_no_prior(capsys, tmp_path, logs):
    """--flange without --scope payload, and --prior-weight with it, are refused before the log is read
    (tests/test_payloads.py identifies payloads)."""
    out = tmp_path / "x.urdf"
    code, _, err = run(capsys, "identify", "ur5", "--log", str(logs[0]), "--flange", "tool0", "--out", str(out))
    assert_one_line_error(code, err, "--flange", "--scope payload")
    code, _, err = run(capsys, "identify", "ur5", "--log", str(logs[0]), "--scope", "payload", "--prior-weight", "1",
                       "--out", str(out))
    assert_one_line_error(code, err, "--prior-weight is for --scope robot")
    assert not out.exists()
