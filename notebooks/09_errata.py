# %% [markdown]
# # 9. The notes, checked: every misprint shown numerically
#
# **What this notebook teaches.** To trust an equation only after checking it. The lecture notes this course
# started from contain misprints — a rotation inverted, a term doubled, a sign flipped. Each one below is
# evaluated twice at a concrete state, as printed and as corrected, and compared with an independent truth:
# Pinocchio (a robotics library that shares no code with ours), exact differentiation, or the exact integral.
# The full list, with the equations as printed and corrected, is the project's `reference/errata.md`; where every
# numbered equation of the notes is checked, by a test and in a notebook, is its `reference/equations.py`.

# %%
import numpy as np
import matplotlib.pyplot as plt
from IPython.display import Markdown, display

from course_dynamics.teaching.exercises import check, given, hint
from course_dynamics_reference.misprints import demonstrations, steps

# %% [markdown]
# ## Printed against corrected
# The error columns are relative, ‖form − truth‖∞ / ‖truth‖∞: a corrected form agrees to round-off (1e-16), a
# printed one is off by percents to hundreds of percents. One row per misprint with a numeric reading: the
# acceleration of a moving point (6.10), the outward and inward iterations (6.45)–(6.52), the worked two-link
# example, the pendulum, example 6.6's J, the Cartesian torque (6.105), the parallel-axis theorem, and the
# misprints found on a second reading (below the figure).

# %%
found = demonstrations()
rows = [f"| {m.where} | {m.quantity} | {m.truth} | {m.printed_error:.2e} | {m.corrected_error:.1e} |" for m in found]
display(Markdown("\n".join(["| where | quantity | compared with | printed error | corrected error |",
                             "|---|---|---|---|---|", *rows])))

# %%
figure, ax = plt.subplots(figsize=(7.5, 1.5 + 0.28 * len(found)), constrained_layout=True)
rows = np.arange(len(found))
floor = 1e-17   # an exact zero is drawn at 1e-17
ax.barh(rows - 0.2, [max(m.printed_error, floor) for m in found], height=0.4, label="as printed", color="tab:red")
ax.barh(rows + 0.2, [max(m.corrected_error, floor) for m in found], height=0.4, label="as corrected", color="tab:green")
ax.set_xscale("log")
ax.set_yticks(rows, [m.where for m in found], fontsize="small")
ax.invert_yaxis()
ax.set_xlabel("relative error against the truth (1)")
ax.set_title("The notes' misprints, evaluated")
ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2)  # below the axes: every row has both bars
ax.grid(alpha=0.3, axis="x")
plt.show()

