# %% [markdown]
# # 1. Acceleration of a rigid body
#
# **What this notebook teaches.** How the linear and angular accelerations of a moving body are defined (6.1),
# (6.2); the acceleration of a point seen from a moving frame (6.10), and of a point fixed in that frame (6.12);
# how angular accelerations add up from frame to frame (6.15). These are the two facts the Newton–Euler
# recursion of notebook 3 is built from. Each formula is checked against finite differences of a moving frame,
# so you can see it is right rather than take it on trust.
#
# **Notation** (Craig): ᴬP_Q is the position of point Q in frame {A}; ᴬV_Q its velocity, ᴬV̇_Q its
# acceleration; ᴬ_BR the orientation of frame {B} in {A}; ᴬΩ_B the angular velocity of {B} relative to {A}
# and ᴬΩ̇_B its derivative; ᴬV_BORG the velocity of the origin of {B}. A dot is a time derivative.

# %%
import numpy as np
import matplotlib.pyplot as plt
from scipy.spatial.transform import Rotation

from course_dynamics.core.algebra import Vec3, point_acceleration as library_point_acceleration
from course_dynamics.teaching.exercises import check, given

# %% [markdown]
# ## Linear acceleration
#
# The acceleration of a point is the time derivative of its velocity,
# $${}^B\dot V_Q = \frac{d}{dt}\,{}^BV_Q = \lim_{\Delta t\to 0}\frac{{}^BV_Q(t+\Delta t) - {}^BV_Q(t)}{\Delta t} \qquad (6.1)$$
# and, likewise, ${}^A\dot\Omega_B = \frac{d}{dt}{}^A\Omega_B$ (6.2). When {B} moves relative to {A}, differentiating
# ${}^AV_Q = {}^A_BR\,{}^BV_Q + {}^A\Omega_B \times {}^A_BR\,{}^BQ$ (6.5) once more gives
# $${}^A\dot V_Q = {}^A\dot V_{BORG} + {}^A_BR\,{}^B\dot V_Q + 2\,{}^A\Omega_B\times{}^A_BR\,{}^BV_Q
#   + {}^A\dot\Omega_B\times{}^A_BR\,{}^BQ + {}^A\Omega_B\times({}^A\Omega_B\times{}^A_BR\,{}^BQ) \qquad (6.10)$$
# (the lecture notes print the Coriolis term $2\,\Omega\times V$ once more than it belongs; notebook 9 shows it).
# For a point fixed in {B}, ${}^BV_Q = {}^B\dot V_Q = 0$ and
# $${}^A\dot V_Q = {}^A\dot V_{BORG} + {}^A\dot\Omega_B\times{}^A_BR\,{}^BQ + {}^A\Omega_B\times({}^A\Omega_B\times{}^A_BR\,{}^BQ) \qquad (6.12)$$
# — the tangential term $\dot\Omega\times P$ and the centripetal term $\Omega\times(\Omega\times P)$.
#
# A moving frame to test it on: {B} turns about a fixed oblique axis $\hat k$ by $\theta(t) = 0.7t + 0.4t^2$ while
# its origin follows a curve; Q is fixed in {B}.

# %%
axis = np.array([1.0, 2.0, 2.0]) / 3.0             # unit axis of rotation in {A}
Q_in_B = np.array([0.4, -0.2, 0.3])                 # ᴮQ, m, fixed in {B}


def theta(t):
    return 0.7 * t + 0.4 * t**2                     # rad


def origin(t):                                      # ᴬP_BORG(t), m
    return np.array([0.5 * t, 0.2 * np.sin(2 * t), 0.1 * t**2])


def position(t):                                    # ᴬP_Q(t) = ᴬP_BORG + ᴬ_BR ᴮQ, m
    return origin(t) + Rotation.from_rotvec(axis * theta(t)).as_matrix() @ Q_in_B


