"""course_dynamics/core/compiled/looped.py: the native loop is the recursions' own steps, shipped as generated C;
it agrees with the recursions as written (1e-12) and with Pinocchio (1e-9) on every robot of any size, refuses
what it cannot trust, and where it is missing, off or wrong the recursions as written run."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys

import numpy as np
import pytest
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states
from helpers import DATA, ROOT, SAMPLES, assert_agrees, chain_urdf

import course_dynamics
from course_dynamics import load_robot, load_urdf
from course_dynamics.core import crba, dynamics, evaluator, newton_euler
from course_dynamics.core.compiled import looped, native, steps
from course_dynamics.core.forward_dynamics import forward_dynamics

pytestmark = pytest.mark.skipif(native.compiler() is None,
                                reason="no C compiler: the package was installed without the loop")


def interpreted(model, q, qd, qdd):
    """τ, M and V + G by the recursions as written."""
    return {"tau": newton_euler.inverse_dynamics(model, q, qd, qdd), "mass_matrix": crba.mass_matrix(model, q),
            "bias": newton_euler.inverse_dynamics(model, q, qd, np.zeros_like(qd))}


def by_the_loop(run, q, qd, qdd):
    return {"tau": run.inverse_dynamics(q, qd, qdd), "mass_matrix": run.mass_matrix(q), "bias": run.bias(q, qd)}


def test_the_shipped_c_is_what_the_recursions_generate_now():
    assert steps.SOURCE.read_text() == steps.c_source(), (
        "looped.c is out of date: python -c 'from course_dynamics.core.compiled import looped; "
        "steps.SOURCE.write_text(steps.c_source())', then reinstall (pip install -e .)")


def test_the_installed_library_was_built_from_the_shipped_c():
    library = looped.library()
    assert library is not None, looped.why_not()
    assert library.SOURCE_SHA256 == steps.source_digest(steps.SOURCE.read_text())


def test_every_step_is_traced_from_the_recursion_with_the_bodys_numbers_as_inputs():
    traced = steps.trace_steps()
    assert set(traced) == {"outward_revolute", "outward_prismatic", "torque_revolute", "torque_prismatic", "carry",
                          "place_revolute", "place_prismatic", "composite", "force", "power"}
    used = {node[1] for node in traced["outward_revolute"].nodes if node[0] == "input"}
    assert {"b44", "b45", "b46", "b53"} <= used                     # the axis and the mass are inputs, not constants
    assert not any(op == "input" and name.startswith("b") and int(name[1:]) < 5
                   for op, name, *_ in traced["outward_revolute"].nodes)   # parent, kind, coupling: the loop's


def test_on_every_robot_it_agrees_with_the_recursions_and_with_pinocchio(robot):
    name, model, oracle, (q, qd, qdd) = robot
    run = looped.looped(model)
    assert run is not None
    ours, theirs = by_the_loop(run, q, qd, qdd), interpreted(model, q, qd, qdd)
    for term in ours:
        scale = np.abs(theirs[term]).max()
        np.testing.assert_allclose(ours[term], theirs[term], rtol=0, atol=1e-12 * scale, err_msg=f"{name} {term}")
    for i in range(0, SAMPLES, 10):
        assert_agrees(ours["tau"][i], oracle.tau(q[i], qd[i], qdd[i]), what=f"{name} tau {i}")
        assert_agrees(ours["mass_matrix"][i], oracle.M(q[i]), what=f"{name} M {i}")
        assert_agrees(ours["bias"][i], oracle.tau(q[i], qd[i], 0 * qdd[i]), what=f"{name} bias {i}")
        one = run.native_call("tau", q[i], qd[i], qdd[i])
        np.testing.assert_array_equal(one, ours["tau"][i])           # one state: the same C as a batch


@pytest.mark.parametrize("joints, joint_type", [(25, "revolute"), (60, "revolute"), (200, "revolute"),
                                                (30, "prismatic")])
def test_chains_of_any_size_agree_with_pinocchio(joints, joint_type, tmp_path):
    """Far beyond what a compiled model takes: the same loop, no compiler at the call."""
    path = tmp_path / "chain.urdf"
    path.write_text(chain_urdf(joints, joint_type))
    model = load_urdf(path)
    oracle = PinocchioOracle(path, model.joint_names, model.gravity)
    q, qd, qdd = random_states(model, 4, seed=joints)
    run = looped.looped(model)
    ours, theirs = by_the_loop(run, q, qd, qdd), interpreted(model, q, qd, qdd)
    for term in ours:
        np.testing.assert_allclose(ours[term], theirs[term], rtol=0, atol=1e-12 * np.abs(theirs[term]).max())
    for i in range(4):
        assert_agrees(ours["tau"][i], oracle.tau(q[i], qd[i], qdd[i]), what=f"chain {joints} tau {i}")
        assert_agrees(ours["mass_matrix"][i], oracle.M(q[i]), what=f"chain {joints} M {i}")


@pytest.mark.parametrize("path", [DATA / "mimic.urdf", DATA / "mimic_order.urdf"])
def test_mimic_joints_enter_and_leave_the_loop_by_the_coupling(path):
    """θ_bodies = S Θ + b at the loop's entry, Sᵀ at its exit (leaders later in the tree, mimics of mimics)."""
    model = load_urdf(path)
    assert model.has_mimic
    q, qd, qdd = random_states(model, 20, seed=3)
    ours, theirs = by_the_loop(looped.looped(model), q, qd, qdd), interpreted(model, q, qd, qdd)
    for term in ours:
        np.testing.assert_allclose(ours[term], theirs[term], rtol=0, atol=1e-12 * np.abs(theirs[term]).max())