# %% [markdown]
# ## Found on a second reading
# Rows from "the (5.45) line" on: five misprints found by reading the notes again, line by line, and two entries of the
# worked example now evaluated where the printed and the corrected forms differ.
# * **The (5.45) line** of the derivation of (6.32) prints ${}^{i+1}\dot\omega_{i+1} = {}^{i+1}_iR\,\dot\omega_i +
#   \dot\theta_{i+1}\,{}^{i+1}\hat Z_{i+1}$. (5.45) propagates angular *velocities*,
#   ${}^{i+1}\omega_{i+1} = {}^{i+1}_iR\,{}^i\omega_i + \dot\theta_{i+1}\,{}^{i+1}\hat Z_{i+1}$: the ω that the
#   cross-product term of (6.15) and (6.32) needs. As printed, it misses θ̈ and the cross product.
# * **(6.5) restated** before (6.34) reads ${}^AV_Q = {}^A_BR\,{}^B\dot V_Q + {}^A\Omega_B\times{}^A_BR\,{}^BQ$: a
#   velocity made of an acceleration; (6.5) has ${}^BV_Q$.
# * **(6.43), in words**: "the joint torque is the Z component of the vector representing the inertial torque". The
#   equation is right, τᵢ = ⁱnᵢᵀ ⁱẐᵢ, with ⁱnᵢ the moment link i−1 exerts on link i; the inertial torque of these
#   notes is ⁱNᵢ (6.37), and its Z component is not the joint torque.
# * **The (6.63) legend** defines B_x and C_x, the coefficients of (6.105); (6.63) has the joint-space B(Θ) and C(Θ),
#   whose B[Θ̇Θ̇] + C[Θ̇²] is V(Θ, Θ̇). Craig's (6.105), τ = Jᵀ M_x Ẍ + B_x[Θ̇Θ̇] + C_x[Θ̇²] + G, has joint torques in
#   B_x and C_x too, but B_x[Θ̇Θ̇] + C_x[Θ̇²] = Jᵀ V_x = V − Jᵀ M_x J̇ Θ̇: the torque that also keeps the tool on its
#   course while the joints move. It is not V (`cartesian_configuration_space_terms` computes B_x and C_x).
# * **(6.105)** prints M where M_x belongs and G_x, a force at the tool, where the joint-space G = Jᵀ G_x belongs.
# * **Setting {A} = {i+1}** before (6.34) names the wrong frame: (6.12) gives an acceleration relative to {A}, and
#   the origin of {i+1} does not move relative to {i+1}; {A} is the base {0}, and the result is then written in
#   {i+1}'s axes. **The prismatic remark** after (6.32), ⁱωᵢ = θ̇ᵢ = 0, stops a sliding link from turning with its
#   parent: a prismatic joint adds no rotation, ⁱ⁺¹ωᵢ₊₁ = ⁱ⁺¹ᵢR ⁱωᵢ, but ⁱωᵢ is not 0.
# * **(6.69)** writes Iᵢ without its C: about the frame origin, the rotational term counts the centre of mass's motion
#   a second time; k needs ᶜⁱIᵢ. **(6.73)** writes P_Cᵢ without its ⁰: ⁱP_Cᵢ is a constant of the link, and u would
#   not change with Θ.
# * **(6.117)** prints ½Θ̈(Δt)Δt². Read as (6.116) reads Θ̈(Δt), a product, that is ½Θ̈Δt³; the step of uniformly
#   accelerated motion is ½Θ̈(t)Δt², as in the notes' own S(t) = S₀ + V₀t + ½at². Released from rest, the printed
#   step moves the double pendulum a hundredth of the distance (Δt = 0.01 s).
# * The worked example's **¹N₁** and **²v̇₂**: ¹N₁'s formula keeps the
#   general indices and, as (6.50) does, an inertia about the frame origin; for the two-link arm's point masses both
#   forms give 0, so it is evaluated on the Panda's first link. ²v̇₂ = ²R² v̇_C₁ has the identity ²₂R where ²₁R belongs.
# * The last four rows: a frame, an index or a superscript that changes a number.
#
# Five have no numeric reading; the tests check each as corrected: the frame with its origin at ᴬP_c in the notes'
# box is {C}, not {A}; (6.2) differentiates ᴬΩ_B, the angular velocity of the frame {B}, not of a point Q; the
# worked example's ¹v̇₁ is ¹₀R ⁰v̇₀, not ¹R^i v̇_i; example 6.1's I_xy needs the integral ∫₀ʷ over x too; and (6.115)
# solves (6.59) with friction, τ = M Θ̈ + V + G + F, not (6.104).

