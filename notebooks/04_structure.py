# %% [markdown]
# # 4. The structure of the equations: M, V, G, and the Coriolis matrix
#
# **What this notebook teaches.** How the Newton–Euler torques of any manipulator fall into the state-space form
# τ = M(Θ)Θ̈ + V(Θ, Θ̇) + G(Θ) (6.59); how V splits into Coriolis and centrifugal terms, B(Θ)[Θ̇Θ̇] + C(Θ)[Θ̇²]
# (6.63); and the properties these terms always have — M symmetric and positive definite, V quadratic in Θ̇, and a
# Coriolis matrix with C Θ̇ = V and Ṁ − 2C skew-symmetric — shown numerically, with M's eigenvalues plotted over the
# workspace.
#
# **Notation** (Craig): Θ, Θ̇, Θ̈ the joint positions, velocities and accelerations (n each); M(Θ) the n × n mass
# matrix; V(Θ, Θ̇) the velocity terms; G(Θ) gravity; [Θ̇Θ̇] the products θ̇ⱼθ̇ₖ (j < k) and [Θ̇²] the squares θ̇ⱼ² (6.64),
# (6.65); B(Θ) and C(Θ) their coefficient matrices.

# %%
import numpy as np
import matplotlib.pyplot as plt
from IPython.display import Markdown, display

from course_dynamics import coriolis_matrix, gravity_torques, load_robot, mass_matrix, velocity_torques
from course_dynamics.teaching.exercises import check, given, hint, my_robot
from course_dynamics.output.render import derivation_text, trace_latex
from course_dynamics.core.symbolic import derive
from course_dynamics.tools.trace import trace
from course_dynamics.core.lagrange import configuration_space_terms, velocity_pairs

arm = load_robot("two_link")

# %% [markdown]
# ## Reading M, V and G off the recursion
#
# The Newton–Euler recursion computes τ for any state. Choosing the state picks out each term (Craig section 6.8):
# G(Θ) = τ(Θ, 0, 0); V(Θ, Θ̇) = τ(Θ, Θ̇, 0) without gravity; column j of M(Θ) is τ(Θ, 0, eⱼ) without gravity. The
# library does exactly this by default for G and V, and computes M by the composite-rigid-body algorithm (the same
# matrix, in one pass).

# %%
q, qd = np.array([0.3, -0.8]), np.array([1.1, 0.6])
print("M =\n", mass_matrix(arm, q).round(5))
print("V =", velocity_torques(arm, q, qd).round(5), "  G =", gravity_torques(arm, q).round(5))

# %% [markdown]
# ## Properties that always hold
#
# The kinetic energy is k = ½ Θ̇ᵀ M Θ̇ (6.71) and is positive whenever anything moves, so **M is symmetric and
# positive definite**. Its eigenvalues say how hard the arm is to accelerate in the easiest and the hardest joint
# direction; for the two-link arm they depend only on θ₂, since only the elbow changes the mass distribution:

# %%
elbow = np.linspace(-np.pi, np.pi, 181)
eigenvalues = np.linalg.eigvalsh(mass_matrix(arm, np.column_stack([np.zeros_like(elbow), elbow])))
figure, ax = plt.subplots(figsize=(6.8, 3.6))
ax.plot(elbow, eigenvalues[:, 0], label="smallest eigenvalue")
ax.plot(elbow, eigenvalues[:, 1], label="largest eigenvalue")
ax.set_xlabel("θ₂ (rad)")
ax.set_ylabel("eigenvalue of M(Θ) (kg·m²)")
ax.set_title("Two-link arm: M(Θ) is positive definite over the whole workspace")
ax.legend()
ax.grid(alpha=0.3)
plt.show()

# %% [markdown]
# **V is quadratic in Θ̇**: every term is a product of two joint rates, so V(Θ, 2Θ̇) = 4 V(Θ, Θ̇). Its coefficients
# are Craig's B (Coriolis, θ̇ⱼθ̇ₖ) and C (centrifugal, θ̇ⱼ²) of (6.63) (the notes' legend of (6.63) names them B_x and
# C_x, the Cartesian ones of (6.105); here they are B(Θ) and C(Θ)):

# %%
B, C = configuration_space_terms(arm, q)
print("pairs of [Θ̇Θ̇]:", velocity_pairs(2), " B =", B.round(5).tolist(), " C =", C.round(5).tolist())
products, squares = np.array([qd[0] * qd[1]]), qd**2
print("B[Θ̇Θ̇] + C[Θ̇²] =", (B @ products + C @ squares).round(6), " V =", velocity_torques(arm, q, qd).round(6))
print("V(Θ, 2Θ̇) / V(Θ, Θ̇) =", (velocity_torques(arm, q, 2 * qd) / velocity_torques(arm, q, qd)).round(12))

# %% [markdown]
# The **Coriolis matrix** C(Θ, Θ̇) — not Craig's centrifugal C(Θ) above, but the n × n matrix with C Θ̇ = V whose
# entries come from the Christoffel symbols of M, Cᵢⱼ = Σₖ Γᵢⱼₖ θ̇ₖ — has one more property: Ṁ − 2C is
# skew-symmetric, which is what makes energy arguments in control work. Ṁ here comes from a finite difference,
# independent of C:

