# %% [markdown]
# # 3. Newton's and Euler's equations, and the iterative Newton–Euler algorithm
#
# **What this notebook teaches.** The two equations that govern one rigid body — Newton's for its centre of mass
# and Euler's for its rotation (6.37) — and how Craig chains them along a manipulator: an *outward* iteration that
# carries velocities and accelerations from the base to the tip (6.45)–(6.50), and an *inward* iteration that
# carries forces and moments back (6.51)–(6.53). The two-link arm of section 6.7 is traced link by link. You then
# write the algorithm yourself, for a planar arm and for a spatial one whose axes are skewed and whose links have
# products of inertia, and the checks compare every quantity of both iterations link by link.
#
# **Notation** (Craig, every vector in the frame of its link): ⁱωᵢ, ⁱω̇ᵢ angular velocity and acceleration of link
# i; ⁱv̇ᵢ the acceleration of the origin of frame i; ⁱv̇_Cᵢ of its centre of mass at ⁱP_Cᵢ; ⁱFᵢ, ⁱNᵢ the inertial
# force and moment at the centre of mass; ⁱfᵢ, ⁱnᵢ the force and moment link i−1 exerts on link i; τᵢ the joint
# torque; ⁱ⁺¹ᵢR the rotation that maps vectors of frame i into frame i+1; ⁱPᵢ₊₁ the origin of frame i+1 in frame i.

# %%
import numpy as np
import matplotlib.pyplot as plt

from course_dynamics.core import inertia
from course_dynamics import inverse_dynamics, gravity_torques, load_robot
from course_dynamics.teaching.exercises import check, given, hint, my_robot
from course_dynamics.output.render import trace_table
from course_dynamics.core.sampling import smooth_trajectory
from course_dynamics.tools.trace import trace

# %% [markdown]
# ## One body
#
# At the centre of mass, with ᶜI the inertia tensor about it,
# $$F = m\,\dot v_C,\qquad N = {}^CI\,\dot\omega + \omega\times{}^CI\,\omega \qquad (6.37)$$
# The second term of Euler's equation is gyroscopic: a body spinning steadily (ω̇ = 0) about an axis that is
# not principal still needs a moment to keep spinning that way. For a 0.3 × 0.5 × 0.1 m box turning at 2 rad/s
# about a diagonal:

# %%
I_c = inertia.box(2.0, 0.3, 0.5, 0.1)           # kg·m², about the centre of mass
omega = 2.0 * np.array([1.0, 1.0, 0.0]) / np.sqrt(2)   # rad/s
print("N =", (I_c @ np.zeros(3) + np.cross(omega, I_c @ omega)).round(5), "N·m, with ω̇ = 0")

# %% [markdown]
# ## The iterations
#
# **Outward, i = 0 … n−1** (for a revolute joint i+1; the base starts with ⁰ω₀ = ⁰ω̇₀ = 0 and ⁰v̇₀ = −g, so that
# gravity loads every link without appearing anywhere else):
# $$\begin{aligned}
# {}^{i+1}\omega_{i+1} &= {}^{i+1}_iR\,{}^i\omega_i + \dot\theta_{i+1}\,{}^{i+1}\hat Z_{i+1} && (6.45)\\
# {}^{i+1}\dot\omega_{i+1} &= {}^{i+1}_iR\,{}^i\dot\omega_i + {}^{i+1}_iR\,{}^i\omega_i\times\dot\theta_{i+1}\,{}^{i+1}\hat Z_{i+1} + \ddot\theta_{i+1}\,{}^{i+1}\hat Z_{i+1} && (6.46)\\
# {}^{i+1}\dot v_{i+1} &= {}^{i+1}_iR\,[{}^i\dot\omega_i\times{}^iP_{i+1} + {}^i\omega_i\times({}^i\omega_i\times{}^iP_{i+1}) + {}^i\dot v_i] && (6.47)\\
# {}^{i+1}\dot v_{C_{i+1}} &= {}^{i+1}\dot\omega_{i+1}\times{}^{i+1}P_{C_{i+1}} + {}^{i+1}\omega_{i+1}\times({}^{i+1}\omega_{i+1}\times{}^{i+1}P_{C_{i+1}}) + {}^{i+1}\dot v_{i+1} && (6.48)\\
# {}^{i+1}F_{i+1} &= m_{i+1}\,{}^{i+1}\dot v_{C_{i+1}} && (6.49)\\
# {}^{i+1}N_{i+1} &= {}^{C_{i+1}}I_{i+1}\,{}^{i+1}\dot\omega_{i+1} + {}^{i+1}\omega_{i+1}\times{}^{C_{i+1}}I_{i+1}\,{}^{i+1}\omega_{i+1} && (6.50)
# \end{aligned}$$
# **Inward, i = n … 1** (with f and n beyond the tip zero, or the load the tip carries):
# $$\begin{aligned}
# {}^if_i &= {}^i_{i+1}R\,{}^{i+1}f_{i+1} + {}^iF_i && (6.51)\\
# {}^in_i &= {}^iN_i + {}^i_{i+1}R\,{}^{i+1}n_{i+1} + {}^iP_{C_i}\times{}^iF_i + {}^iP_{i+1}\times{}^i_{i+1}R\,{}^{i+1}f_{i+1} && (6.52)\\
# \tau_i &= {}^in_i^T\,{}^i\hat Z_i && (6.53)
# \end{aligned}$$
# The lecture notes print several of these with the rotation inverted or the wrong link's quantities; the lines
# above are the corrected ones (notebook 9 shows each misprint numerically). In words, (6.53) takes the Ẑ component
# of ⁱnᵢ, the moment the parent exerts on link i — not of the inertial moment ⁱNᵢ, as the notes' sentence reads.
#
# ## The two-link arm of section 6.7, link by link
#
# Point masses m₁ = 2 kg and m₂ = 1 kg at the ends of links of l₁ = 0.5 m and l₂ = 0.4 m, gravity along −Y₀.
# `trace` runs both iterations once and keeps every intermediate vector (each checked against Pinocchio's own
# per-link data in the tests):