t0 = 1.3
R = Rotation.from_rotvec(axis * theta(t0)).as_matrix()
Omega, Omega_dot = axis * (0.7 + 0.8 * t0), axis * 0.8          # ᴬΩ_B (rad/s), ᴬΩ̇_B (rad/s²)
origin_acceleration = np.array([0.0, -0.8 * np.sin(2 * t0), 0.2])  # ᴬV̇_BORG, m/s²
P = R @ Q_in_B
by_6_12 = np.array(tuple(library_point_acceleration(*(Vec3.of(x) for x in (origin_acceleration, Omega_dot, Omega, P)))))
h = 1e-4
by_differences = (position(t0 + h) - 2 * position(t0) + position(t0 - h)) / h**2
print("(6.12):                 ", by_6_12.round(6), "m/s²")
print("finite differences:     ", by_differences.round(6), "m/s²")

# %% [markdown]
# How close the finite difference comes depends on its step: the truncation error falls as h², until round-off,
# which grows as 1/h², takes over. The formula is the limit the differences approach.

# %%
steps = np.logspace(-6, -0.5, 40)
errors = [np.abs((position(t0 + s) - 2 * position(t0) + position(t0 - s)) / s**2 - by_6_12).max() for s in steps]
figure, ax = plt.subplots(figsize=(6.5, 3.6))
ax.loglog(steps, errors, "o-", markersize=3)
ax.set_xlabel("finite-difference step h (s)")
ax.set_ylabel("|difference − (6.12)| (m/s²)")
ax.set_title("Central differences converge to (6.12), then round-off takes over")
ax.grid(alpha=0.3, which="both")
plt.show()

# %% [markdown]
# ### Exercise 1.1 — the acceleration of a point fixed in a moving frame
# Write (6.12) as a function for the instant when the axes of {B} and {A} are aligned (${}^A_BR = 1$):
# `point_acceleration(v_dot, omega_dot, omega, P)` returns $\dot v + \dot\omega\times P + \omega\times(\omega\times P)$
# for 3-vectors (numpy arrays). Use `np.cross`.

# %%
def point_acceleration(v_dot, omega_dot, omega, P):
    ### BEGIN SOLUTION
    return v_dot + np.cross(omega_dot, P) + np.cross(omega, np.cross(omega, P))
    ### END SOLUTION


# %%
check("point_acceleration")

# %% [markdown]
# ## Angular acceleration
#
# Angular velocities add when frames are chained: ${}^A\Omega_C = {}^A\Omega_B + {}^A_BR\,{}^B\Omega_C$ (6.13).
# Differentiating, the second term's rotation contributes a cross product:
# $${}^A\dot\Omega_C = {}^A\dot\Omega_B + {}^A_BR\,{}^B\dot\Omega_C + {}^A\Omega_B\times{}^A_BR\,{}^B\Omega_C \qquad (6.15)$$
# This is (6.32) of the recursion in disguise: {C} is link i+1 turning about its joint axis relative to link i.
#
# ### Exercise 1.2 — adding angular accelerations
# `given("omega_dot_C")` holds ᴬΩ_B, ᴬΩ̇_B, ᴬ_BR, ᴮΩ_C and ᴮΩ̇_C (rad/s, rad/s²). Compute ᴬΩ̇_C by (6.15)
# as `omega_dot_C` (a numpy array of 3 numbers).

# %%
data = given("omega_dot_C")
for key, value in data.items():
    print(key, "=", np.round(value, 4).tolist())

# %%
### BEGIN SOLUTION
omega_dot_C = data["Omega_B_dot"] + data["R_AB"] @ data["Omega_C_dot_in_B"] + np.cross(
    data["Omega_B"], data["R_AB"] @ data["Omega_C_in_B"])
### END SOLUTION

# %%
check("omega_dot_C")

# %% [markdown]
# **Going further.** Set $\theta(t)$ to a constant and see the tangential term vanish; make the axis turn and see
# (6.15)'s cross term appear. The same checks, for every link of a robot, are what notebook 3 runs.