# %%
C_matrix = coriolis_matrix(arm, q, qd)
dt = 1e-7
M_dot = (mass_matrix(arm, q + dt * qd) - mass_matrix(arm, q - dt * qd)) / (2 * dt)
S = M_dot - 2 * C_matrix
print(f"largest |C Θ̇ − V|        = {np.abs(C_matrix @ qd - velocity_torques(arm, q, qd)).max():.1e} N·m")
print(f"largest |S + Sᵀ|, S = Ṁ − 2C = {np.abs(S + S.T).max():.1e} kg·m²/s (round-off of the finite difference)")

# %% [markdown]
# ### Exercises 4.1–4.3 — the closed forms (6.60)–(6.62)
# Collect the torques of notebook 3's iterations for the two-link arm into M, V and G, and write them as functions
# of numpy arrays: `M_two_link(q)` returning a 2 × 2 array, `V_two_link(q, qd)` and `G_two_link(q)` returning 2
# numbers. Your exercises use your own arm (point masses at the link ends, gravity along −Y₀); its numbers are
# below, and the cell after them reads them into `m1, m2, l1, l2, g`. The checks name the wrong entries of M and the
# wrong Coriolis or centrifugal coefficients of V.

# %%
print(my_robot("two_link").describe())
mine = my_robot("two_link").parameters
m1, m2, l1, l2, g = (mine[name] for name in ("m1", "m2", "l1", "l2", "g"))   # kg, m, m/s²


# %%
def M_two_link(q):
    ### BEGIN SOLUTION
    c2 = np.cos(q[1])
    off_diagonal = l2**2 * m2 + l1 * l2 * m2 * c2
    return np.array([[l2**2 * m2 + 2 * l1 * l2 * m2 * c2 + l1**2 * (m1 + m2), off_diagonal],
                     [off_diagonal, l2**2 * m2]])
    ### END SOLUTION


# %%
check("M_two_link")

# %%
def V_two_link(q, qd):
    ### BEGIN SOLUTION
    h = m2 * l1 * l2 * np.sin(q[1])
    return np.array([-h * qd[1] ** 2 - 2 * h * qd[0] * qd[1], h * qd[0] ** 2])
    ### END SOLUTION


# %%
check("V_two_link")

# %% [markdown]
# **Predict first.** Before you write G, decide for your arm: with the arm stretched out horizontally, Θ = (0, 0),
# is G₁ positive or negative? And in your pose below — link 1 raised by your θ₁ above the horizontal, link 2
# pointing straight back, horizontally, θ₂ = π − θ₁? Your arm's numbers (above) decide the second one. Write your
# two answers, and why, in the cell below as a comment; then run it. (G is the torque that holds the arm still
# against gravity; a positive torque turns a link counter-clockwise, from X₀ towards Y₀.)

# %%
theta1 = given("predict_G")["theta1"]   # rad, your own
print(f"your pose: θ₁ = {theta1} rad, θ₂ = π − θ₁")

# %%
# my prediction for Θ = (0, 0): …   and for my pose: …
your_arm = my_robot("two_link").model
for pose in ([0.0, 0.0], [theta1, np.pi - theta1]):
    print(f"Θ = ({pose[0]:g}, {pose[1]:.4g}): G₁ = {gravity_torques(your_arm, pose)[0]:.4f} N·m")

# %% [markdown]
# Did your pose surprise you? With link 2 pointing back, its mass sits at l₁ cos θ₁ − l₂ along X₀ from joint 1 and
# link 1's at l₁ cos θ₁: G₁ = g((m₁ + m₂) l₁ cos θ₁ − m₂ l₂) turns negative once m₂l₂ outweighs (m₁ + m₂) l₁ cos θ₁
# — for some of your classmates' arms in their poses it does, for others not. Your `G_two_link` must give the same
# two numbers.

# %%
def G_two_link(q):
    ### BEGIN SOLUTION
    c1, c12 = np.cos(q[0]), np.cos(q[0] + q[1])
    return np.array([m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1, m2 * l2 * g * c12])
    ### END SOLUTION


# %%
check("G_two_link")

# %% [markdown]
# (with the solutions only)
#
# ## The closed form, by the library
# Now that you have collected them: the iterations of notebook 3 run on symbols, and collecting τ by Θ̈, Θ̇ and g,
# give the section's closed form (6.60)–(6.62) (with the section's symbols m₁, m₂, l₁, l₂, g):

# %%
# (with the solutions only)
symbolic = trace(arm, None, None, None, symbols=("m1", "m2", "l1", "l2", "g"))
display(Markdown("$$" + trace_latex(symbolic).replace("% Newton-Euler iterations of two_link\n", "") + "$$"))

# %%
# (with the solutions only)
display(Markdown(derivation_text(derive(arm, ("m1", "m2", "l1", "l2", "g")), "markdown")))