# %%
arm = load_robot("two_link")
print(trace_table(trace(arm, [0.3, -0.8], [1.1, 0.6], [-0.4, 0.9])))

# %% [markdown]
# The same iterations run on symbols too (`trace(arm, None, None, None, symbols=...)`); notebook 4 shows what they
# give once you have collected the closed form yourself.

# %% [markdown]
# ## Torques along a motion
#
# Along a smooth motion, the torque splits into the part that holds the arm against gravity, G(Θ), and the part
# that accelerates it. The gravity part dominates slow motions of heavy arms.

# %%
t, q, qd, qdd = smooth_trajectory(arm, duration=4.0)
tau, G = inverse_dynamics(arm, q, qd, qdd), gravity_torques(arm, q)
figure, ax = plt.subplots(figsize=(7, 3.8))
for j, name in enumerate(arm.joint_names):
    line, = ax.plot(t, tau[:, j], label=f"τ of {name}")
    ax.plot(t, G[:, j], "--", color=line.get_color(), label=f"G of {name} (gravity alone)")
ax.set_xlabel("t (s)")
ax.set_ylabel("joint torque (N·m)")
ax.set_title("Two-link arm: inverse dynamics along a smooth motion")
ax.legend(fontsize="small", ncol=2)
ax.grid(alpha=0.3)
plt.show()

# %% [markdown]
# ## Your exercises: your own arms
#
# Your exercises use your own arms, not the section's: the same joints and frames, with lengths, masses and
# inertias of their own. Their numbers are below (`my_robot(...).parameters` gives them by name, m1, l1, lc1, …,
# and `my_robot(...).model` the model itself); the worked examples above keep the section's numbers.

# %%
print(my_robot("two_link").describe())
print(my_robot("spatial_arm").describe())

# %% [markdown]
# ### Exercise 3.1 — the algorithm, by hand
# Write `tau_two_link(q, qd, qdd)`: the joint torques of your two-link arm by the outward and inward iterations,
# for Θ, Θ̇, Θ̈ given as numpy arrays of 2 numbers (rad, rad/s, rad/s²). Frame i turns about its Ẑ by θᵢ, so
# ⁱ⁻¹ᵢR = Rot_z(θᵢ); joint 2 sits at ¹P₂ = (l₁, 0, 0) and link i's centre of mass at ⁱP_Cᵢ = (lcᵢ, 0, 0); the
# masses are points (ᶜI = 0); gravity g acts along −Y₀. Take mᵢ, lᵢ, lcᵢ and g from
# `my_robot("two_link").parameters`. The check grades it as the course's grader does and names what is wrong.

