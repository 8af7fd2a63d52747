"""course_dynamics/core/compiled/rollout.py (run by looped.rollout): a whole fixed-step simulation in native calls
is the Python steps' run, to round-off, on every integrator, torque input, friction and drives, with a compiled
model's C or the native loop; it agrees with Pinocchio; it stops where the Python steps stop, naming the same
problem at the same time (an ensemble's earliest, however it is shared); it refuses what it cannot trust; and
where it cannot run, the Python steps do."""
from __future__ import annotations

import ctypes

import numpy as np
import pytest
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from helpers import DATA, arm_urdf

from course_dynamics import load_robot, load_urdf, robot_path
from course_dynamics.core.compiled import compile_model, looped, native, rollout
from course_dynamics.core.drives import Drives
from course_dynamics.core.forward_dynamics import SingularMassMatrixError
from course_dynamics.core.friction import Friction
from course_dynamics.tools import simulation
from course_dynamics.tools.simulation import SimulationError, TorqueTable, simulate

pytestmark = pytest.mark.skipif(native.compiler() is None,
                                reason="no C compiler: the package was installed without the native run")


def in_python(monkeypatch):
    """Make simulate take its Python steps (as where there is no native run)."""
    monkeypatch.setattr(simulation, "rollout", lambda *arguments: None)


def assert_same_run(native_run, python_run, tolerance=1e-12):
    for name in ("q", "qd", "qdd", "tau", "energy"):
        ours, theirs = getattr(native_run, name), getattr(python_run, name)
        scale = max(1.0, np.abs(theirs).max())
        np.testing.assert_allclose(ours, theirs, rtol=0, atol=tolerance * scale, err_msg=name)
    assert native_run.events == python_run.events


def spied(monkeypatch):
    """Count the native run's calls (simulate still runs it)."""
    calls = []
    original = simulation.rollout

    def counted(*arguments):
        calls.append(arguments[4])
        return original(*arguments)

    monkeypatch.setattr(simulation, "rollout", counted)
    return calls


ROBOTS = ["double_pendulum_continuous", "ur5", "rp_arm", str(DATA / "mimic_order.urdf")]


def robot(name):
    return load_urdf(name) if name.endswith(".urdf") else load_robot(name)


@pytest.mark.parametrize("name", ROBOTS)
@pytest.mark.parametrize("integrator", ["euler", "semi-implicit", "rk4"])
@pytest.mark.parametrize("source", ["compiled", "loop"])
def test_the_native_run_is_the_python_steps_run(name, integrator, source, monkeypatch):
    """With friction (tanh), drives and a torque table: the same samples, Θ̈, τ, energy and limit events."""
    model = robot(name)
    n = model.n
    rng = np.random.default_rng(7)
    q0, qd0 = 0.3 * rng.standard_normal(n), 0.5 * rng.standard_normal(n)
    table = TorqueTable(t=np.array([0.0, 0.05, 0.12]), tau=rng.standard_normal((3, n)))
    options = dict(duration=0.15, dt=1e-3, integrator=integrator, torque=table,
                   friction=Friction(viscous=np.full(n, 0.05), coulomb=np.full(n, 0.1), smoothing=0.02),
                   drives=Drives(armature=np.full(n, 0.01), offset=np.linspace(-0.1, 0.1, n)),
                   compiled=source == "compiled")
    if source == "loop":
        monkeypatch.setattr(simulation, "implementation", lambda model, **_: looped.looped(model))
    calls = spied(monkeypatch)
    ours = simulate(model, q0, qd0, **options)
    assert calls == [integrator]
    kind = "PyCapsule" if source == "compiled" else "ndarray"
    assert type(looped.terms(simulation.implementation(model, calls=600, compiled=True) if source == "compiled"
                             else looped.looped(model))).__name__ == kind
    in_python(monkeypatch)
    assert_same_run(ours, simulate(model, q0, qd0, **options))


