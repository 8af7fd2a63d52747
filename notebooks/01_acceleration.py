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
import sympy
from scipy.spatial.transform import Rotation

from course_dynamics.teaching.exercises import check, given, hint, my_robot

# %% [markdown]
# ## Linear acceleration
#
# The acceleration of a point is the time derivative of its velocity,
# $${}^B\dot V_Q = \frac{d}{dt}\,{}^BV_Q = \lim_{\Delta t\to 0}\frac{{}^BV_Q(t+\Delta t) - {}^BV_Q(t)}{\Delta t} \qquad (6.1)$$
# and, likewise, ${}^A\dot\Omega_B = \frac{d}{dt}{}^A\Omega_B$ (6.2) (the notes write it for an ᴬΩ_Q, "ω_Q in frame
# {B}", where the angular velocity of the frame {B} itself is meant). When {B} moves relative to {A}, Q's velocity
# has a part from Q moving in {B} and a part from {B} turning, ${}^AV_Q = {}^A_BR\,{}^BV_Q + {}^A\Omega_B \times
# {}^A_BR\,{}^BQ$ (6.5). Differentiating it once more, every product is differentiated factor by factor, and a
# vector carried by the turning rotation ${}^A_BR$ changes at ${}^A\Omega_B\times$ (that vector):
# $${}^A\dot V_Q = \frac{d}{dt}({}^A_BR\,{}^BV_Q) + {}^A\dot\Omega_B\times{}^A_BR\,{}^BQ
#   + {}^A\Omega_B\times\frac{d}{dt}({}^A_BR\,{}^BQ) \qquad (6.7)$$
# Collecting the terms of (6.7)–(6.8), with the acceleration of {B}'s origin added, is (6.10) — exercise 1.3 asks
# you to do it (the lecture notes print one term too many there; notebook 9 shows it). For a point fixed in {B},
# ${}^BV_Q = {}^B\dot V_Q = 0$, and what remains is (6.12): a tangential term in ${}^A\dot\Omega_B$ and a
# centripetal term in ${}^A\Omega_B$ twice (exercise 1.1).
#
# A moving frame to try it on: {B} turns about a fixed oblique axis $\hat k$ by $\theta(t) = 0.7t + 0.4t^2$ while
# its origin follows a curve; Q is fixed in {B}. Its acceleration, by exact differentiation of ᴬP_Q(t) (sympy),
# is what (6.12) must give and what finite differences approach.

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
P = R @ Q_in_B                                                   # ᴬ_BR ᴮQ, m