def test_forward_dynamics_solves_with_the_loops_terms():
    model = load_robot("panda")
    run = looped.looped(model)
    q, qd, qdd = random_states(model, 5, seed=9)
    tau = newton_euler.inverse_dynamics(model, q, qd, qdd)
    np.testing.assert_allclose(run.forward_dynamics(q, qd, tau), qdd, rtol=0, atol=1e-9 * np.abs(qdd).max())
    np.testing.assert_allclose(run.forward_dynamics(q[0], qd[0], tau[0]), qdd[0], rtol=0, atol=1e-9 * np.abs(qdd).max())


def test_a_shared_batch_equals_one_thread(monkeypatch):
    model = load_robot("ur5")
    run = looped.looped(model)
    Q = np.random.default_rng(4).uniform(-1, 1, (3, 3 * native.THREAD_STATES + 7, model.n))
    shared = run.inverse_dynamics(*Q), run.mass_matrix(Q[0])
    monkeypatch.setattr(native, "THREADS", 1)
    np.testing.assert_array_equal(shared[0], run.inverse_dynamics(*Q))
    np.testing.assert_array_equal(shared[1], run.mass_matrix(Q[0]))


def test_the_c_refuses_a_model_array_it_cannot_trust():
    library = looped.library()
    model = load_robot("ur5")
    good = steps.model_array(model)
    z, out = np.zeros(6), np.empty(6)
    library.tau(good, z, z, z, out)
    body = steps.HEADER + 2 * steps.BODY                            # the third body's record
    for change in ({body: 2.0}, {body: 7.0}, {body: -2.0}, {body: 0.5},   # a parent that is not before it
                   {body + 1: 2.0},                                    # a joint kind it has no step for
                   {body + 2: 6.0}, {body + 2: -1.0},                  # a coordinate out of range
                   {0: 7.0}, {1: 7.0}, {0: 1e9}, {5: np.nan}, {body + 50: np.inf}):
        bad = good.copy()
        for k, v in change.items():
            bad[k] = v
        with pytest.raises(ValueError, match="model array"):
            library.tau(bad, z, z, z, out)
    with pytest.raises(ValueError, match="model array"):
        library.mass_matrix(good[:-1], z, np.empty(36))
    with pytest.raises(ValueError, match="not finite"):
        library.tau(good, np.full(6, np.nan), z, z, out)
    with pytest.raises(ValueError, match="whole number"):
        library.tau(good, z, z, z, np.empty(5))
    with pytest.raises(TypeError, match="float64"):
        library.bias(good, z.astype(np.float32), z, out)
    with pytest.raises(TypeError):
        library.tau(good, z, z, out)


def test_the_evaluator_runs_the_loop_for_little_work_and_for_any_size(tmp_path, monkeypatch):
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cold"))
    arm = load_robot("ur5").with_gravity([0, 0, -9.7])                # numbers no cache holds
    chosen = evaluator.choice(arm)
    assert (chosen.path, chosen.reason, chosen.native) == ("loop", evaluator.LITTLE, True)
    original, calls = looped.Looped.native_call, []
    monkeypatch.setattr(looped.Looped, "native_call", lambda self, *a: (calls.append(a[0]), original(self, *a))[1])
    q = np.random.default_rng(0).uniform(-1, 1, 6)
    assert looped.remembered(arm) is chosen.run                        # the choice is remembered natively
    tau = course_dynamics.inverse_dynamics(arm, q, q, q)               # so the native entry runs the loop
    np.testing.assert_allclose(tau, newton_euler.inverse_dynamics(arm, q, q, q), rtol=0, atol=1e-12 * np.abs(tau).max())
    assert calls == [] and np.array_equal(tau, chosen.run.inverse_dynamics(q, q, q))  # the same bits