# %%
def tau_two_link(q, qd, qdd):
    ### BEGIN SOLUTION
    p = my_robot("two_link").parameters
    m, l, l_c, g = [p["m1"], p["m2"]], [p["l1"], p["l2"]], [p["lc1"], p["lc2"]], p["g"]
    z = np.array([0.0, 0.0, 1.0])

    def rot_z(angle):
        c, s = np.cos(angle), np.sin(angle)
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

    R = [rot_z(q[0]), rot_z(q[1])]                      # frame i in frame i−1
    P = [np.zeros(3), np.array([l[0], 0.0, 0.0])]         # origin of frame i in frame i−1
    w, w_dot, v_dot = np.zeros(3), np.zeros(3), np.array([0.0, g, 0.0])
    F = []
    for i in range(2):                                  # outward (6.45)–(6.49)
        Rt = R[i].T
        v_dot = Rt @ (np.cross(w_dot, P[i]) + np.cross(w, np.cross(w, P[i])) + v_dot)
        w_dot = Rt @ w_dot + np.cross(Rt @ w, qd[i] * z) + qdd[i] * z
        w = Rt @ w + qd[i] * z
        P_c = np.array([l_c[i], 0.0, 0.0])
        F.append(m[i] * (np.cross(w_dot, P_c) + np.cross(w, np.cross(w, P_c)) + v_dot))
    f, n, tau = np.zeros(3), np.zeros(3), np.zeros(2)
    for i in (1, 0):                                    # inward (6.51)–(6.53); N = 0 for point masses
        R_next = R[1] if i == 0 else np.eye(3)
        P_next = P[1] if i == 0 else np.zeros(3)
        n = R_next @ n + np.cross(np.array([l_c[i], 0.0, 0.0]), F[i]) + np.cross(P_next, R_next @ f)
        f = R_next @ f + F[i]
        tau[i] = n @ z
    return tau
    ### END SOLUTION


# %%
check("tau_two_link")

# %% [markdown]
# ### Exercise 3.2 — one step by hand
# At the state `given("v_dot_c1")` (your own), compute ¹v̇_C₁, the acceleration of your link 1's centre of mass in
# frame 1, as `v_dot_c1` (3 numbers, m/s²): first ¹v̇₁ by (6.47) from the base's ⁰v̇₀ = −g, then (6.48). Work it
# out on paper first; `hint("v_dot_c1", 1)`, `2` and `3` help, the last with the formula. (The lecture notes'
# worked example misprints this step — the rotation of ¹v̇₁ and one entry of ¹v̇_C₁ — and later ¹F₁, ¹N₁ and ²v̇₂:
# derive it rather than copy it; notebook 9 shows each.)

# %%
state = given("v_dot_c1")
print(state)

# %%
### BEGIN SOLUTION
mine = my_robot("two_link").parameters
s1, c1 = np.sin(state["q"][0]), np.cos(state["q"][0])
v_dot_c1 = np.array([-mine["lc1"] * state["qd"][0] ** 2 + mine["g"] * s1,
                     mine["lc1"] * state["qdd"][0] + mine["g"] * c1, 0.0])
### END SOLUTION

# %%
check("v_dot_c1")

# %% [markdown]
# ### Exercise 3.3 — both iterations on a spatial arm, link by link
# Your spatial arm (`robots/spatial_arm.urdf`, its numbers printed above) has three revolute joints, each about the
# Ẑ of its own frame, but the frames are skewed against each other and the links have products of inertia, so every
# term of (6.45)–(6.53) counts. In its model, `my_robot("spatial_arm").model`, link i (numbered from 0 in
# Python) is `model.bodies[i]`, and for that `body`:
#
# * `body.R0 @ Rot_z(θᵢ)`, the orientation ⁱ⁻¹ᵢR of frame i in its parent (so ⁱᵢ₋₁R is its transpose);
# * `body.P`, the origin ⁱ⁻¹Pᵢ of frame i in its parent;
# * `body.p_com`, `body.I_com` and `body.mass`: ⁱP_Cᵢ, ᶜⁱIᵢ (about the centre of mass, in frame i) and mᵢ;
# * `model.gravity`, the vector g in the base frame: the base starts with ⁰v̇₀ = −g.
#
# Write `links_spatial_arm(q, qd, qdd)` (Θ, Θ̇, Θ̈ as arrays of 3) returning a dict with the keys `omega`,
# `omega_dot`, `v_dot`, `v_dot_c`, `F`, `N`, `f`, `n` and `tau`: each a list with one entry per link, in order —
# a 3-vector in the link's own frame (ⁱωᵢ, ⁱω̇ᵢ, ⁱv̇ᵢ, ⁱv̇_Cᵢ, ⁱFᵢ, ⁱNᵢ, ⁱfᵢ, ⁱnᵢ) — and for `tau` one number per
# joint. The check runs it at your state `given("links_spatial_arm")`, compares the quantities in the order the
# iterations compute them, names the first one that is wrong and for which links, and, if one of the usual slips
# (a rotation transposed, a cross product reversed, a term left out, …) explains it, names that slip.