@pytest.mark.parametrize("friction", [None, Friction(viscous=[0.1, 0.2], coulomb=[0.3, 0.05])])
@pytest.mark.parametrize("torque", [None, [0.5, -0.2]])
def test_zero_and_constant_torques_and_coulombs_sign_run_natively(friction, torque, monkeypatch):
    model = load_robot("double_pendulum_continuous")
    calls = spied(monkeypatch)
    ours = simulate(model, [2.0, 0.1], [0.0, 0.3], duration=0.3, dt=1e-3, torque=torque, friction=friction)
    assert calls == ["rk4"]
    in_python(monkeypatch)
    assert_same_run(ours, simulate(model, [2.0, 0.1], [0.0, 0.3], duration=0.3, dt=1e-3, torque=torque,
                                   friction=friction))


def test_a_run_agrees_with_pinocchio():
    """The same RK4 steps with Pinocchio's aba: 1e-9 of the motion's size at every sample."""
    model = load_robot("ur5")
    oracle = PinocchioOracle(robot_path("ur5"), model.joint_names)
    q0, torque = np.array([0.0, -1.2, 1.0, -0.5, 0.5, 0.0]), np.array([1.0, -2.0, 0.5, 0.1, 0.0, 0.2])
    ours = simulate(model, q0, np.zeros(6), duration=0.2, dt=1e-3, torque=torque, compiled=True)

    def aba(q, qd, tau):
        return np.reshape([oracle.aba(a, b, c) for a, b, c in zip(q.reshape(-1, 6), qd.reshape(-1, 6),
                                                                  tau.reshape(-1, 6))], q.shape)

    theirs = simulate(model, q0, np.zeros(6), duration=0.2, dt=1e-3, torque=torque, dynamics=aba)
    for name in ("q", "qd", "qdd"):
        scale = np.abs(getattr(theirs, name)).max()
        np.testing.assert_allclose(getattr(ours, name), getattr(theirs, name), rtol=0, atol=1e-9 * scale)


def test_an_ensemble_shared_over_threads_is_the_same_bits(monkeypatch):
    model = load_robot("double_pendulum_continuous")
    q0 = np.array([2.0, 0.0]) + 0.01 * np.random.default_rng(3).standard_normal((9, 2))
    monkeypatch.setattr(native, "THREADS", 1)
    alone = simulate(model, q0, np.zeros(2), duration=0.1, dt=1e-3)
    monkeypatch.setattr(native, "THREADS", 3)
    monkeypatch.setattr(native, "THREAD_STATES", 1)
    shared = simulate(model, q0, np.zeros(2), duration=0.1, dt=1e-3)
    for name in ("q", "qd", "qdd", "tau"):
        np.testing.assert_array_equal(getattr(shared, name), getattr(alone, name))
    in_python(monkeypatch)
    assert_same_run(shared, simulate(model, q0, np.zeros(2), duration=0.1, dt=1e-3))


def test_progress_is_told_in_chunks_that_add_up_to_every_step(monkeypatch):
    monkeypatch.setattr(looped, "CHUNK_EVALUATIONS", 40)
    told = []
    model = load_robot("pendulum")
    run = simulate(model, [0.5], [0.0], duration=0.1, dt=1e-3, progress=told.append)
    assert sum(told) == 100 and len(told) == 10 and len(run.t) == 101
    in_python(monkeypatch)
    assert_same_run(run, simulate(model, [0.5], [0.0], duration=0.1, dt=1e-3))


def test_a_state_that_blows_up_natively_is_the_same_error():
    model = load_robot("pendulum")
    with pytest.raises(SimulationError, match="the state became non-finite near t = 2 s \\(try a smaller dt\\)"):
        simulate(model, [0.1], [0.0], duration=4.0, dt=2.0, integrator="euler", torque=[1e308])


@pytest.mark.parametrize("integrator", ["euler", "semi-implicit", "rk4"])
def test_terms_that_overflow_at_a_finite_state_are_the_same_error_at_the_same_time(integrator, monkeypatch):
    """A torque of 1e200 N·m: the first accelerations overflow, which both paths call a state gone non-finite
    (not a singular mass matrix), at the same time."""
    model = load_robot("rp_arm")
    found = []
    for _ in range(2):
        with pytest.raises(SimulationError, match="the state became non-finite near t = ") as error:
            simulate(model, [0.0, 0.5], [0.0, 0.0], duration=0.05, dt=1e-3, integrator=integrator,
                     torque=[1e200, 1e200])
        found.append(str(error.value))
        in_python(monkeypatch)
    assert found[0] == found[1]


