# %% [markdown]
# # 10. Identification: the parameters a robot really has
#
# **What this notebook teaches.** The torques of every rigid manipulator are *linear* in its inertial parameters,
# τ = Y(Θ, Θ̇, Θ̈) π, because Newton's and Euler's equations are, once written about the link's frame origin
# instead of its centre of mass. That makes the masses, centres of mass and inertias measurable: move the robot,
# record Θ and τ, and solve a least-squares problem. Worked here for the two-link arm of section 6.7 — one column
# of Y by hand, the combinations of parameters that torques can and cannot reveal (the *base parameters*), an
# excitation trajectory that reveals them well, and an identification from a noisy simulated log.
#
# **Notation** (Craig, every vector in the frame of its link, as in notebook 3): for link i, mᵢ its mass, cᵢ = ⁱP_Cᵢ
# its centre of mass, hᵢ = mᵢ cᵢ its first moment (kg·m), ᶜIᵢ its inertia about the centre of mass and I_o,ᵢ about
# the frame origin (kg·m²); ω, ω̇, v̇ the link's angular velocity, angular acceleration and the acceleration of its
# frame origin; π the 10 n parameters, ten per link: m, h_x, h_y, h_z, and the six entries of I_o.

# %%
from dataclasses import replace

import numpy as np
import matplotlib.pyplot as plt
from IPython.display import Markdown, display

from course_dynamics import inverse_dynamics, load_robot, newton_euler_links
from course_dynamics.core.regressor import base_parameters, parameter_names, parameters, regressor
from course_dynamics.teaching.exercises import check, given, hint, my_robot
from course_dynamics.tools.excitation import condition_number, excitation
from course_dynamics.tools.identification import identify
from course_dynamics.tools.logs import JointLog

# %% [markdown]
# ## Newton and Euler about the frame origin
#
# At the centre of mass, F = m v̇_C and N = ᶜI ω̇ + ω × ᶜI ω (6.37), with v̇_C = ω̇ × c + ω × (ω × c) + v̇ (6.36).
# Substituting v̇_C and moving the moment to the frame origin (n = N + c × F) gives, after the parallel-axis theorem
# I_o = ᶜI + m (cᵀc 1 − c cᵀ) collects the terms in c,
# $$f = m\,\dot v + \dot\omega\times h + \omega\times(\omega\times h),\qquad
#   n = I_o\,\dot\omega + \omega\times I_o\,\omega + h\times\dot v,\qquad h = m\,c .$$
# Every term is a parameter (m, h or I_o) times something the motion alone fixes (ω, ω̇ and v̇ come from the
# outward iteration, which never uses a mass). The inward iteration (6.51)–(6.53), as corrected in notebook 9, only
# rotates, shifts and adds these f and n. So each τᵢ is a linear combination of the parameters.
#
# A check on a two-link arm with real inertias (not the section's point masses). Link 2 is the last link, so the
# force and moment that link 1 exerts on it, ²f₂ and ²n₂, are exactly its own f and n above:

# %%
arm = load_robot("two_link")            # Craig's section 6.7: point masses m1 = 2 kg at l1 = 0.5 m, m2 = 1 kg at 0.4 m
link1, link2 = arm.bodies
solid = replace(arm, bodies=(link1, replace(link2, p_com=[0.35, 0.02, 0.0], I_com=np.diag([0.001, 0.03, 0.03]))))
q, qd, qdd = np.array([0.4, -1.1]), np.array([0.8, -0.5]), np.array([1.5, 0.3])   # rad, rad/s, rad/s²
links = newton_euler_links(solid, q, qd, qdd)
m = solid.bodies[1].mass                                     # kg
c = solid.bodies[1].p_com                                    # m, in frame 2
h = m * c                                                    # kg·m
I_o = solid.bodies[1].I_com + m * (c @ c * np.eye(3) - np.outer(c, c))   # kg·m², about the origin of frame 2
w, w_dot, v_dot = links.omega[1], links.omega_dot[1], links.v_dot[1]
f = m * v_dot + np.cross(w_dot, h) + np.cross(w, np.cross(w, h))
n = I_o @ w_dot + np.cross(w, I_o @ w) + np.cross(h, v_dot)
print("f:", f.round(6), " library ²f₂:", links.f[1].round(6), "N")
print("n:", n.round(6), " library ²n₂:", links.n[1].round(6), "N·m")

