# %% [markdown]
# # 3. Newton's and Euler's equations, and the iterative Newton–Euler algorithm
#
# **What this notebook teaches.** The two equations that govern one rigid body — Newton's for its centre of mass
# and Euler's for its rotation (6.37) — and how Craig chains them along a manipulator: an *outward* iteration that
# carries velocities and accelerations from the base to the tip (6.45)–(6.50), and an *inward* iteration that
# carries forces and moments back (6.51)–(6.53). The two-link arm of section 6.7 is traced link by link, as a table
# and in LaTeX, and its closed form (6.60)–(6.62) is derived symbolically. You then write the algorithm yourself.
#
# **Notation** (Craig, every vector in the frame of its link): ⁱωᵢ, ⁱω̇ᵢ angular velocity and acceleration of link
# i; ⁱv̇ᵢ the acceleration of the origin of frame i; ⁱv̇_Cᵢ of its centre of mass at ⁱP_Cᵢ; ⁱFᵢ, ⁱNᵢ the inertial
# force and moment at the centre of mass; ⁱfᵢ, ⁱnᵢ the force and moment link i−1 exerts on link i; τᵢ the joint
# torque; ⁱ⁺¹ᵢR the rotation that maps vectors of frame i into frame i+1; ⁱPᵢ₊₁ the origin of frame i+1 in frame i.

# %%
import numpy as np
import matplotlib.pyplot as plt
from IPython.display import Markdown, display

from course_dynamics.core import inertia
from course_dynamics import inverse_dynamics, gravity_torques, load_robot
from course_dynamics.teaching.exercises import check, given
from course_dynamics.output.render import derivation_text, trace_latex, trace_table
from course_dynamics.core.sampling import smooth_trajectory
from course_dynamics.core.symbolic import derive
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
# above are the corrected ones (notebook 9 shows each misprint numerically).
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
# The same iterations on symbols reproduce the notes' hand derivation (corrected):

# %%
symbolic = trace(arm, None, None, None, symbols=("m1", "m2", "l1", "l2", "g"))
display(Markdown("$$" + trace_latex(symbolic).replace("% Newton-Euler iterations of two_link\n", "") + "$$"))

# %% [markdown]
# and collecting τ by Θ̈, Θ̇ and g gives the closed form (6.60)–(6.62):

# %%
display(Markdown(derivation_text(derive(arm, ("m1", "m2", "l1", "l2", "g")), "markdown")))

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
# ### Exercise 3.1 — the algorithm, by hand
# Write `tau_two_link(q, qd, qdd)`: the joint torques of the two-link arm by the outward and inward iterations,
# for Θ, Θ̇, Θ̈ given as numpy arrays of 2 numbers (rad, rad/s, rad/s²). Frame i turns about its Ẑ by θᵢ, so
# ⁱ⁻¹ᵢR = Rot_z(θᵢ); ¹P₂ = (l₁, 0, 0); ⁱP_Cᵢ = (lᵢ, 0, 0); the masses are points (ᶜI = 0); gravity
# g = 9.81 m/s² along −Y₀. The check grades it as the course's grader does and names what is wrong.

# %%
def tau_two_link(q, qd, qdd):
    ### BEGIN SOLUTION
    m, l, g = [2.0, 1.0], [0.5, 0.4], 9.81
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
        P_c = np.array([l[i], 0.0, 0.0])
        F.append(m[i] * (np.cross(w_dot, P_c) + np.cross(w, np.cross(w, P_c)) + v_dot))
    f, n, tau = np.zeros(3), np.zeros(3), np.zeros(2)
    for i in (1, 0):                                    # inward (6.51)–(6.53); N = 0 for point masses
        R_next = R[1] if i == 0 else np.eye(3)
        P_next = P[1] if i == 0 else np.zeros(3)
        n = R_next @ n + np.cross(np.array([l[i], 0.0, 0.0]), F[i]) + np.cross(P_next, R_next @ f)
        f = R_next @ f + F[i]
        tau[i] = n @ z
    return tau
    ### END SOLUTION


# %%
check("tau_two_link")

# %% [markdown]
# ### Exercise 3.2 — one step by hand
# At the state `given("v_dot_c1")`, compute ¹v̇_C₁, the acceleration of link 1's centre of mass in frame 1 (6.48),
# as `v_dot_c1` (3 numbers, m/s²). With ¹v̇₁ = ¹₀R (0, g, 0) = (g s₁, g c₁, 0) it is
# (−l₁θ̇₁² + g s₁, l₁θ̈₁ + g c₁, 0) — the notes print g s₁ in the second entry.

# %%
state = given("v_dot_c1")
print(state)

# %%
### BEGIN SOLUTION
s1, c1 = np.sin(state["q"][0]), np.cos(state["q"][0])
v_dot_c1 = np.array([-0.5 * state["qd"][0] ** 2 + 9.81 * s1, 0.5 * state["qdd"][0] + 9.81 * c1, 0.0])
### END SOLUTION

# %%
check("v_dot_c1")