def test_a_compiled_model_without_its_c_has_the_loop_stand_in(tmp_path, monkeypatch):
    """A call that pays for the Python programs but not for a C build: τ, M and V + G by the loop meanwhile."""
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cold"))
    arm = load_robot("rrr_arm").with_gravity([0, 0, -9.7])
    chosen = evaluator.choice(arm, calls=200)                          # pays for Python, not for C
    assert chosen.path == "compiled" and not chosen.run.native and chosen.run.loop is not None and chosen.native
    q = np.random.default_rng(1).uniform(-1, 1, (3, 50, 3))
    for ours, theirs in ((chosen.run.inverse_dynamics(*q), newton_euler.inverse_dynamics(arm, *q)),
                         (chosen.run.mass_matrix(q[0]), crba.mass_matrix(arm, q[0])),
                         (chosen.run.coriolis_matrix(q[0], q[1]), dynamics.coriolis_matrix(arm, q[0], q[1])),
                         (chosen.run.forward_dynamics(q[0, 0], q[1, 0], q[2, 0]),
                          forward_dynamics(arm, q[0, 0], q[1, 0], q[2, 0]))):
        np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-12 * np.abs(theirs).max())


def test_turned_off_the_recursions_as_written_run(monkeypatch, tmp_path):
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cold"))
    monkeypatch.setenv("COURSE_DYNAMICS_NATIVE", "off")
    assert looped.library() is None and "COURSE_DYNAMICS_NATIVE=off" in looped.why_not()
    arm = load_robot("two_link").with_gravity([0, 0, -9.6])
    assert evaluator.choice(arm).path == "interpreted"


def test_without_the_library_the_recursions_as_written_run(monkeypatch, tmp_path):
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cold"))
    monkeypatch.setattr(looped, "_LIBRARY", [None])                     # as where it was not built
    assert looped.looped(load_robot("ur5")) is None and "not built" in looped.why_not()
    arm = load_robot("two_link").with_gravity([0, 0, -9.5])
    chosen = evaluator.choice(arm)
    assert chosen.path == "interpreted" and not chosen.native
    q = np.array([0.3, -0.2])
    np.testing.assert_array_equal(course_dynamics.inverse_dynamics(arm, q, q, q),
                                  newton_euler.inverse_dynamics(arm, q, q, q))


def test_a_library_that_disagrees_with_the_recursions_is_not_used(monkeypatch):
    class Wrong:
        SOURCE_SHA256 = ""

        def __init__(self, right):
            self.right = right

        def tau(self, *arguments):
            self.right.tau(*arguments)
            arguments[-1][...] *= 1 + 1e-6                          # off in the sixth digit

        def mass_matrix(self, *arguments):
            self.right.mass_matrix(*arguments)

        def bias(self, *arguments):
            self.right.bias(*arguments)

    monkeypatch.setattr(looped, "_LIBRARY", [Wrong(looped.library())])
    assert looped.looped(load_robot("ur5")) is None


def test_a_build_that_fails_leaves_an_install_without_the_loop(tmp_path):
    """The extension is optional: a compiler that fails gives no library and a successful install."""
    tree = tmp_path / "tree"
    (tree / "course_dynamics" / "core" / "compiled").mkdir(parents=True)
    shutil.copy(ROOT / "setup.py", tree)
    shutil.copy(steps.SOURCE, tree / "course_dynamics" / "core" / "compiled")
    done = subprocess.run([sys.executable, "setup.py", "build_ext", "--inplace"], cwd=tree, capture_output=True,
                          text=True, timeout=120, env=dict(os.environ, CC="false", LDSHARED="false"))
    assert done.returncode == 0, done.stderr
    assert not list(tree.rglob("_looped*.so"))
    assert "failed" in (done.stdout + done.stderr).lower()


def test_a_coupling_onto_fewer_coordinates_writes_only_within_its_output():
    """Many bodies on one coordinate (a mimic's coupling) write M's n × n entries and nothing beyond them."""
    array = steps.model_array(load_robot("two_link")).reshape(-1)[:steps.HEADER + steps.BODY].copy()
    body = array[steps.HEADER:].copy()
    many = np.concatenate([array[:steps.HEADER]] + [body] * 2000)
    many[0], many[1] = 2000, 1
    many[steps.HEADER::steps.BODY] = np.arange(-1, 1999)              # a chain: each body's parent the one before
    out = np.full(3, np.nan)                                          # one entry of M, and two beyond it
    looped.library().mass_matrix(many, np.zeros(1), out[:1])
    assert np.isfinite(out[0]) and np.isnan(out[1:]).all()