# %%
def links_spatial_arm(q, qd, qdd):
    ### BEGIN SOLUTION
    model = my_robot("spatial_arm").model
    bodies, z = model.bodies, np.array([0.0, 0.0, 1.0])

    def rot_z(angle):
        c, s = np.cos(angle), np.sin(angle)
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

    R = [body.R0 @ rot_z(q[i]) for i, body in enumerate(bodies)]     # frame i in its parent
    w, w_dot, v_dot = np.zeros(3), np.zeros(3), -model.gravity         # the base: ⁰v̇₀ = −g
    out = {key: [] for key in ("omega", "omega_dot", "v_dot", "v_dot_c", "F", "N", "f", "n", "tau")}
    for i, body in enumerate(bodies):                                  # outward (6.45)–(6.50)
        Rt = R[i].T
        v_dot = Rt @ (np.cross(w_dot, body.P) + np.cross(w, np.cross(w, body.P)) + v_dot)
        w_dot = Rt @ w_dot + np.cross(Rt @ w, qd[i] * z) + qdd[i] * z
        w = Rt @ w + qd[i] * z
        v_dot_c = np.cross(w_dot, body.p_com) + np.cross(w, np.cross(w, body.p_com)) + v_dot
        for key, value in (("omega", w), ("omega_dot", w_dot), ("v_dot", v_dot), ("v_dot_c", v_dot_c),
                           ("F", body.mass * v_dot_c), ("N", body.I_com @ w_dot + np.cross(w, body.I_com @ w))):
            out[key].append(value)
    f, n = np.zeros(3), np.zeros(3)
    for i in reversed(range(len(bodies))):                             # inward (6.51)–(6.53)
        R_next = R[i + 1] if i + 1 < len(bodies) else np.eye(3)
        P_next = bodies[i + 1].P if i + 1 < len(bodies) else np.zeros(3)
        n = out["N"][i] + R_next @ n + np.cross(bodies[i].p_com, out["F"][i]) + np.cross(P_next, R_next @ f)
        f = R_next @ f + out["F"][i]
        out["f"].insert(0, f)
        out["n"].insert(0, n)
        out["tau"].insert(0, n @ z)
    return out
    ### END SOLUTION


# %%
check("links_spatial_arm")

# %% [markdown]
# ### Exercise 3.4 — the torques of the spatial arm
# Write `tau_spatial_arm(q, qd, qdd)`: the three joint torques (N·m) of your spatial arm, for Θ, Θ̇, Θ̈ as arrays
# of 3. This check grades it as the course's grader grades a submission: on random states of your arm, with its
# diagnosis of what is wrong. (Your function of exercise 3.3 may do the work.)

# %%
def tau_spatial_arm(q, qd, qdd):
    ### BEGIN SOLUTION
    return np.array(links_spatial_arm(q, qd, qdd)["tau"], dtype=float)
    ### END SOLUTION


# %%
check("tau_spatial_arm")

# %% [markdown]
# ## Where the iterations come from: the notes' homework
#
# Each line of the outward iteration is an acceleration rule of notebook 1 applied to two neighbouring links, and
# each line of the inward one a force or moment balance. Derive them yourself; each check runs your function on
# your own spatial arm, `my_robot("spatial_arm")` — the rotations, vectors and rates of its links, one joint at a
# time, at states of yours — and names a slip it recognises. Below, `R` is always a 3 × 3 rotation
# matrix, vectors are numpy arrays of 3 numbers, and the joint axis is Ẑ = (0, 0, 1) of the frame it belongs to.
#
# ### Exercise 3.5 — (6.32) from (6.15) and (5.45)
# Link i+1 turns relative to link i by θ̇ᵢ₊₁ about its Ẑ, so ⁱ⁺¹ωᵢ₊₁ = ⁱ⁺¹ᵢR ⁱωᵢ + θ̇ᵢ₊₁Ẑ (the velocity
# propagation of (5.45)). Differentiate it with the rule (6.15) — {A} the base {0} (an inertial frame), {B} link i,
# {C} link i+1, which turns relative to {B} by the joint's rotation — then write the result in frame i+1's axes, and
# write `omega_dot_propagation(R, w, wd, qd, qdd)` returning ⁱ⁺¹ω̇ᵢ₊₁, with R = ⁱ⁺¹ᵢR,
# w = ⁱωᵢ, wd = ⁱω̇ᵢ, qd = θ̇ᵢ₊₁, qdd = θ̈ᵢ₊₁ (numbers). The notes' "from (5.45)" line is misprinted (notebook 9).