# %% [markdown]
# ## The regressor of the two-link arm
# Stacking the parameters of both links into π (20 numbers, in this order):

# %%
names = parameter_names(arm)
print(names)

# %% [markdown]
# τ = Y π with Y a 2 × 20 matrix that depends on the state only. Take the column of h₂,ₓ = `mcx_2` (for the
# section's arm, m₂ l₂). In row 2, τ₂ is the z-component of ²n₂ = I_o ω̇ + ω × I_o ω + h × ²v̇₂. For the planar
# arm ω = (θ̇₁ + θ̇₂) Ẑ, so ω × I_o ω has no z-component, and (h × ²v̇₂)_z = h_x ²v̇₂,y − h_y ²v̇₂,x. The `mcx_2`
# entry of row 2 is therefore ²v̇₂,y: by (6.47) with ¹P₂ = (l₁, 0, 0) and gravity through ⁰v̇₀ = −g, that is
# l₁ c₂ θ̈₁ + l₁ s₂ θ̇₁² + g c₁₂. In the same way the `Izz_2` entry of row 2 is θ̈₁ + θ̈₂. At the state above:

# %%
l1, g = link2.P[0], 9.81                   # m, m/s²: joint 2 sits 0.5 m along link 1
by_hand = [l1 * np.cos(q[1]) * qdd[0] + l1 * np.sin(q[1]) * qd[0] ** 2 + g * np.cos(q[0] + q[1]), qdd[0] + qdd[1]]
Y = regressor(arm, q, qd, qdd)             # (2, 20): N·m per unit of each parameter
print("row 2, columns mcx_2 and Izz_2 by hand:", np.round(by_hand, 6))
print("the same from regressor():             ", Y[1, [names.index("mcx_2"), names.index("Izz_2")]].round(6))
print("Y π equals τ:", np.allclose(Y @ parameters(solid), inverse_dynamics(solid, q, qd, qdd)))

# %% [markdown]
# ## Your exercises: your own arm
# The exercises below use your own two-link arm, not the section's: the same joints and frames, with lengths and
# masses of its own. Its numbers are below (`my_robot("two_link").parameters` gives them by name, l1, g, …).

# %%
print(my_robot("two_link").describe())

# %% [markdown]
# ### Exercise 10.1 — a whole column of Y
# At your state `given("Y_mcx2")`, compute both entries (rows 1 and 2) of the `mcx_2` column of your two-link arm's
# regressor, `Y_mcx2` (2 numbers, N·m per kg·m). Row 1 needs the moment ²n₂ and force ²f₂ carried to joint 1 by
# (6.51)–(6.52); or collect the terms in m₂ l₂ of the closed form (6.60)–(6.62). Take your arm's l₁ and g from
# `my_robot("two_link").parameters`.

# %%
state = given("Y_mcx2")
print(state)

# %%
### BEGIN SOLUTION
mine = my_robot("two_link").parameters
my_l1, my_g = mine["l1"], mine["g"]                                   # m, m/s²
s2, c2, c12 = np.sin(state["q"][1]), np.cos(state["q"][1]), np.cos(state["q"].sum())
(t1_dot, t2_dot), (t1_ddot, t2_ddot) = state["qd"], state["qdd"]
Y_mcx2 = np.array([my_l1 * c2 * (2 * t1_ddot + t2_ddot) - my_l1 * s2 * (t2_dot**2 + 2 * t1_dot * t2_dot)
                   + my_g * c12, my_l1 * c2 * t1_ddot + my_l1 * s2 * t1_dot**2 + my_g * c12])
### END SOLUTION

# %%
check("Y_mcx2")