CHANGED_WHILE_RUNNING = """
import threading
import numpy as np
from course_dynamics import load_robot
from course_dynamics.core.compiled import looped, steps
library = looped.library()
array = steps.model_array(load_robot("ur5"))
kind = steps.HEADER + 5 * steps.BODY + 1
q = np.random.default_rng(0).uniform(-1, 1, (200_000, 6))
out = np.empty_like(q)
stop = False
def flip():
    while not stop:
        array[kind] = 5e9
        array[kind] = 0.0
writer = threading.Thread(target=flip)
writer.start()
try:
    library.tau(array, q, q, q, out)               # computed from the array as it was checked ...
except ValueError as error:                        # ... or refused, if it was caught with a kind it has no step for
    assert "model array" in str(error)
stop = True
writer.join()
alias = steps.model_array(load_robot("ur5"))
library.tau(alias, q[:2], q[:2], q[:2], alias[steps.HEADER:steps.HEADER + 12])   # an output over the model
fresh = steps.model_array(load_robot("ur5"))
library.mass_matrix(fresh, q[0], fresh[steps.HEADER:steps.HEADER + 36])
print("done")
"""


def test_the_model_is_read_once_whatever_its_array_holds_meanwhile():
    """Another thread writing the model array, or an output that overlaps it: the C computes from a copy."""
    done = subprocess.run([sys.executable, "-c", CHANGED_WHILE_RUNNING], capture_output=True, text=True, timeout=120,
                          env=dict(os.environ, PYTHONPATH=str(ROOT)))
    assert done.returncode == 0 and done.stdout.strip() == "done", done.stderr[-2000:]


def test_a_loops_model_array_cannot_be_changed():
    run = looped.looped(load_robot("two_link"))
    with pytest.raises(ValueError, match="read-only"):
        run.array[steps.HEADER + steps.SLOTS["mass"]] *= 10


def test_a_library_built_from_any_other_c_is_told_apart():
    source = steps.SOURCE.read_text()
    assert steps.source_digest(source) == looped.library().SOURCE_SHA256
    for change in (("nb > 100000", "nb > 100"), ("#define BODY 64", "#define BODY 65"), ("out[0] = ", "out[0] =  ")):
        assert change[0] in source
        assert steps.source_digest(source.replace(*change[:2], 1)) != steps.source_digest(source), change


def test_turned_off_mid_process_the_loop_no_longer_stands_in(tmp_path, monkeypatch):
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cold"))
    arm = load_robot("rrr_arm").with_gravity([0, 0, -9.65])
    assert evaluator.choice(arm, calls=200).run.loop is not None
    monkeypatch.setenv("COURSE_DYNAMICS_NATIVE", "off")
    chosen = evaluator.choice(arm, calls=200)
    assert chosen.run.loop is None and not chosen.native


def test_compiling_a_model_ends_the_one_state_shortcut_to_its_loop(tmp_path, monkeypatch):
    """Once the cache holds the compiled model, a one-state call runs it, as the choice says."""
    from course_dynamics.core.compiled import CompiledModel, compile_model

    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cold"))
    arm = load_robot("ur5").with_gravity([0, 0, -9.66])
    q = np.random.default_rng(2).uniform(-1, 1, 6)
    course_dynamics.inverse_dynamics(arm, q, q, q)
    assert isinstance(looped.remembered(arm), looped.Looped)
    compile_model(arm)
    ran = []
    original = CompiledModel.native_call
    monkeypatch.setattr(CompiledModel, "native_call", lambda self, *a: (ran.append(a[0]), original(self, *a))[1])
    course_dynamics.inverse_dynamics(arm, q, q, q)
    assert ran == ["tau"] and evaluator.choice(arm).path == "compiled"
    assert isinstance(looped.remembered(arm), CompiledModel)