def test_a_table_whose_slope_overflows_is_the_same_error_or_the_same_run(monkeypatch):
    """As numpy.interp: a row's own value at its time, the torque named where the line between rows overflows."""
    model = load_robot("rp_arm")
    steep = TorqueTable(t=np.array([0.0, 0.0105]), tau=np.array([[0.0, 0.0], [1e307, 1e307]]))
    held = TorqueTable(t=np.array([0.0, 1e-310, 1e-3, 1.0]), tau=np.array([[1.0, 1.0], [1e300, 1e300],
                                                                            [1.0, 1.0], [1.0, 1.0]]))
    found, runs = [], []
    for _ in range(2):
        for q0 in (np.zeros(2), np.zeros((3, 2))):
            with pytest.raises(SimulationError, match="the torque at t = 0.0005 s is \\[inf, inf\\]") as error:
                simulate(model, q0, np.zeros_like(q0), duration=0.05, dt=1e-3, torque=steep)
            found.append(str(error.value))
        runs.append(simulate(model, [0.0, 0.5], [0.0, 0.0], duration=0.005, dt=1e-3, integrator="euler",
                             torque=held))
        in_python(monkeypatch)
    assert found[:2] == found[2:] and "(or shape (3, 2))" in found[1]
    assert_same_run(*runs)
    np.testing.assert_array_equal(runs[0].tau, np.ones((6, 2)))


@pytest.mark.parametrize("threads", [1, 2, 4])
def test_an_ensemble_stops_at_its_earliest_failure_however_it_is_shared(threads, monkeypatch):
    """The members fail at different times; the first member fails last: the run names the earliest time on any
    number of threads, as the Python steps do."""
    model = load_robot("double_pendulum_continuous")
    q0, qd0 = np.tile([0.3, 0.4], (4, 1)), np.array([[1e5, 0.0], [1e10, 0.0], [1e20, 0.0], [1e40, 0.0]])
    monkeypatch.setattr(native, "THREADS", threads)
    monkeypatch.setattr(native, "THREAD_STATES", 1)
    with pytest.raises(SimulationError, match="near t = 0.2 s") as native_error:
        simulate(model, q0, qd0, duration=1.0, dt=0.1, integrator="euler")
    done = looped.rollout(looped.looped(model), np.arange(11) * 0.1, q0, qd0, "euler", np.zeros(1), np.zeros((1, 2)))
    assert done.failure == "not finite" and done.member == 3 and done.t == pytest.approx(0.2)
    in_python(monkeypatch)
    with pytest.raises(SimulationError) as python_error:
        simulate(model, q0, qd0, duration=1.0, dt=0.1, integrator="euler")
    assert str(native_error.value) == str(python_error.value)


def test_a_singular_mass_matrix_is_named_by_the_checked_solve(tmp_path):
    path = tmp_path / "massless.urdf"
    path.write_text(arm_urdf(mass="0", ixx="0", iyy="0", izz="0"))
    model = load_urdf(path)
    with pytest.raises(SingularMassMatrixError, match="joint 'joint2' moves no mass"):
        simulate(model, [0.1, 0.2], [0.0, 0.0], duration=0.01, dt=1e-3)


def test_what_needs_python_runs_the_python_steps(monkeypatch):
    """A torque that is a function of the state (with joint stops too), the adaptive integrator, a dynamics of
    one's own."""
    model = load_robot("rp_arm")
    calls = spied(monkeypatch)
    simulate(model, [0.0, 0.5], [0.0, 0.0], duration=0.02, dt=1e-3, torque=lambda t, q, qd: -qd)
    simulate(model, [0.0, 0.5], [0.0, 0.0], duration=0.02, dt=1e-3, torque=lambda t, q, qd: -qd, limits="stop")
    simulate(model, [0.0, 0.5], [0.0, 0.0], duration=0.02, dt=1e-3, integrator="adaptive")
    simulate(model, [0.0, 0.5], [0.0, 0.0], duration=0.02, dt=1e-3, dynamics=lambda q, qd, tau: 0 * q)
    assert calls == []


