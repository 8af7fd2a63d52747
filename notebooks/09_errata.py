# %% [markdown]
# # 9. The notes, checked: every misprint shown numerically
#
# **What this notebook teaches.** To trust an equation only after checking it. The lecture notes this course
# started from contain misprints — a rotation inverted, a term doubled, a sign flipped. Each one below is
# evaluated twice at a concrete state, as printed and as corrected, and compared with an independent truth:
# Pinocchio (a robotics library that shares no code with ours), exact differentiation, or the exact integral.
# The full list, with the equations as printed and corrected, is the project's `reference/errata.md`.

# %%
import numpy as np
import matplotlib.pyplot as plt
from IPython.display import Markdown, display

from course_dynamics.teaching.exercises import check, given
from course_dynamics_reference.misprints import demonstrations

# %% [markdown]
# ## Printed against corrected
# The error columns are relative, ‖form − truth‖∞ / ‖truth‖∞: a corrected form agrees to round-off (1e-16), a
# printed one is off by percents to hundreds of percents.

# %%
found = demonstrations()
rows = [f"| {m.where} | {m.quantity} | {m.truth} | {m.printed_error:.2e} | {m.corrected_error:.1e} |" for m in found]
display(Markdown("\n".join(["| where | quantity | compared with | printed error | corrected error |",
                             "|---|---|---|---|---|", *rows])))

# %%
figure, ax = plt.subplots(figsize=(7.5, 4.6))
rows = np.arange(len(found))
floor = 1e-17   # an exact zero is drawn at 1e-17
ax.barh(rows - 0.2, [max(m.printed_error, floor) for m in found], height=0.4, label="as printed", color="tab:red")
ax.barh(rows + 0.2, [max(m.corrected_error, floor) for m in found], height=0.4, label="as corrected", color="tab:green")
ax.set_xscale("log")
ax.set_yticks(rows, [m.where for m in found], fontsize="small")
ax.invert_yaxis()
ax.set_xlabel("relative error against the truth (1)")
ax.set_title("The notes' misprints, evaluated")
ax.legend(loc="lower right")
ax.grid(alpha=0.3, axis="x")
plt.show()

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
# in frame i, a 3 × 3 array), f_next = ⁱ⁺¹fᵢ₊₁ and F = ⁱFᵢ (3-vectors).

# %%
def inward_force(R, f_next, F):
    ### BEGIN SOLUTION
    return R @ f_next + F
    ### END SOLUTION


# %%
check("inward_force")

# %% [markdown]
# **Correct as printed** (checked the same way, in the project's tests): (6.12), (6.13), (6.15), the inertia
# definitions and examples 6.1 and 6.2, (6.32)–(6.44), (6.53), (6.59)–(6.64), (6.69)–(6.77), (6.91)–(6.99),
# (6.104), (6.115)–(6.117).
