# %% [markdown]
# # 8. Simulation: integrating the equations of motion
#
# **What this notebook teaches.** How to turn the dynamics into motion: solve for the accelerations
# Θ̈ = M⁻¹(τ − V − G − F) (6.115) and integrate them in time. The notes' Euler scheme (6.116), (6.117) against
# better ones (semi-implicit Euler, Runge–Kutta 4); how their energy error grows with the step size; why a double
# pendulum cannot be predicted for long (chaos, shown with an ensemble of runs); and the motion itself, animated.
#
# **Notation** (Craig): Θ(t), Θ̇(t), Θ̈(t) the joint positions, velocities and accelerations; Δt the time step;
# E = k + u the total energy, constant for a robot with no torque and no friction.

# %%
import numpy as np
import matplotlib.pyplot as plt

from course_dynamics import gravity_torques, load_robot, mass_matrix, robot_path, velocity_torques
from course_dynamics.teaching.exercises import check, hint, my_robot
from course_dynamics.core.forward_dynamics import forward_dynamics
from course_dynamics.tools.simulation import simulate
from course_dynamics.output.viewer import show

pendulum = load_robot("double_pendulum_continuous")   # two links; θ = 0 points straight up

# %% [markdown]
# ## The accelerations, then a step
# Forward dynamics solves τ = M Θ̈ + V + G + F for Θ̈:
# $$\ddot\Theta = M^{-1}(\Theta)\,[\tau - V(\Theta, \dot\Theta) - G(\Theta) - F(\Theta, \dot\Theta)] \qquad (6.115)$$
# and the notes step it forward over Δt as a body would move if Θ̈ stayed constant during the step: the new velocity
# (6.116) and the new position (6.117) of uniformly accelerated motion, both from the old Θ, Θ̇ and Θ̈. (The notes
# say (6.115) comes "from (6.104)", the Cartesian form; it is (6.59) with friction solved for Θ̈. And they print the
# last term of (6.117) as ½Θ̈(Δt)Δt²: read as (6.116) reads Θ̈(Δt), a product, that is Θ̈Δt³/2; the acceleration
# belongs at time t. Notebook 9 shows both.)

# %%
q, qd = np.array([2.0, 0.0]), np.array([0.0, 0.0])
print("Θ̈ at release =", forward_dynamics(pendulum, q, qd, [0.0, 0.0]).round(4), "rad/s²")

# %% [markdown]
# ### Exercise 8.1 — the accelerations
# On your own two-link arm, `arm = my_robot("two_link").model`, write `forward_accelerations(q, qd, tau)`
# returning Θ̈ of (6.115) without friction, from the library's M(Θ) (`mass_matrix(arm, q)`), V(Θ, Θ̇)
# (`velocity_torques(arm, q, qd)`) and G(Θ) (`gravity_torques(arm, q)`): solve the linear system rather than invert
# M. (Calling `forward_dynamics` would pass this check, but not the grader.)

# %%
arm = my_robot("two_link").model


def forward_accelerations(q, qd, tau):
    ### BEGIN SOLUTION
    return np.linalg.solve(mass_matrix(arm, q), tau - velocity_torques(arm, q, qd) - gravity_torques(arm, q))
    ### END SOLUTION


# %%
check("forward_accelerations")

# %% [markdown]
# ### Exercise 8.2 — one step of the notes' scheme
# Write `euler_step(q, qd, qdd, dt)` returning the pair (Θ(t + Δt), Θ̇(t + Δt)) of (6.117) and (6.116): the
# position and velocity one step later, with the acceleration held at Θ̈(t) over the step (arrays in, arrays out;
# Δt in s).

# %%
def euler_step(q, qd, qdd, dt):
    ### BEGIN SOLUTION
    return q + qd * dt + 0.5 * qdd * dt**2, qd + qdd * dt
    ### END SOLUTION


# %%
check("euler_step")

# %% [markdown]
# ### Exercise 8.3 — semi-implicit Euler
# The same step in the other order, and simpler: update Θ̇ first, as (6.116) does, then move Θ over Δt at the
# *new* velocity alone (no Θ̈ term). Write `semi_implicit_step(q, qd, qdd, dt)` returning the new (Θ, Θ̇).

# %%
def semi_implicit_step(q, qd, qdd, dt):
    ### BEGIN SOLUTION
    qd_next = qd + qdd * dt
    return q + qd_next * dt, qd_next
    ### END SOLUTION


# %%
check("semi_implicit_step")

# %% [markdown]
# ## How wrong is each integrator?
# With no torque and no friction, energy is conserved exactly, so the energy a simulation gains or loses is its
# error. The first-order schemes err in proportion to Δt, Runge–Kutta 4 to Δt⁴:

# %%
steps = [0.01, 0.005, 0.002, 0.001]   # s
figure, ax = plt.subplots(figsize=(6.8, 3.8))
for integrator in ("euler", "semi-implicit", "rk4"):
    drift = []
    for dt in steps:
        run = simulate(pendulum, [2.0, 0.0], [0.0, 0.0], duration=2.0, dt=dt, integrator=integrator)
        drift.append(np.abs(run.energy - run.energy[0]).max() / abs(run.energy[0]))
    ax.loglog(steps, drift, "o-", label=integrator)
ax.set_xlabel("time step Δt (s)")
ax.set_ylabel("largest |E(t) − E(0)| / |E(0)| over 2 s")
ax.set_title("Double pendulum: energy error against step size")
ax.legend()
ax.grid(alpha=0.3, which="both")
plt.show()

# %% [markdown]
# ## A joint that hits its limit
# A URDF's joint limits are where the mechanism stops the joint. `simulate(..., limits="report")` only says when a
# joint passes one and goes on through it; `limits="stop"` stops the joint there by an impulse through M (the
# velocity projected, in the metric of M, onto the motions that keep the stopped joints still) and holds it while
# the motion pushes into the limit. That impulse can only take kinetic energy, never add it: a stop is an
# inelastic collision. The RRR arm released from rest falls until its second joint reaches its upper limit:

# %%
rrr = load_robot("rrr_arm")
free = simulate(rrr, [0.0, 0.3, 1.0], np.zeros(3), duration=2.0, dt=1e-3, limits="report")
stopped = simulate(rrr, [0.0, 0.3, 1.0], np.zeros(3), duration=2.0, dt=1e-3, limits="stop")
print(free.events[0])
for stop in stopped.stops[:3]:
    print(stop.sentence())
taken = sum(stop.energy for stop in stopped.stops)
print(f"{len(stopped.stops)} stops took {-taken:.4f} J; E(end) − E(0) = {stopped.energy[-1] - stopped.energy[0]:.4f} J")
figure, ax = plt.subplots(figsize=(6.8, 3.8))
ax.plot(free.t, free.energy, label='limits="report": passes through the limit')
ax.plot(stopped.t, stopped.energy, label='limits="stop": stopped by an impulse')
for stop in stopped.stops:
    ax.axvline(stop.t, color="tab:red", alpha=0.3, linewidth=0.8)
ax.set_xlabel("t (s)")
ax.set_ylabel("E = k + u (J)")
ax.set_title("RRR arm falling onto a joint limit: each stop (red) takes energy")
ax.legend()
ax.grid(alpha=0.3)
plt.show()

# %% [markdown]
# The energy is constant between stops (no torque, no friction) and drops at each one by what the stop's impulse
# took, so E(end) − E(0) is the sum of the stops' energies.

# %% [markdown]
# ## Chaos: an ensemble of nearly equal starts
# Released near upright, the double pendulum is chaotic: two starts a billionth of a radian apart soon move
# completely differently. `simulate` integrates many copies at once (each step one batched call):

# %%
starts = np.array([0.5, 0.5]) + 1e-9 * np.random.default_rng(0).standard_normal((40, 2))
starts[0] = [0.5, 0.5]
ensemble = simulate(pendulum, starts, np.zeros(2), duration=6.0, dt=2e-3)
distance = np.abs(ensemble.q[:, 1:] - ensemble.q[:, :1]).max(axis=-1)
figure, ax = plt.subplots(figsize=(6.8, 3.8))
ax.semilogy(ensemble.t, np.maximum(distance, 1e-16), color="tab:blue", alpha=0.3, linewidth=0.8)
ax.semilogy(ensemble.t, np.median(np.maximum(distance, 1e-16), axis=1), color="black", label="median of 39 members")
ax.set_xlabel("t (s)")
ax.set_ylabel("max |θⱼ − θⱼ of member 0| (rad)")
ax.set_title("40 double pendulums started 1e-9 rad apart")
ax.legend()
ax.grid(alpha=0.3)
plt.show()

# %% [markdown]
# ## The motion, animated
# The animation below is embedded in the notebook (it plays offline; drag to turn the view, and *Open Controls →
# Animations* has play, pause and a time slider).

# %%
run = simulate(pendulum, [2.0, 0.0], [0.0, 0.0], duration=4.0, dt=1e-3)
show(pendulum, robot_path("double_pendulum_continuous"), t=run.t[::10], q=run.q[::10], draw_path=True, static=True)
