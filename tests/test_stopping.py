"""course_dynamics/core/compiled/stopping.py (run by looped.rollout with joint stops): simulate(..., limits="stop")
in native code is the Python StopRun's run, to round-off (its samples, Θ̈, τ, λ, energy and the same stops: the
joints, sides, limits and times), on every integrator, robot with limits, torque input, friction and drives,
with a compiled model's C or the native loop; an ensemble on any number of threads is its members run alone;
no stop adds energy; it fails where the Python steps fail, with the same error; it refuses bounds it cannot
trust; and where it cannot run, the Python steps do."""
from __future__ import annotations

import numpy as np
import pytest
from helpers import chain_urdf

from course_dynamics import load_robot, load_urdf
from course_dynamics.core.compiled import looped, native
from course_dynamics.core.compiled.impulses import STOP_RECORD
from course_dynamics.core.drives import Drives
from course_dynamics.core.friction import Friction
from course_dynamics.core.robots import robot_names
from course_dynamics.tools import simulation
from course_dynamics.tools.joint_stops import limit_bounds
from course_dynamics.tools.simulation import SimulationError, TorqueTable, simulate

pytestmark = pytest.mark.skipif(native.compiler() is None,
                                reason="no C compiler: the package was installed without the native run")

LIMITED = [name for name in robot_names() if np.isfinite(limit_bounds(load_robot(name))[0]).any()]


def in_python(monkeypatch):
    """Make simulate take its Python steps (as where there is no native run)."""
    monkeypatch.setattr(simulation, "rollout", lambda *arguments: None)


def spied(monkeypatch):
    """The native run's calls: whether each had joint stops (simulate still runs it)."""
    calls = []
    original = simulation.rollout

    def counted(*arguments):
        calls.append(arguments[-1] is not None)
        return original(*arguments)

    monkeypatch.setattr(simulation, "rollout", counted)
    return calls


def toward_limits(model, speed=1.0):
    """85 % of the way from each limited joint's middle to a limit (alternately upper and lower), moving toward it
    at ``speed`` times half its range a second."""
    lower, upper = limit_bounds(model)
    limited = np.isfinite(lower)
    sign = np.resize([1.0, -1.0], model.n)
    middle, half = np.where(limited, 0.5 * (lower + upper), 0.0), np.where(limited, 0.5 * (upper - lower), 1.0)
    return middle + 0.85 * half * sign * limited, speed * half * sign * limited


def assert_same_stopped_run(ours, theirs, tolerance=1e-10):
    """The same samples to round-off of each quantity's size, and the same stops."""
    for name in ("q", "qd", "qdd", "tau", "energy", "reaction"):
        a, b = getattr(ours, name), getattr(theirs, name)
        scale = max(1.0, np.abs(b).max())
        np.testing.assert_allclose(a, b, rtol=0, atol=tolerance * scale, err_msg=name)
    assert len(ours.stops) == len(theirs.stops)
    for a, b in zip(ours.stops, theirs.stops):
        assert (a.member, a.joints, a.sides) == (b.member, b.joints, b.sides), (a.sentence(), b.sentence())
        assert a.t == pytest.approx(b.t, abs=1e-9) and a.limits == pytest.approx(b.limits, abs=1e-12)
        scale = max(1.0, b.kinetic_before)
        assert a.kinetic_before == pytest.approx(b.kinetic_before, abs=tolerance * scale)
        assert a.kinetic_after == pytest.approx(b.kinetic_after, abs=tolerance * scale)


@pytest.mark.parametrize("name", LIMITED)
@pytest.mark.parametrize("integrator", ["euler", "semi-implicit", "rk4"])
def test_native_stops_are_the_python_stops(name, integrator, monkeypatch):
    """Every limited joint run into a limit, with a torque table, friction (tanh) and drives."""
    model = load_robot(name)
    n = model.n
    rng = np.random.default_rng(11)
    q0, qd0 = toward_limits(model)
    table = TorqueTable(t=np.array([0.0, 0.2, 0.5]), tau=0.2 * rng.standard_normal((3, n)))
    dt = 2e-4 if (name, integrator) == ("panda", "semi-implicit") else 1e-3
    options = dict(duration=0.6, dt=dt, integrator=integrator, torque=table, limits="stop",
                   friction=Friction(viscous=np.full(n, 0.02), coulomb=np.full(n, 0.05), smoothing=0.02),
                   drives=Drives(armature=np.full(n, 0.01), offset=np.linspace(-0.05, 0.05, n)))
    calls = spied(monkeypatch)
    ours = simulate(model, q0, qd0, **options)
    assert calls == [True] and ours.stops
    in_python(monkeypatch)
    assert_same_stopped_run(ours, simulate(model, q0, qd0, **options))