# %%
def omega_dot_propagation(R, w, wd, qd, qdd):
    ### BEGIN SOLUTION
    z = np.array([0.0, 0.0, 1.0])
    return R @ wd + np.cross(R @ w, qd * z) + qdd * z
    ### END SOLUTION


# %%
check("omega_dot_propagation")

# %% [markdown]
# ### Exercise 3.6 — (6.34) from (6.12)
# (The notes restate (6.5) on the way with ᴮV̇_Q where the velocity ᴮV_Q belongs; for a point fixed in link i both
# vanish, and (6.12) is all that is needed.)
# The origin of frame i+1 is a point fixed in link i, at ⁱPᵢ₊₁. Apply (6.12) with {A} the base and {B} link i, in
# frame i's axes, and rotate the result into frame i+1: `v_dot_propagation(R, w, wd, vd, P)` returns ⁱ⁺¹v̇ᵢ₊₁ from R = ⁱ⁺¹ᵢR, w = ⁱωᵢ, wd = ⁱω̇ᵢ,
# vd = ⁱv̇ᵢ and P = ⁱPᵢ₊₁.

# %%
def v_dot_propagation(R, w, wd, vd, P):
    ### BEGIN SOLUTION
    return R @ (np.cross(wd, P) + np.cross(w, np.cross(w, P)) + vd)
    ### END SOLUTION


# %%
check("v_dot_propagation")

# %% [markdown]
# ### Exercise 3.7 — (6.36), the centre of mass
# Trace (6.12) once more, for link i's centre of mass at ⁱP_Cᵢ, everything in frame i:
# `v_dot_com(w, wd, vd, P_c)` returns ⁱv̇_Cᵢ from w = ⁱωᵢ, wd = ⁱω̇ᵢ, vd = ⁱv̇ᵢ and P_c = ⁱP_Cᵢ.

# %%
def v_dot_com(w, wd, vd, P_c):
    ### BEGIN SOLUTION
    return np.cross(wd, P_c) + np.cross(w, np.cross(w, P_c)) + vd
    ### END SOLUTION


# %%
check("v_dot_com")

# %% [markdown]
# ### Exercise 3.8 — (6.42) from (6.38) and (6.39)
# Balance the moments on link i about the origin of frame i ((6.38) for the forces, (6.39) for the moments about
# the centre of mass), with ⁱPᵢ = 0, and solve for ⁱnᵢ: `inward_moment(R, N, n_next, P_c, F, P_next, f_next)`
# with R = ⁱᵢ₊₁R (from frame i+1 into frame i), N = ⁱNᵢ, n_next = ⁱ⁺¹nᵢ₊₁, P_c = ⁱP_Cᵢ, F = ⁱFᵢ,
# P_next = ⁱPᵢ₊₁ and f_next = ⁱ⁺¹fᵢ₊₁.

# %%
def inward_moment(R, N, n_next, P_c, F, P_next, f_next):
    ### BEGIN SOLUTION
    return N + R @ n_next + np.cross(P_c, F) + np.cross(P_next, R @ f_next)
    ### END SOLUTION


# %%
check("inward_moment")

# %% [markdown]
# ### Exercise 3.9 — a prismatic joint, (6.35) and (6.44)
# When joint i+1 slides by dᵢ₊₁ along its Ẑ, link i+1 turns with link i (ⁱ⁺¹ωᵢ₊₁ = ⁱ⁺¹ᵢR ⁱωᵢ), and its origin is
# a point *moving* in link i: (6.10) adds two terms to (6.34). Write `prismatic_joint(R, w, wd, vd, P, d_dot,
# d_ddot, f)` returning the pair (ⁱ⁺¹v̇ᵢ₊₁, τᵢ₊₁): the acceleration of frame i+1's origin, and the joint's force
# from f = ⁱ⁺¹fᵢ₊₁ (6.44). The check puts a sliding joint, with rates of yours, in place of one of your spatial
# arm's joints.

# %%
def prismatic_joint(R, w, wd, vd, P, d_dot, d_ddot, f):
    ### BEGIN SOLUTION
    z = np.array([0.0, 0.0, 1.0])
    v_dot = R @ (np.cross(wd, P) + np.cross(w, np.cross(w, P)) + vd) + 2 * np.cross(R @ w, d_dot * z) + d_ddot * z
    return v_dot, float(f @ z)
    ### END SOLUTION


# %%
check("prismatic_joint")