# %% [markdown]
# ## The steps no other notebook shows
# Printed correctly, or left blank, and checked here against Pinocchio's own quantities or by exact differentiation:
# * (6.7) and (6.8): differentiating (6.5) once more,
#   $${}^A\dot V_Q = \frac{d}{dt}({}^A_BR\,{}^BV_Q) + {}^A\dot\Omega_B\times{}^A_BR\,{}^BQ
#     + {}^A\Omega_B\times\frac{d}{dt}({}^A_BR\,{}^BQ) \qquad (6.7)$$
#   then each derivative by (6.5) again (6.8); (6.10) collects the terms.
# * (6.15′) and (6.15″) stand empty in the notes: the two steps from (6.15) to (6.32) that the homework asks for.
#   With {A} = {0}, {B} = {i}, {C} = {i+1}, the joint gives ${}^B\Omega_C = \dot\theta_{i+1}\,{}^i\hat Z_{i+1}$, so
#   $${}^0\dot\omega_{i+1} = {}^0\dot\omega_i + {}^0_iR\,\ddot\theta_{i+1}\,{}^i\hat Z_{i+1}
#     + {}^0\omega_i\times{}^0_iR\,\dot\theta_{i+1}\,{}^i\hat Z_{i+1} \qquad (6.15')$$
#   and, in the axes of frame i+1 (a rotation carries a cross product over),
#   $${}^{i+1}\dot\omega_{i+1} = {}^{i+1}_iR\,{}^i\dot\omega_i + \ddot\theta_{i+1}\,{}^{i+1}\hat Z_{i+1}
#     + {}^{i+1}_iR\,{}^i\omega_i\times\dot\theta_{i+1}\,{}^{i+1}\hat Z_{i+1} \qquad (6.15'')$$
#   which is (6.32).
# * (6.31) appears only in the range "(6.31)–(6.37)": the outward iteration starts with the angular velocity,
#   ${}^{i+1}\omega_{i+1} = {}^{i+1}_iR\,{}^i\omega_i + \dot\theta_{i+1}\,{}^{i+1}\hat Z_{i+1}$ (5.45), restated as (6.45).
# * (6.35): a prismatic joint adds
#   $2\,{}^{i+1}\omega_{i+1}\times\dot d_{i+1}\,{}^{i+1}\hat Z_{i+1} + \ddot d_{i+1}\,{}^{i+1}\hat Z_{i+1}$ to (6.34);
#   checked on the RP arm of example 6.5.
# * (6.38) and (6.39): the balance of forces and moments at the centre of mass,
#   ${}^iF_i = {}^if_i - {}^i_{i+1}R\,{}^{i+1}f_{i+1}$ and
#   ${}^iN_i = {}^in_i - {}^in_{i+1} + (-{}^iP_{C_i})\times{}^if_i - ({}^iP_{i+1} - {}^iP_{C_i})\times{}^if_{i+1}$
#   (with ${}^in_{i+1}$, ${}^if_{i+1}$ in frame i's axes), from Pinocchio's own forces and moments.
# * (6.44): a prismatic joint's force is τᵢ = ⁱfᵢᵀ ⁱẐᵢ.

# %%
rows = [f"| {c.where} | {c.quantity} | {c.truth} | {c.error:.1e} |" for c in steps()]
display(Markdown("\n".join(["| equation | quantity | compared with | relative error |", "|---|---|---|---|", *rows])))

# %% [markdown]
# ## Two of them, by hand
#
# ### Exercise 9.1 — the parallel-axis theorem for products of inertia
# The notes print ᴬI_xy = ᶜI_xy − m x_c y_c. For the box of example 6.1 about its corner — m, w, l, h in
# `given("I_xy_corner")`, centre of mass at (w/2, l/2, h/2), ᶜI_xy = 0 by symmetry — compute the correct
# ᴬI_xy = ∭ x y ρ dv as `I_xy_corner` (kg·m²).

# %%
box = given("I_xy_corner")
print(box)

# %%
### BEGIN SOLUTION
I_xy_corner = 0.0 + box["m"] * (box["w"] / 2) * (box["l"] / 2)
### END SOLUTION

# %%
check("I_xy_corner")

# %% [markdown]
# ### Exercise 9.2 — the inward force, corrected
# The notes print (6.51) as ⁱfᵢ = ⁱIᵢ₊₁ ⁱR^{i+1} fᵢ₊₁ + Fᵢ, with a stray inertia tensor. Write the corrected
# `inward_force(R, f_next, F)`: the force on link i from link i−1, given R = ⁱᵢ₊₁R (the orientation of frame i+1
# in frame i, a 3 × 3 array), f_next = ⁱ⁺¹fᵢ₊₁ and F = ⁱFᵢ (3-vectors). The check runs it on your own spatial arm
# (`my_robot("spatial_arm")`, notebook 3's), link by link, at states of yours.

# %%
def inward_force(R, f_next, F):
    ### BEGIN SOLUTION
    return R @ f_next + F
    ### END SOLUTION


# %%
check("inward_force")

# %% [markdown]
# **Correct as printed** (checked the same way, in the project's tests): (6.1), (6.5), (6.7), (6.8), (6.12), (6.13),
# (6.15), the inertia definitions and example 6.2, (6.32)–(6.42), (6.44), (6.53), (6.59)–(6.62), (6.64),
# (6.71), (6.75), (6.77), (6.91)–(6.99), (6.104), (6.115), (6.116). `reference/equations.py` names the test and the notebook
# cell of every label.