# %% [markdown]
# ## What the torques cannot tell apart
# Some columns of Y are zero for every motion (m₁: the arm's moments about joint 1 never involve m₁ itself, only
# h₁ and I_o,₁), and some are combinations of others: the mass of link 2 sits at joint 2, which turns about joint
# 1 at distance l₁, so in τ it looks exactly like a piece of link 1. Only the *base parameters* π_b = β π can be
# identified; every π with the same π_b gives the same torques along every motion.
#
# ### Exercise 10.2 — the base parameters of the two-link arm
# The two-link arm has six base parameters: h₁,ₓ, h₁,ᵧ and I_zz,₁ of link 1, each with what link 2's mass adds to
# it, and h₂,ₓ, h₂,ᵧ and I_zz,₂ of link 2 as they are. Write `base_two_link(pi)`: from a π of 20 numbers (the order
# printed above), the six values (π_b1 … π_b6) in that order, for your arm. Think of where link 2's mass sits in
# link 1.

# %%
def base_two_link(pi):
    ### BEGIN SOLUTION
    p, joint_2 = dict(zip(names, pi)), my_robot("two_link").parameters["l1"]   # m: joint 2 along link 1
    return np.array([p["mcx_1"] + joint_2 * p["m_2"], p["mcy_1"], p["Izz_1"] + joint_2**2 * p["m_2"],
                     p["mcx_2"], p["mcy_2"], p["Izz_2"]])
    ### END SOLUTION


# %%
check("base_two_link")

# %% [markdown]
# The library finds them from Y itself, stacked over random states (rank and independent columns by QR), and
# names them in the notes' symbols (lc the distance of a centre of mass from its joint):

# %%
base = base_parameters(arm)
print(base.describe(["m1", "m2", "l1", "lc1", "lc2"]))
print("never act:", [name for k, name in enumerate(names) if not base.beta[:, k].any()])

# %% [markdown]
# ## An excitation trajectory
# Least squares on τ = Y_b π_b is only as good as Y_b stacked over the log is conditioned: its condition number κ
# (columns scaled to unit norm, so that kg and kg·m² count alike) bounds how much the torques' noise is amplified
# in π_b. A periodic Fourier motion per joint, its coefficients optimised for a small κ within the joint limits,
# is the standard choice (`course-dynamics excite` on the command line):

# %%
motion = excitation(arm, 6.0, harmonics=4, samples=16, max_iterations=30)   # 6 s period, at rest in the middle
print(f"κ = {motion.condition:.3g} (the random start: {motion.condition_start:.3g})")
for kind in ("position", "velocity", "effort"):
    share, joint = motion.limits.largest(kind)
    print(f"largest share of the {kind} limits: {share:.0%} ({joint})")
figure, ax = plt.subplots(figsize=(7, 3.4), constrained_layout=True)
for j, joint in enumerate(arm.joint_names):
    ax.plot(motion.t, motion.q[:, j], label=f"q of {joint}")
ax.set_xlabel("t (s)")
ax.set_ylabel("joint angle (rad)")
ax.set_title(f"Excitation of the two-link arm, κ = {motion.condition:.3g}")
ax.legend()
ax.grid(alpha=0.3)
plt.show()

# %% [markdown]
# ## Identification from a noisy log
# The "real" arm differs from its model: link 2 carries a 0.3 kg gripper that moves its centre of mass, and both
# links have inertia about their centres of mass that the model's point masses lack. The log runs the excitation
# four times, then a second excitation (another seed) that `identify` holds out (its last 20 %) to judge the
# result. Rates as a filter gives them; measured torques with 0.2 N·m of noise.

# %%
real = replace(arm, bodies=(replace(link1, mass=2.2, p_com=[0.47, 0.0, 0.0], I_com=np.diag([0.001, 0.04, 0.04])),
                            replace(link2, mass=1.3, p_com=[0.43, 0.01, 0.0], I_com=np.diag([0.001, 0.02, 0.02]))))