def test_turned_off_or_missing_the_python_steps_run(monkeypatch):
    model = load_robot("double_pendulum_continuous")
    reference = simulate(model, [2.0, 0.0], [0.0, 0.0], duration=0.1, dt=1e-3)
    monkeypatch.setattr(looped, "library", lambda: None)
    assert looped.rollout(looped.looped(model), np.arange(3.0), np.zeros(2), np.zeros(2), "rk4", np.zeros(1),
                          np.zeros((1, 2))) is None
    assert_same_run(simulate(model, [2.0, 0.0], [0.0, 0.0], duration=0.1, dt=1e-3), reference)
    monkeypatch.undo()
    monkeypatch.setenv("COURSE_DYNAMICS_NATIVE", "off")
    assert looped.library() is None or looped.rollout(object(), np.arange(3.0), np.zeros(2), np.zeros(2), "rk4",
                                                      np.zeros(1), np.zeros((1, 2))) is None
    assert_same_run(simulate(model, [2.0, 0.0], [0.0, 0.0], duration=0.1, dt=1e-3), reference)


def test_the_c_refuses_what_it_cannot_trust():
    library = looped.library()
    model = load_robot("ur5")
    run = looped.looped(model)
    n, T = 6, 4
    times, z = np.arange(T) * 1e-3, np.zeros((T, n))
    table, parameters, status = np.zeros((1, n + 1)), np.zeros(4 * n + 1), np.zeros(3 + 3 * n)

    def call(*changes, source=run.array, integers=(2, 0, T - 1, 0, 1)):
        arrays = [times, z.copy(), z.copy(), z.copy(), z.copy(), table, parameters, status]
        for k, value in changes:
            arrays[k] = value
        return library.rollout(source, *arrays, *integers)

    assert call() == 0
    for integers in ((3, 0, T - 1, 0, 1), (2, 0, T, 0, 1), (2, 2, 1, 0, 1), (2, 0, T - 1, 0, 2), (2, -1, 1, 0, 1)):
        with pytest.raises(ValueError, match="sizes"):
            call(integers=integers)
    for change in ((1, np.zeros((T, 5))), (5, np.zeros((1, n))), (6, np.zeros(4 * n)), (7, np.zeros(3))):
        with pytest.raises(ValueError, match="sizes"):
            call(change)
    for change in ((0, times[::-1].copy()), (0, np.array([0.0, np.nan, 1.0, 2.0])),
                   (5, np.zeros((2, n + 1))), (6, np.full(4 * n + 1, -1.0))):
        with pytest.raises(ValueError, match="order"):
            call(change)
    with pytest.raises(TypeError, match="float64"):
        call((1, z.astype(np.float32)))
    with pytest.raises(ValueError, match="model array"):
        call(source=run.array[:-1].copy())
    with pytest.raises(ValueError):
        call(source=np.zeros(3))
    make = ctypes.pythonapi.PyCapsule_New
    make.restype, make.argtypes = ctypes.py_object, [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_void_p]
    held = ctypes.c_int(1)
    with pytest.raises(ValueError):  # a capsule of another name
        call(source=make(ctypes.addressof(held), b"something.else", None))
    with pytest.raises(TypeError):
        library.rollout(run.array, times)
    assert rollout.STATUS[call((1, np.full((T, n), np.nan)))] == "not finite"  # the start: status 1


def test_a_compiled_models_capsule_is_its_own_m_and_bias():
    model = load_robot("ur5")
    fast = compile_model(model)
    capsule = looped.terms(fast)
    assert type(capsule).__name__ == "PyCapsule" and rollout.CAPSULE in repr(capsule)
    times = np.arange(50) * 1e-3
    q0 = np.array([0.0, -1.2, 1.0, -0.5, 0.5, 0.0])
    by_c = looped.rollout(fast, times, q0, np.zeros(6), "rk4", np.zeros(1), np.zeros((1, 6)))
    by_loop = looped.rollout(looped.looped(model), times, q0, np.zeros(6), "rk4", np.zeros(1), np.zeros((1, 6)))
    np.testing.assert_allclose(by_c.q, by_loop.q, rtol=0, atol=1e-13)
    np.testing.assert_allclose(by_c.qdd, by_loop.qdd, rtol=0, atol=1e-11 * np.abs(by_loop.qdd).max())
