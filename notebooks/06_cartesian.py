# %% [markdown]
# # 6. Dynamics in Cartesian space
#
# **What this notebook teaches.** How to write the dynamics in terms of the end effector's motion instead of the
# joints': the Cartesian mass matrix M_x, velocity terms V_x and gravity G_x (6.91)–(6.99), and the joint torques
# that produce a desired Cartesian acceleration (6.104). Example 6.6, the two-link arm in its tool frame, is done
# symbolically; and what happens near a singularity, where J loses rank, is plotted.
#
# **Notation** (Craig): X the position (and orientation) of a tool frame; J(Θ) its Jacobian, Ẋ = J Θ̇; F the
# force (and moment) at the tool; ³J the Jacobian expressed in frame {3}, the tool frame of the two-link arm.

# %%
import numpy as np
import matplotlib.pyplot as plt
import sympy
from IPython.display import Markdown, display

from course_dynamics import inverse_dynamics, load_robot
from course_dynamics.core.cartesian import SingularityError, cartesian_dynamics, jacobian
from course_dynamics.teaching.exercises import check, given, hint, my_robot, symbols
from course_dynamics.core.symbolic import derive_cartesian

arm = load_robot("two_link")

# %% [markdown]
# ## From joint space to Cartesian space
# With τ = Jᵀ F and Ẋ = J Θ̇, so Ẍ = J̇ Θ̇ + J Θ̈ (6.97), substituting Θ̈ = J⁻¹(Ẍ − J̇ Θ̇) into
# τ = M Θ̈ + V + G and multiplying by J⁻ᵀ (6.94), (6.98) gives F = M_x Ẍ + V_x + G_x (6.91) with
# $$M_x = J^{-T}MJ^{-1},\qquad V_x = J^{-T}(V - MJ^{-1}\dot J\dot\Theta),\qquad G_x = J^{-T}G \qquad (6.99)$$
# and back in joint space, τ = Jᵀ(M_x Ẍ + V_x + G_x) (6.104). This needs a square, invertible J: as many task
# directions as joints.
#
# ## Example 6.6: the two-link arm in its tool frame
#
# ### Exercise 6.1 — the tool-frame Jacobian
# The tool frame {3} sits at the tip of link 2, its x axis along the link. Write ³J for the two-link arm as a
# 2 × 2 sympy matrix `J_tool` in l1, l2 and θ₂ (the symbols below): the velocity of the tip in frame {3}, rows
# x and y, per unit θ̇₁ (first column) and θ̇₂ (second column).

# %%
l1, l2, theta2 = symbols("l1", "l2", "theta2")

# %%
### BEGIN SOLUTION
J_tool = sympy.Matrix([[l1 * sympy.sin(theta2), 0], [l1 * sympy.cos(theta2) + l2, l2]])
### END SOLUTION

# %%
check("J_tool")

# %% [markdown]
# (with the solutions only)
#
# The same library functions that compute J, M, V and G numerically run on symbols, and give example 6.6 in closed
# form — ³J among them, to compare with yours:

# %%
# (with the solutions only)
closed = derive_cartesian(arm, "tool", rows=["x", "y"], expressed_in="frame", symbols=("m1", "m2", "l1", "l2", "g"))
for name in ("J", "Mx", "Vx", "Gx"):
    display(Markdown(f"${name} = {sympy.latex(getattr(closed, name))}$"))

# %% [markdown]
# (The notes' J of example 6.6 has one entry wrong, and the J⁻¹ they print is the inverse of that wrong J; notebook 9
# shows which.)

# %% [markdown]
# (with the solutions only)
#
# (The notes print J with l₁c₂ where ³J has l₁c₂ + l₂; the J⁻¹ they print is the inverse of the right one.)

# %% [markdown]
# ### Exercise 6.2 — the Cartesian mass matrix at one state
# Your exercise uses your own two-link arm, not the section's: its numbers are below, and `your_arm` is its model.
# At your Θ = `given("Mx_value")["q"]`, compute M_x (2 × 2, kg) of your arm's tool frame from (6.99), with the
# numeric ³J and M of your arm (`jacobian(your_arm, q, "tool", expressed_in="frame", rows=["x", "y"])` and
# `mass_matrix(your_arm, q)` may help).

# %%
from course_dynamics import mass_matrix

print(my_robot("two_link").describe())
your_arm = my_robot("two_link").model
q = given("Mx_value")["q"]
print("Θ =", q, "rad")

# %%
### BEGIN SOLUTION
J = jacobian(your_arm, q, "tool", expressed_in="frame", rows=["x", "y"])
J_inv = np.linalg.inv(J)
Mx_value = J_inv.T @ mass_matrix(your_arm, q) @ J_inv
### END SOLUTION

# %%
check("Mx_value")

# %% [markdown]
# ## Near a singularity
# At θ₂ = 0 the arm is stretched out and ³J loses rank: no joint rate moves the tip along the arm. M_x then grows
# as m₁/s₂²: pushing the tool along the arm would take an ever larger force, and (6.99) stops making sense. The
# library refuses rather than print huge numbers:

# %%
elbow = np.logspace(-4, 0, 60)
M_xx, condition = [], []
for angle in elbow:
    terms = cartesian_dynamics(arm, [0.3, angle], [0.0, 0.0], "tool", expressed_in="frame", rows=["x", "y"])
    M_xx.append(terms.Mx[0, 0])
    condition.append(terms.condition)
figure, ax = plt.subplots(figsize=(6.8, 3.8))
ax.loglog(elbow, M_xx, label="M_x[x, x] (kg)")
ax.loglog(elbow, condition, label="condition number of J (1)")
ax.set_xlabel("θ₂ (rad), approaching the singularity at 0")
ax.set_ylabel("value")
ax.set_title("Two-link arm near the stretched-out singularity")
ax.legend()
ax.grid(alpha=0.3, which="both")
plt.show()
try:
    cartesian_dynamics(arm, [0.3, 0.0], [0.0, 0.0], "tool", expressed_in="frame", rows=["x", "y"])
except SingularityError as error:
    print("error:", error)

# %% [markdown]
# ## Back to the joints: (6.104)
# τ = Jᵀ(M_x Ẍ + V_x + G_x) with Ẍ = J Θ̈ + J̇ Θ̇ gives the same torques as the joint-space equations:

# %%
q, qd, qdd = np.array([0.4, 0.9]), np.array([0.7, -1.2]), np.array([0.3, 0.5])
terms = cartesian_dynamics(arm, q, qd, "tool", expressed_in="frame", rows=["x", "y"])
x_ddot = terms.J @ qdd + terms.J_dot @ qd
print("Jᵀ(M_x Ẍ + V_x + G_x) =", terms.joint_torques(x_ddot).round(9), "N·m")
print("M Θ̈ + V + G          =", inverse_dynamics(arm, q, qd, qdd).round(9), "N·m")