@pytest.mark.parametrize("source", ["compiled", "loop"])
def test_the_loop_and_a_compiled_models_c_stop_alike(source, monkeypatch):
    """UR5 released toward its limits with no torque: the same run from either C as from the Python steps."""
    model = load_robot("ur5")
    q0, qd0 = toward_limits(model, speed=2.0)
    if source == "loop":
        monkeypatch.setattr(simulation, "implementation", lambda model, **_: looped.looped(model))
    options = dict(duration=0.5, dt=1e-3, limits="stop", compiled=source == "compiled")
    calls = spied(monkeypatch)
    ours = simulate(model, q0, qd0, **options)
    assert calls == [True] and len(ours.stops) > 3
    in_python(monkeypatch)
    assert_same_stopped_run(ours, simulate(model, q0, qd0, **options))


def test_joints_that_start_on_their_limits_and_many_stops_in_one_call(tmp_path, monkeypatch):
    """Four four-joint chains started on their limits running into them (a contact at t = 0 stopping several
    joints at once), bouncing for two seconds on one thread: more stops in one native call than its record's
    first allocation, the same as the Python steps' and none adding energy."""
    path = tmp_path / "chain.urdf"
    path.write_text(chain_urdf(4).replace('lower="-1" upper="1"', 'lower="-0.3" upper="0.3"'))
    model = load_urdf(path)
    q0 = np.tile([0.3, -0.3, 0.3, -0.3], (4, 1))
    qd0 = np.array([1.0, -1.0, 1.0, -1.0]) * np.array([[1.0], [0.9], [1.1], [1.2]])
    monkeypatch.setattr(native, "THREADS", 1)
    ours = simulate(model, q0, qd0, duration=2.0, dt=1e-3, limits="stop")
    assert ours.stops[0].t == 0.0 and len(ours.stops[0].joints) > 1 and len(ours.stops) > 16
    assert all(stop.energy <= 1e-12 * (1.0 + stop.kinetic_before) for stop in ours.stops)
    in_python(monkeypatch)
    assert_same_stopped_run(ours, simulate(model, q0, qd0, duration=2.0, dt=1e-3, limits="stop"))


def test_a_joint_held_against_its_limit_is_held_alike(monkeypatch):
    """rp_arm pushed into d2's upper limit by 5 N: stopped, then held for the rest of the run, its reaction λ the
    same on both paths."""
    model = load_robot("rp_arm")
    options = dict(duration=1.0, dt=1e-3, torque=[0.3, 5.0], limits="stop")
    ours = simulate(model, [0.0, 0.5], [0.4, 0.0], **options)
    held = ours.reaction[:, 1] != 0
    assert held.sum() > 500 and np.all(ours.q[held, 1] == 0.8) and np.all(ours.qd[held, 1] == 0.0)
    in_python(monkeypatch)
    assert_same_stopped_run(ours, simulate(model, [0.0, 0.5], [0.4, 0.0], **options))


@pytest.mark.parametrize("threads", [1, 3])
def test_an_ensemble_is_its_members_run_alone_on_any_number_of_threads(threads, monkeypatch):
    model = load_robot("rrr_arm")
    q0 = np.array([[0.0, 1.5, 2.0], [0.2, -1.0, 1.0], [0.0, 0.0, 0.0], [0.1, 0.3, -0.5]])
    qd0 = np.array([[1.0, 2.0, 3.0], [-1.0, -3.0, 1.0], [0.0, 0.0, 0.0], [2.0, 0.0, -2.0]])
    monkeypatch.setattr(native, "THREADS", threads)
    monkeypatch.setattr(native, "THREAD_STATES", 1)
    together = simulate(model, q0, qd0, duration=0.5, dt=1e-3, limits="stop")
    assert {stop.member for stop in together.stops} == {0, 1, 2, 3}
    assert [(s.t, s.member or 0) for s in together.stops] == sorted((s.t, s.member or 0) for s in together.stops)
    for k in range(len(q0)):
        alone = simulate(model, q0[k], qd0[k], duration=0.5, dt=1e-3, limits="stop")
        np.testing.assert_array_equal(together.q[:, k], alone.q)
        np.testing.assert_array_equal(together.reaction[:, k], alone.reaction)
        assert [(s.t, s.joints) for s in together.stops if s.member == k] == [(s.t, s.joints) for s in alone.stops]
        assert all(s.member is None for s in alone.stops)
    in_python(monkeypatch)
    assert_same_stopped_run(together, simulate(model, q0, qd0, duration=0.5, dt=1e-3, limits="stop"))