def gantry_urdf(seed: int) -> str:
    """A tree of prismatic joints on tilted frames, every axis horizontal in the world: V + G ≡ 0 at any state."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(seed)
    inertial = ('<inertial><origin xyz="{} {} {}"/><mass value="{}"/><inertia ixx="0.01" iyy="0.02" izz="0.03" '
                'ixy="0" ixz="0" iyz="0"/></inertial>')
    parts, world = ['<?xml version="1.0"?><robot name="gantry"><link name="base"/>'], {"base": np.eye(3)}
    for i, parent in enumerate(["base", "l0", "l0", "l1"]):
        rpy = rng.uniform(-np.pi, np.pi, 3)
        world[f"l{i}"] = world[parent] @ Rotation.from_euler("xyz", rpy).as_matrix()
        phi = rng.uniform(0, 2 * np.pi)
        axis = world[f"l{i}"].T @ np.array([np.cos(phi), np.sin(phi), 0.0])
        parts.append(f'<link name="l{i}">' + inertial.format(*rng.uniform(-0.1, 0.1, 3), rng.uniform(0.5, 5)) +
                     "</link>")
        parts.append(f'<joint name="j{i}" type="prismatic"><parent link="{parent}"/><child link="l{i}"/>'
                     f'<origin xyz="{" ".join(map(repr, rng.uniform(-0.3, 0.3, 3).tolist()))}" '
                     f'rpy="{" ".join(map(repr, rpy.tolist()))}"/><axis xyz="{" ".join(map(repr, axis.tolist()))}"/>'
                     '<limit lower="-1" upper="1" effort="100" velocity="1"/></joint>')
    return "".join(parts) + "</robot>"


def test_a_robot_gravity_does_not_load_gets_its_loop(tmp_path):
    """V + G ≡ 0: rounding residues of either sign in the loop and the recursions, not a disagreement."""
    residues = 0
    for seed in range(8):
        path = tmp_path / f"gantry{seed}.urdf"
        path.write_text(gantry_urdf(seed))
        model = load_urdf(path)
        run = looped.looped(model)
        assert run is not None, seed
        q, qd, _ = random_states(model, 1, seed=seed)
        bias = newton_euler.inverse_dynamics(model, q[0], qd[0], 0 * qd[0])
        assert np.abs(bias).max() < 1e-12
        residues += not np.array_equal(run.native_call("bias", q[0], qd[0]), bias)
    assert residues                                                    # the case the check must not mistake


def test_the_check_is_the_same_in_every_process():
    """Its state is drawn from the model's own numbers, so a robot's loop is used, or not, everywhere alike."""
    script = ("from course_dynamics import load_robot; from course_dynamics.core.compiled import looped; "
              "import numpy as np; r = looped.looped(load_robot('panda')); "
              "print(r is not None)")
    outs = {subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60,
                           env=dict(os.environ, PYTHONPATH=str(ROOT))).stdout for _ in range(2)}
    assert outs == {"True\n"}


def test_turned_off_mid_process_a_compiled_model_runs_its_python_programs(tmp_path, monkeypatch):
    from course_dynamics.core.compiled import compile_model

    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    arm = load_robot("two_link").with_gravity([0, 0, -9.64])
    compile_model(arm)
    q = np.array([0.2, -0.4])
    course_dynamics.inverse_dynamics(arm, q, q, q)
    assert evaluator.choice(arm).run.native
    monkeypatch.setenv("COURSE_DYNAMICS_NATIVE", "off")
    chosen = evaluator.choice(arm)
    assert chosen.path == "compiled" and not chosen.run.native and not chosen.native
    np.testing.assert_allclose(course_dynamics.inverse_dynamics(arm, q, q, q), newton_euler.inverse_dynamics(arm, q, q, q),
                               rtol=1e-12)


def test_a_compiled_model_whose_c_is_building_is_not_remembered_for_one_state_calls(tmp_path, monkeypatch):
    """Each one-state call then makes its choice, which takes the library up once the build has ended."""
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    arm = load_robot("rrr_arm").with_gravity([0, 0, -9.63])
    chosen = evaluator.choice(arm, calls=10_000)                       # a long run: its C starts building
    assert chosen.run.native_build is not None, chosen.run.native_reason
    again = evaluator.choice(arm)
    assert again.run.native_build is not None and looped.remembered(arm) is None
    finished = again.run.collected(wait=60)
    assert finished.native


def test_the_loop_will_not_be_built_with_fast_math(tmp_path):
    """-ffast-math would let the compiler drop the C's checks for NaN: the build stops, and the package runs
    without the loop."""
    import sysconfig

    cc = native.compiler()
    done = subprocess.run([cc, "-ffast-math", "-fsyntax-only", "-I", sysconfig.get_paths()["include"],
                           str(steps.SOURCE)], capture_output=True, text=True, timeout=120)
    assert done.returncode != 0 and "without -ffast-math" in done.stderr
