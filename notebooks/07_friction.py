# %% [markdown]
# # 7. Friction and other effects the rigid-body model leaves out
#
# **What this notebook teaches.** Real joints lose torque to friction, a term F(Θ, Θ̇) added to the rigid-body
# equation, τ = M Θ̈ + V + G + F (6.114). The common models: viscous friction proportional to speed (6.110),
# Coulomb friction of constant size opposing the motion (6.111), and both (6.112); what each does to the torque
# along a motion, and where the simple models stop (sticking at rest).
#
# **Notation** (Craig): v the viscous coefficient (N·m·s/rad), c the Coulomb coefficient (N·m); sgn(θ̇) the sign
# of the joint velocity.

# %%
import numpy as np
import matplotlib.pyplot as plt

from course_dynamics import inverse_dynamics, load_robot
from course_dynamics.teaching.exercises import check, given, hint, my_robot
from course_dynamics.core.friction import Friction
from course_dynamics.core.sampling import smooth_trajectory

# %% [markdown]
# ## The models
# $$F = v\,\dot\theta \quad (6.110)\qquad F = c\,\mathrm{sgn}(\dot\theta) \quad (6.111)\qquad F = c\,\mathrm{sgn}(\dot\theta) + v\,\dot\theta \quad (6.112)$$
# Both oppose the motion (F θ̇ ≥ 0: friction only ever takes energy out). Coulomb friction jumps at θ̇ = 0; real
# joints also *stick* there until the torque exceeds a breakaway level, which these models do not capture. A
# smooth approximation, c tanh(θ̇/ε), avoids the jump in simulation.

# %%
rates = np.linspace(-2.0, 2.0, 401)   # rad/s
models = {"viscous (6.110), v = 0.4": Friction([0.4], [0.0]), "Coulomb (6.111), c = 0.5": Friction([0.0], [0.5]),
          "combined (6.112)": Friction([0.4], [0.5]), "combined, smoothed (ε = 0.05)": Friction([0.4], [0.5], 0.05)}
figure, ax = plt.subplots(figsize=(6.8, 3.8))
for label, model in models.items():
    ax.plot(rates, model.torques(rates[:, None])[:, 0], label=label)
ax.set_xlabel("joint velocity θ̇ (rad/s)")
ax.set_ylabel("friction torque F (N·m)")
ax.set_title("Friction models")
ax.legend(fontsize="small")
ax.grid(alpha=0.3)
plt.show()

# %% [markdown]
# ### Exercise 7.1 — the combined model
# Write `friction_torque(qd, v, c)`: (6.112) for arrays of joint velocities qd, viscous coefficients v and Coulomb
# coefficients c (one per joint). The check runs it with your own arm's coefficients, those of
# `given("tau_with_friction")` below, at joint velocities of yours (some of them 0).

# %%
def friction_torque(qd, v, c):
    ### BEGIN SOLUTION
    return c * np.sign(qd) + v * qd
    ### END SOLUTION


# %%
check("friction_torque")

# %% [markdown]
# ## Along a motion
# The torque a motor must give is the rigid-body torque plus the friction; at reversals of a joint's velocity the
# Coulomb part flips sign.

# %%
arm = load_robot("two_link")
t, q, qd, qdd = smooth_trajectory(arm, duration=4.0, samples=801)
friction = Friction(viscous=[0.3, 0.2], coulomb=[0.8, 0.5])
rigid = inverse_dynamics(arm, q, qd, qdd)
figure, axes = plt.subplots(2, 1, sharex=True, figsize=(7, 5.2), constrained_layout=True)
for j, name in enumerate(arm.joint_names):
    axes[j].plot(t, rigid[:, j], label="rigid body, M Θ̈ + V + G")
    axes[j].plot(t, rigid[:, j] + friction.torques(qd)[:, j], label="with friction, + F(Θ̇) (6.114)")
    axes[j].set_ylabel(f"τ of {name} (N·m)")
    axes[j].grid(alpha=0.3)
axes[0].legend(fontsize="small")
axes[1].set_xlabel("t (s)")
axes[0].set_title("Two-link arm: torques with and without joint friction")
plt.show()

# %% [markdown]
# ### Exercise 7.2 — the torque with friction at one state
# Your exercise uses your own two-link arm, not the section's arm of the plot above: its numbers are below, read
# into `m1, m2, l1, l2, g`. At your state `given("tau_with_friction")` (q, qd, qdd and the viscous and Coulomb
# coefficients of both joints), compute your arm's joint torques including friction, (6.114), as
# `tau_with_friction` (2 numbers, N·m): the rigid-body part M Θ̈ + V + G from the closed forms you wrote in
# notebook 4 (6.60)–(6.62), with your numbers, then the friction of (6.112) with yours.

# %%
print(my_robot("two_link").describe())
mine = my_robot("two_link").parameters
m1, m2, l1, l2, g = (mine[name] for name in ("m1", "m2", "l1", "l2", "g"))   # kg, m, m/s²
state = given("tau_with_friction")
print(state)

# %%
### BEGIN SOLUTION
q, qd, qdd = state["q"], state["qd"], state["qdd"]
c1, c2, s2, c12 = np.cos(q[0]), np.cos(q[1]), np.sin(q[1]), np.cos(q[0] + q[1])
M = np.array([[l2**2 * m2 + 2 * l1 * l2 * m2 * c2 + l1**2 * (m1 + m2), l2**2 * m2 + l1 * l2 * m2 * c2],
              [l2**2 * m2 + l1 * l2 * m2 * c2, l2**2 * m2]])
V = np.array([-m2 * l1 * l2 * s2 * qd[1] ** 2 - 2 * m2 * l1 * l2 * s2 * qd[0] * qd[1], m2 * l1 * l2 * s2 * qd[0] ** 2])
G = np.array([m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1, m2 * l2 * g * c12])
tau_with_friction = M @ qdd + V + G + state["coulomb"] * np.sign(qd) + state["viscous"] * qd
### END SOLUTION

# %%
check("tau_with_friction")

# %% [markdown]
# **Other effects** the rigid-body model leaves out, which the notes mention only in passing: joint flexibility,
# gear backlash, motor dynamics and the torque needed to accelerate the motor's own rotor (its *armature*
# inertia, which adds to M's diagonal through the gear ratio squared).