def test_no_stop_adds_energy_over_a_long_native_run():
    """The Panda released with no torque for 5 s under 'stop': every stop takes energy, and the total never
    rises above the start's plus the integrator's own drift without stops."""
    model = load_robot("panda")
    q0 = [0, 0, 0, -1.5, 0, 1.5, 0.7, 0.02]
    report = simulate(model, q0, np.zeros(8), duration=5.0, dt=1e-3, limits="report")
    stop = simulate(model, q0, np.zeros(8), duration=5.0, dt=1e-3, limits="stop")
    drift = np.abs(report.energy - report.energy[0]).max()
    assert len(stop.stops) > 3 and all(each.energy <= 1e-12 * (1.0 + each.kinetic_before) for each in stop.stops)
    assert stop.energy.max() <= report.energy[0] + drift + 1e-12 * abs(report.energy[0])
    lower, upper = limit_bounds(model)
    assert np.all(stop.q >= lower) and np.all(stop.q <= upper)


def test_failures_under_stops_are_the_python_steps_errors(monkeypatch):
    """A state that blows up, and a table torque whose line overflows with a joint started on its limit."""
    model = load_robot("rp_arm")
    steep = TorqueTable(t=np.array([0.0, 0.0105]), tau=np.array([[0.0, 0.0], [1e307, 1e307]]))
    found = []
    for _ in range(2):
        with pytest.raises(SimulationError, match="the state became non-finite near t = ") as error:
            simulate(model, [0.0, 0.5], [0.0, 0.0], duration=0.5, dt=1e-3, torque=[1e200, 1e200], limits="stop")
        found.append(str(error.value))
        with pytest.raises(SimulationError, match="the torque at t = 0.0005 s is \\[inf, inf\\]") as error:
            simulate(model, [0.0, 0.8], [0.0, 1.0], duration=0.5, dt=1e-3, torque=steep, limits="stop")
        found.append(str(error.value))
        in_python(monkeypatch)
    assert found[:2] == found[2:]


def test_the_c_refuses_bounds_it_cannot_trust():
    library = looped.library()
    model = load_robot("rp_arm")
    n, T = 2, 4
    times, z = np.arange(T) * 1e-3, np.zeros((T, n))
    table, parameters, status = np.zeros((1, n + 1)), np.zeros(4 * n + 1), np.zeros(3 + 3 * n)
    good = np.array([1e-3, -1.0, -np.inf, 1.0, np.inf])

    def call(bounds=good, records=None, held=None):
        arrays = [times, z.copy(), z.copy(), z.copy(), z.copy(), table, parameters, status]
        extra = [z.copy() if held is None else held, z.copy(), bounds, [] if records is None else records]
        return library.rollout(looped.looped(model).array, *arrays, 2, 0, T - 1, 0, 1, *extra)

    assert call() == 0
    for bounds in (np.array([0.0, -1.0, -1.0, 1.0, 1.0]), np.array([np.nan, -1.0, -1.0, 1.0, 1.0]),
                   np.array([1e-3, 1.0, -1.0, 1.0, 1.0]), np.array([1e-3, np.nan, -1.0, 1.0, 1.0])):
        with pytest.raises(ValueError, match="bounds are not in order"):
            call(bounds)
    with pytest.raises(ValueError, match="sizes"):
        call(good[:-1].copy())
    with pytest.raises(ValueError, match="sizes"):
        call(held=np.zeros((T, n + 1)))
    with pytest.raises(TypeError, match="list"):
        call(records=())
    with pytest.raises(TypeError, match="float64"):
        call(held=z.astype(np.float32))
    with pytest.raises(TypeError, match="three arrays and a list"):
        library.rollout(looped.looped(model).array, times, *[z.copy()] * 4, table, parameters, status, 2, 0, 1, 0,
                        1, z.copy())
    records = []
    assert call(np.array([1e-3, -1.0, -1.0, 0.0, 1.0]), records) == 0  # joint 1 starts at rest on its upper limit
    rows = np.frombuffer(b"".join(records)).reshape(-1, 4 + 2 * n)
    assert len(STOP_RECORD) == 6  # t, member, the energy before and after, the sides, the positions
    np.testing.assert_array_equal(rows, [[0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]])


def test_turned_off_or_a_state_dependent_torque_the_python_steps_stop(monkeypatch):
    model = load_robot("rp_arm")
    options = dict(duration=0.5, dt=1e-3, limits="stop")
    reference = simulate(model, [0.0, 0.5], [1.0, 1.0], torque=[0.0, 2.0], **options)
    calls = spied(monkeypatch)
    by_function = simulate(model, [0.0, 0.5], [1.0, 1.0], torque=lambda t, q, qd: np.array([0.0, 2.0]), **options)
    assert calls == []
    assert_same_stopped_run(reference, by_function)
    monkeypatch.undo()
    monkeypatch.setenv("COURSE_DYNAMICS_NATIVE", "off")
    assert_same_stopped_run(reference, simulate(model, [0.0, 0.5], [1.0, 1.0], torque=[0.0, 2.0], **options))
