# %% [markdown]
# # 2. Mass distribution: the inertia tensor
#
# **What this notebook teaches.** How a body's mass distribution enters the dynamics through its inertia tensor;
# the moments and products of inertia; the parallel-axis theorem that moves a tensor from the centre of mass to
# another point; examples 6.1 and 6.2 (a rectangular box about its corner and about its centre); principal axes;
# and the conditions every real body's tensor meets — the ones a URDF must meet for `course_dynamics` to load it.
#
# **Notation** (Craig): ᴬI is the inertia tensor about the origin of {A}, in the axes of {A} (kg·m²); ᶜI the
# tensor about the centre of mass; ᴬP_C = (x_c, y_c, z_c) the centre of mass in {A}; m the mass.

# %%
import numpy as np
import matplotlib.pyplot as plt
import sympy

from course_dynamics.core import inertia
from course_dynamics.teaching.exercises import check, given, hint, symbols

# %% [markdown]
# ## The tensor
#
# For a body of density ρ, with ᴬP = (x, y, z) the position of its volume element dv in {A},
# $${}^AI = \begin{bmatrix} I_{xx} & -I_{xy} & -I_{xz}\\ -I_{xy} & I_{yy} & -I_{yz}\\ -I_{xz} & -I_{yz} & I_{zz}\end{bmatrix},\quad
#   I_{xx} = \iiint (y^2+z^2)\rho\,dv,\ \ldots,\quad I_{xy} = \iiint xy\,\rho\,dv,\ \ldots$$
# The moments I_xx, I_yy, I_zz resist rotation about each axis; the products I_xy, I_xz, I_yz measure how far the
# mass distribution is from being symmetric about the axes. `course_dynamics.core.inertia` has the tensors of simple
# bodies about their centres (exact, and checked against the integrals and against Pinocchio):

# %%
m, w, l, h = symbols("m", "w", "l", "h")
sympy.Matrix(inertia.box(m, w, l, h))      # example 6.2: a box of sides w, l, h about its centre

# %% [markdown]
# ## Moving the tensor: the parallel-axis theorem
#
# About a point {A} from which the centre of mass is at ᴬP_C = (x_c, y_c, z_c),
# $${}^AI = {}^CI + m\,(P_C^TP_C\,\mathbf 1 - P_C P_C^T),\qquad
#   {}^AI_{zz} = {}^CI_{zz} + m(x_c^2 + y_c^2),\qquad {}^AI_{xy} = {}^CI_{xy} + m\,x_c y_c$$
# (the notes print − in the product rule; with $I_{xy} = \iiint xy\rho\,dv$ it is +, which is what example 6.1's
# ᴬI_xy = m w l / 4 needs; their example 6.1 also leaves out the integral over x in I_xy, and where they say "the
# frame {A} has its origin at ᴬP_c" the frame at the centre of mass, {C}, is meant). The moment about an axis is least about the parallel axis through the centre of mass,
# and grows with the square of the distance:

# %%
box = inertia.box(2.0, 0.3, 0.5, 0.1)                 # kg, m: a 2 kg plate
offsets = np.linspace(-0.6, 0.6, 121)                 # m: shift of the axis along x
I_zz = [inertia.parallel_axis(box, 2.0, (d, 0.0, 0.0))[2, 2] for d in offsets]
figure, ax = plt.subplots(figsize=(6.5, 3.4))
ax.plot(offsets, I_zz)
ax.axhline(box[2, 2], color="gray", linestyle="--", label="ᶜI_zz (through the centre of mass)")
ax.set_xlabel("distance of the z axis from the centre of mass, x_c (m)")
ax.set_ylabel("I_zz (kg·m²)")
ax.set_title("Parallel-axis theorem: I_zz = ᶜI_zz + m x_c²")
ax.legend()
ax.grid(alpha=0.3)
plt.show()

# %% [markdown]
# ### Exercise 2.1 — example 6.1: the box about its corner
# Frame {A} has its origin at a corner of the box, its axes along the edges w (x), l (y) and h (z), so the centre
# of mass is at ᴬP_C = (w/2, l/2, h/2). Compute ᴬI as a 3×3 sympy matrix `I_corner` in the symbols m, w, l, h
# above. You may use `inertia.box` and `inertia.parallel_axis`, or integrate.

# %%
### BEGIN SOLUTION
I_corner = sympy.Matrix(inertia.parallel_axis(inertia.box(m, w, l, h), m, (w / 2, l / 2, h / 2)))
### END SOLUTION

# %%
check("I_corner")

# %% [markdown]
# Example 6.1 integrates two entries of this matrix, I_xx and I_xy: compare yours with the notes' (the tensor holds
# −I_xy off the diagonal).

# %% [markdown]
# (with the solutions only)
#
# The library's products of inertia of the box about its corner, I_xy, I_xz and I_yz:

# %%
# (with the solutions only)
products = inertia.products_of_inertia(inertia.parallel_axis(inertia.box(m, w, l, h), m, (w / 2, l / 2, h / 2)))
print("I_xy, I_xz, I_yz =", [sympy.factor(p) for p in products])

# %% [markdown]
# ## Principal axes
#
# Every inertia tensor is symmetric, so some rotation of the axes makes it diagonal: along these *principal axes*
# the products of inertia vanish and the diagonal holds the *principal moments*, the eigenvalues of the tensor.
#
# ### Exercise 2.2 — principal moments
# `given("principal_moments")["I"]` is a tensor in kg·m². Find its principal moments, smallest first, as
# `principal_moments` (3 numbers).

# %%
I = given("principal_moments")["I"]
print(I)

# %%
### BEGIN SOLUTION
principal_moments = np.linalg.eigvalsh(I)
### END SOLUTION

# %%
check("principal_moments")

# %% [markdown]
# ## Which tensors are physical?
#
# A real body's tensor is symmetric, has no negative principal moment, and its principal moments obey the
# triangle inequality I₁ + I₂ ≥ I₃: each is an integral of squared distances, and
# I₁ + I₂ − I₃ = 2∭ z² ρ dv ≥ 0 in principal axes. A flat plate meets it with equality; a point mass has the zero
# tensor. `inertia.physical_problems` says what is wrong with a tensor, and the URDF loader refuses a robot with
# such a link.
#
# ### Exercise 2.3 — spot the impossible bodies
# For each of the three tensors in `given("physical")["tensors"]`, decide whether a real body can have it: a list
# `physical` of three booleans.

# %%
tensors = given("physical")["tensors"]
for k, tensor in enumerate(tensors, start=1):
    print(f"tensor {k}:\n{tensor}")

# %%
### BEGIN SOLUTION
physical = [not inertia.physical_problems(tensor) for tensor in tensors]
### END SOLUTION

# %%
check("physical")