check_motion = excitation(arm, 6.0, harmonics=4, samples=16, max_iterations=30, seed=1)
pieces = [motion] * 4 + [check_motion]
t = np.concatenate([p.t[:-1] + 6.0 * k for k, p in enumerate(pieces)])        # s
q, qd, qdd = (np.vstack([getattr(p, name)[:-1] for p in pieces]) for name in ("q", "qd", "qdd"))
rng = np.random.default_rng(0)
tau_measured = inverse_dynamics(real, q, qd, qdd) + rng.normal(0.0, 0.2, q.shape)   # N·m
found = identify(arm, JointLog(t, q, qd, qdd, measured=tau_measured), friction="none", holdout=0.2)
print(f"κ of the fitted log: {found.condition_number:.3g}; solver: {found.solver}")

# %%
truth = base.values(parameters(real))
columns = zip(base.describe().splitlines(), found.base_urdf, truth, found.base_wls, found.base_error,
              found.base_consistent)
rows = [f"| {line.split(' = ')[0]} | {line.split(' = ')[1]} | {urdf:.4f} | {true:.4f} | {wls:.4f} ± {error:.4f} | "
        f"{identified:.4f} |" for line, urdf, true, wls, error, identified in columns]
display(Markdown("\n".join(["| | combination | URDF | real arm | least squares ± σ | identified (consistent) |",
                             "|---|---|---|---|---|---|", *rows])))

# %% [markdown]
# Every base parameter is found to within a few standard errors; the individual masses and inertias are not (no
# log could find them), and stay as close to the URDF as the data allow. On the held-out motion, torques predicted
# with the identified model against those with the URDF's:

# %%
t_held, measured, urdf_tau, identified_tau = found.held_out
figure, axes = plt.subplots(2, 1, sharex=True, figsize=(7.2, 5.2), constrained_layout=True)
for j, joint in enumerate(arm.joint_names):
    axes[j].plot(t_held, measured[:, j], ".", color="0.6", markersize=2, label="measured (noisy)")
    axes[j].plot(t_held, urdf_tau[:, j], label=f"URDF, RMS error {found.rms_before[j]:.3g} N·m")
    axes[j].plot(t_held, identified_tau[:, j], label=f"identified, RMS error {found.rms_after[j]:.3g} N·m")
    axes[j].set_ylabel(f"τ of {joint} (N·m)")
    axes[j].legend(fontsize="small")
    axes[j].grid(alpha=0.3)
axes[1].set_xlabel("t (s)")
axes[0].set_title("Held-out motion: torques by the URDF and by the identified model")
plt.show()

# %% [markdown]
# The identified model's error is the noise itself (0.2 N·m); the URDF's is the gripper and the inertias it did not
# know about. What a poor trajectory would have cost: κ of a slow single sine on each joint,

# %%
w_slow, slow = np.pi / 3, np.linspace(0, 6.0, 601)          # rad/s (one period in 6 s), s
in_phase = np.sin(w_slow * slow)[:, None] * [1.0, 0.5]     # rad: both joints swing together
sine = (in_phase, w_slow * np.cos(w_slow * slow)[:, None] * [1.0, 0.5], -w_slow**2 * in_phase)
print(f"κ of a slow sine: {condition_number(arm, *sine):.3g}, of the excitation: {motion.condition:.3g}")

# %% [markdown]
# ## A payload on a known arm
# Once the arm is known, what it carries is ten parameters more: a payload fixed to the tool frame adds to body 2,
# and the torques it costs, τ_meas − τ_arm = Y_F π_P, are linear in its own m, m c and inertia about the tool frame's
# origin, written in the tool's frame (`course_dynamics.tools.payloads`: Y_F is the regressor's ten columns of body 2,
# moved from frame 2 to the tool frame by the parallel-axis theorem (6.25) and a rotation). The real arm picks up a
# 0.5 kg part 3 cm beyond the tool point, and runs the excitation again:

# %%
from course_dynamics.core.regressor import PARAMETER_NAMES
from course_dynamics.tools.loads import Payload, with_payload
from course_dynamics.tools.payloads import identify_payload