s = sympy.Symbol("t")
k = sympy.Matrix([1, 2, 2]) / 3
K = sympy.Matrix([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
angle = sympy.Rational(7, 10) * s + sympy.Rational(2, 5) * s**2
R_of_t = sympy.eye(3) + sympy.sin(angle) * K + (1 - sympy.cos(angle)) * K * K   # Rodrigues' formula
P_of_t = sympy.Matrix([s / 2, sympy.sin(2 * s) / 5, s**2 / 10]) + R_of_t * sympy.Matrix(Q_in_B)
exact = np.array(P_of_t.diff(s, 2).subs(s, t0).evalf(20), dtype=float).ravel()    # ᴬV̇_Q, m/s²
h = 1e-4
by_differences = (position(t0 + h) - 2 * position(t0) + position(t0 - h)) / h**2
print("exact differentiation:  ", exact.round(6), "m/s²")
print("finite differences:     ", by_differences.round(6), "m/s²")

# %% [markdown]
# How close the finite difference comes depends on its step: the truncation error falls as h², until round-off,
# which grows as 1/h², takes over. The exact value is the limit the differences approach.

# %%
steps = np.logspace(-6, -0.5, 40)
errors = [np.abs((position(t0 + d) - 2 * position(t0) + position(t0 - d)) / d**2 - exact).max() for d in steps]
figure, ax = plt.subplots(figsize=(6.5, 3.6))
ax.loglog(steps, errors, "o-", markersize=3)
ax.set_xlabel("finite-difference step h (s)")
ax.set_ylabel("|difference − exact| (m/s²)")
ax.set_title("Central differences converge to the exact ᴬV̇_Q, then round-off takes over")
ax.grid(alpha=0.3, which="both")
plt.show()

# %% [markdown]
# ### Exercise 1.1 — the acceleration of a point fixed in a moving frame
# Write (6.12) as a function, for the instant when the axes of {B} and {A} are aligned (${}^A_BR = 1$):
# `point_acceleration(v_dot, omega_dot, omega, P)` returns the acceleration of the point Q (m/s²) from the
# acceleration `v_dot` of {B}'s origin, {B}'s angular acceleration `omega_dot` and angular velocity `omega`, and
# Q's position `P` relative to that origin — all 3-vectors (numpy arrays). `np.cross` computes a cross product;
# `hint("point_acceleration", 1)` and on help if you are stuck. The check runs your function on your own robot
# (`my_robot("spatial_arm")`, notebook 3's arm): each link's frame at states of yours, Q its centre of mass, where
# (6.12) gives the link's ⁱv̇_Cᵢ.

# %%
def point_acceleration(v_dot, omega_dot, omega, P):
    ### BEGIN SOLUTION
    return v_dot + np.cross(omega_dot, P) + np.cross(omega, np.cross(omega, P))
    ### END SOLUTION


# %%
check("point_acceleration")

# %% [markdown]
# Your function on the moving frame above (with ᴬ_BR ᴮQ as P, its axes are {A}'s): it should print the exact value.

# %%
print("your (6.12):", point_acceleration(origin_acceleration, Omega_dot, Omega, P), " exact:", exact.round(6))

# %% [markdown]
# ## Angular acceleration
#
# Angular velocities add when frames are chained: ${}^A\Omega_C = {}^A\Omega_B + {}^A_BR\,{}^B\Omega_C$ (6.13).
# Differentiating (6.13) gives the rule for angular accelerations, (6.15). Its first term is plain; in the second,
# both ᴮΩ_C and the rotation ᴬ_BR change with time, and a rotation turning at ᴬΩ_B changes a vector it carries at
# the rate ${}^A\Omega_B\times$ (that vector). (6.15) is (6.32) of the recursion in disguise: {C} is link i+1
# turning about its joint axis relative to link i.
#
# ### Exercise 1.2 — adding angular accelerations
# `given("omega_dot_C")` holds ᴬΩ_B, ᴬΩ̇_B, ᴬ_BR, ᴮΩ_C and ᴮΩ̇_C (rad/s, rad/s²). Differentiate (6.13) to find
# (6.15), then compute ᴬΩ̇_C as `omega_dot_C` (a numpy array of 3 numbers, rad/s²).

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
# ### Exercise 1.3 — a point that moves in a moving frame
# Carry out the differentiation of (6.7) (the notes' (6.8) is its next line) and collect the terms into (6.10), as
# a function `moving_point(Vd_org, R, Omega, Omega_dot, Q, V_Q, Vd_Q)` returning ᴬV̇_Q (m/s²): `Vd_org` is
# ᴬV̇_BORG, `R` is ᴬ_BR, `Omega` and `Omega_dot` are ᴬΩ_B and ᴬΩ̇_B, and `Q`, `V_Q`, `Vd_Q` are ᴮQ, ᴮV_Q and
# ᴮV̇_Q — numpy arrays (R 3 × 3, the others 3 numbers). Count how often a term in both Ω and V_Q appears: the
# check knows the notes' version. It runs your function on your own spatial arm: {A} its base, {B} one of its
# links at a state of yours, Q a point moving in that link.

# %%
def moving_point(Vd_org, R, Omega, Omega_dot, Q, V_Q, Vd_Q):
    ### BEGIN SOLUTION
    return (Vd_org + R @ Vd_Q + 2 * np.cross(Omega, R @ V_Q) + np.cross(Omega_dot, R @ Q)
            + np.cross(Omega, np.cross(Omega, R @ Q)))
    ### END SOLUTION


# %%
check("moving_point")

# %% [markdown]
# **Going further.** Set $\theta(t)$ to a constant and see the tangential term vanish; make the axis turn and see
# (6.15)'s cross term appear. The same checks, for every link of a robot, are what notebook 3 runs.