part = Payload(0.5, link="tool", com=(0.03, 0.01, 0.0))                     # kg, m in the tool frame
carrying = with_payload(real, part)
tau_part = inverse_dynamics(carrying, q, qd, qdd) + rng.normal(0.0, 0.2, q.shape)   # N·m, measured
picked = identify_payload(real, JointLog(t, q, qd, qdd, measured=tau_part), link="tool")
print(f"mass {picked.mass:.3f} ± {picked.mass_sigma:.2g} kg (the part: {part.mass} kg)")
print("seen by the log: " + ", ".join(f"{name} {share:.2f}" for name, share in zip(PARAMETER_NAMES, picked.seen)))
print("centre of mass in the tool frame (m):", picked.com.round(4), "(NaN: not determined)")

# %% [markdown]
# A planar arm shows the payload's mass, its first moments in the plane and its inertia about the axis, and nothing
# else: its joints' axes are parallel, so m c_z and the other inertias never act. The identification says so
# rather than inventing them (c_z is not determined: NaN). A six-joint arm's wrist
# turns the payload about three axes and shows all ten: `identify --scope payload` and `excite --scope payload`.

# %% [markdown]
# ## What a model that matches the robot is for: collisions
# A model whose torques match the robot's (the identified one, or here the real arm itself) makes the measured
# torques tell when something else pushed the robot. With p = M Θ̇, the robot obeys ṗ = τ − F + CᵀΘ̇ − G + τ_ext
# (since Ṁ = C + Cᵀ), τ_ext being the torque the surroundings apply to the joints. The momentum observer
# r = K (p − p(0) − ∫(τ − F + CᵀΘ̇ − G + r) ds) then follows τ_ext with a lag of 1/K, from Θ, Θ̇ and τ alone,
# no Θ̈ (`course_dynamics.tools.collisions`, the `detect` command). The held-out motion again, now with a push of
# 15 N down on the tip for 0.2 s at t = 2 s (the arm moves in the x–z plane), measured as before:

# %%
from course_dynamics.core.cartesian import jacobian
from course_dynamics.tools.collisions import detect

t_c, q_c, qd_c, qdd_c = check_motion.t, check_motion.q, check_motion.qd, check_motion.qdd   # s, rad, rad/s, rad/s²
push = np.zeros((len(t_c), 6))
push[(t_c >= 2.0) & (t_c < 2.2), :3] = [0.0, 0.0, -15.0]       # N on the tip, down (base z)
tau_ext = np.einsum("kji,kj->ki", jacobian(real, q_c, "tool"), push)          # τ_ext = Jᵀ F
tau_c = inverse_dynamics(real, q_c, qd_c, qdd_c) - tau_ext + rng.normal(0.0, 0.2, q_c.shape)   # N·m, measured
qd_measured = qd_c + rng.normal(0.0, 1e-3, q_c.shape)                                          # rad/s
log = {"t": t_c} | {f"{kind}_{j}": x[:, i] for kind, x in (("q", q_c), ("qd", qd_measured), ("tau_meas", tau_c))
                    for i, j in enumerate(arm.joint_names)}
collision = detect(real, log)
for event in collision.events:
    print(f"contact from {event.start:.3f} s to {event.end:.3f} s (detected at {event.detected:.3f} s); "
          "peak τ_ext " + ", ".join(f"{j} {p:+.2f}" for j, p in zip(event.joints, event.peak)) + " N·m")
figure, axes = plt.subplots(2, 1, sharex=True, figsize=(7.2, 4.6), constrained_layout=True)
for j, joint in enumerate(arm.joint_names):
    axes[j].plot(t_c, tau_ext[:, j], color="0.5", label="τ_ext injected")
    axes[j].plot(t_c, collision.r[:, j], label="observer's r")
    for sign in (1, -1):
        axes[j].axhline(sign * collision.threshold[j], color="0.4", linestyle="--", linewidth=0.8)
    for event in collision.events:
        axes[j].axvspan(event.start, event.end, color="tab:red", alpha=0.2)
    axes[j].set_ylabel(f"{joint} (N·m)")
    axes[j].grid(alpha=0.3)
axes[0].legend(fontsize="small")
axes[1].set_xlabel("t (s)")
axes[0].set_title("Momentum observer: r(t), its thresholds (dashed) and the contact found (shaded)")
plt.show()
