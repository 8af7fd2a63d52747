# %% [markdown]
# # 5. The Lagrangian formulation
#
# **What this notebook teaches.** A second route to the same equations of motion, from energy instead of forces:
# the kinetic energy k (6.69), (6.71), the potential energy u (6.73), the Lagrangian L = k − u (6.75) and the
# Euler–Lagrange equation (6.76), (6.77). Worked step by step for the pendulum and the RP arm of example 6.5, and
# compared with Newton–Euler — they agree exactly.
#
# **Notation** (Craig): kᵢ = ½ mᵢ v_Cᵢᵀ v_Cᵢ + ½ ωᵢᵀ Iᵢ ωᵢ the kinetic energy of link i; uᵢ = −mᵢ ⁰gᵀ ⁰P_Cᵢ + u_ref
# its potential energy; k = Σ kᵢ = ½ Θ̇ᵀ M(Θ) Θ̇; u = Σ uᵢ.

# %%
import numpy as np
import matplotlib.pyplot as plt
import sympy
from IPython.display import Markdown, display

from course_dynamics.core import lagrange
from course_dynamics import load_robot
from course_dynamics.teaching.exercises import check, hint, symbols, time_functions
from course_dynamics.tools.simulation import simulate

# %% [markdown]
# ## The equations
#
# $$k = \sum_i \tfrac12 m_i v_{C_i}^Tv_{C_i} + \tfrac12\omega_i^T I_i\omega_i = \tfrac12\dot\Theta^TM(\Theta)\dot\Theta \qquad (6.69),\ (6.71)$$
# $$u = \sum_i -m_i\,{}^0g^T\,{}^0P_{C_i} + u_{ref} \qquad (6.73)\qquad L = k - u \qquad (6.75)$$
# $$\frac{d}{dt}\frac{\partial L}{\partial\dot\Theta} - \frac{\partial L}{\partial\Theta} = \tau
#   \quad\Longleftrightarrow\quad \frac{d}{dt}\frac{\partial k}{\partial\dot\Theta} - \frac{\partial k}{\partial\Theta} + \frac{\partial u}{\partial\Theta} = \tau \qquad (6.77)$$
#
# ## The pendulum
# A point mass m on a massless rod of length l, θ measured from hanging straight down. Its speed is l θ̇ and its
# height below the pivot l cos θ.
#
# ### Exercise 5.1 — kinetic energy
# Write the pendulum's kinetic energy `k_pendulum` as a sympy expression in the symbols below.

# %%
m, l, g, theta, theta_dot, theta_ddot = symbols("m", "l", "g", "theta", "theta_dot", "theta_ddot")

# %%
### BEGIN SOLUTION
k_pendulum = m * (l * theta_dot) ** 2 / 2
### END SOLUTION

# %%
check("k_pendulum")

# %% [markdown]
# ### Exercise 5.2 — potential energy
# Write its potential energy `u_pendulum` (any reference height will do: only ∂u/∂θ enters the equation).

# %%
### BEGIN SOLUTION
u_pendulum = m * g * l * (1 - sympy.cos(theta))
### END SOLUTION

# %%
check("u_pendulum")

# %% [markdown]
# ### Exercise 5.3 — the equation of motion
# Apply (6.77) as on paper: θ is a function of time, so write it as one, build L from it, and let sympy take
# ∂/∂θ̇, ∂/∂θ and the time derivative d/dt with the chain rule. `time_functions("theta")` gives t and θ(t);
# `theta_t.diff(t)` is θ̇(t). Write `tau_pendulum`, the torque at the pivot; the check reads θ(t), θ̇(t), θ̈(t)
# as θ, θ̇, θ̈. (Differentiating with respect to θ̇(t) treats it as its own variable, as (6.77) intends.)

# %%
t, theta_t = time_functions("theta")

# %%
### BEGIN SOLUTION
L = m * (l * theta_t.diff(t)) ** 2 / 2 - m * g * l * (1 - sympy.cos(theta_t))
tau_pendulum = sympy.diff(sympy.diff(L, theta_t.diff(t)), t) - sympy.diff(L, theta_t)
### END SOLUTION

# %%
check("tau_pendulum")

# %% [markdown]
# (The notes print this with a minus sign before m g l sin θ; notebook 9 shows why it must be +: with −, the
# pendulum would fall away from hanging.) Energy flows between k and u while their sum stays constant:

# %%
pendulum = load_robot("pendulum")
run = simulate(pendulum, [1.2], [0.0], duration=4.0, dt=1e-3)
kinetic = lagrange.kinetic_energy(pendulum, run.q, run.qd)
potential = run.energy - kinetic
figure, ax = plt.subplots(figsize=(6.8, 3.6))
ax.plot(run.t, kinetic, label="k (kinetic)")
ax.plot(run.t, potential - potential.min(), label="u − u_min (potential)")
ax.plot(run.t, run.energy - potential.min(), "k--", label="k + u − u_min")
ax.set_xlabel("t (s)")
ax.set_ylabel("energy (J)")
ax.set_title("Pendulum, m = 1 kg, l = 1 m, released at θ = 1.2 rad")
ax.legend(loc="upper right")
ax.grid(alpha=0.3)
plt.show()

# %% [markdown]
# ## Example 6.5: the RP arm
# Link 1 turns by θ₁ from the horizontal X₀ and has its centre of mass at l₁ along it, with mass m₁ and I_zz1
# about its centre of mass; link 2 slides along link 1 by d₂, with mass m₂ at d₂ and I_zz2. Gravity g acts along
# −Y₀.
#
# ### Exercise 5.4 — example 6.5 by Lagrange
# Derive the two equations of motion the way example 6.5 does: write each link's kinetic energy (6.69) and
# potential energy (6.73) with θ₁(t) and d₂(t) as functions of time, form L (6.75), and apply (6.77) to each
# joint. Give `lagrange_rp_arm = [tau1, tau2]`. The check accepts any equivalent form and names a missing or
# extra term by the part of τ it belongs to (Mᵢⱼ, a Coriolis or centrifugal term of Vᵢ, Gᵢ).

# %%
m1, m2, l1, Izz1, Izz2 = symbols("m1", "m2", "l1", "Izz1", "Izz2")
t, theta1, d2 = time_functions("theta1", "d2")

# %%
### BEGIN SOLUTION
k1 = (m1 * l1**2 + Izz1) * theta1.diff(t) ** 2 / 2
k2 = m2 * (d2.diff(t) ** 2 + d2**2 * theta1.diff(t) ** 2) / 2 + Izz2 * theta1.diff(t) ** 2 / 2
u1, u2 = m1 * g * l1 * sympy.sin(theta1), m2 * g * d2 * sympy.sin(theta1)
L = k1 + k2 - u1 - u2
lagrange_rp_arm = [sympy.diff(sympy.diff(L, x.diff(t)), t) - sympy.diff(L, x) for x in (theta1, d2)]
### END SOLUTION

# %%
check("lagrange_rp_arm")

# %% [markdown]
# **Where the 2 of the Coriolis term comes from.** ∂L/∂θ̇₁ holds m₂d₂²θ̇₁, and both d₂ and θ̇₁ change in time:
# d/dt (m₂d₂²θ̇₁) = m₂d₂²θ̈₁ + m₂·(d/dt d₂²)·θ̇₁ = m₂d₂²θ̈₁ + 2m₂d₂ḋ₂θ̇₁. The first part belongs to M₁₁, the
# second is the Coriolis term: the 2 is the derivative of the square. Replacing θ̇ by θ̈ (what the pendulum's
# constant ml² allowed) loses it. In Craig's split (6.63), V = B(Θ)[Θ̇Θ̇] + C(Θ)[Θ̇²]: B multiplies the products
# θ̇ⱼθ̇ₖ (j < k; here only θ̇₁ḋ₂), C the squares (θ̇₁², ḋ₂²).
#
# ### Exercise 5.5 — Craig's B and C
# Read off `B_rp_arm` (a 2 × 1 sympy Matrix: the coefficients of θ̇₁ḋ₂ in τ₁ and τ₂) and `C_rp_arm` (2 × 2: row
# i holds the coefficients of θ̇₁² and ḋ₂² in τᵢ), in the symbols m2 and d2 (the joint value d₂ as a plain symbol).

# %%
d2_symbol = symbols("d2")

# %%
### BEGIN SOLUTION
B_rp_arm = sympy.Matrix([[2 * m2 * d2_symbol], [0]])
### END SOLUTION

# %%
check("B_rp_arm")

# %%
### BEGIN SOLUTION
C_rp_arm = sympy.Matrix([[0, 0], [-m2 * d2_symbol, 0]])
### END SOLUTION

# %%
check("C_rp_arm")

# %% [markdown]
# (with the solutions only)
#
# The library's Lagrangian path computes each link's kinetic energy from its Jacobians, and (6.77) gives the same
# equations, here with M, V, G and Craig's B and C read off:

# %%
# (with the solutions only)
from course_dynamics.core.parameters import joint_symbols, symbolic_model
from course_dynamics.core.symbolic import canonical, derive
from course_dynamics.output.render import derivation_text

rp, parameters = symbolic_model(load_robot("rp_arm"), ("m1", "m2", "l1", "Izz1", "Izz2", "g"))
q, qd, qdd = joint_symbols(rp)
k1, k2 = lagrange.link_kinetic_energies(rp, q, qd)
display(Markdown(f"$k_1 = {sympy.latex(sympy.simplify(k1))}$, $\\quad k_2 = {sympy.latex(sympy.simplify(k2))}$"))
display(Markdown(derivation_text(derive(load_robot("rp_arm"), ("m1", "m2", "l1", "Izz1", "Izz2", "g"),
                                        method="lagrange"), "markdown")))

# %% [markdown]
# ## The same equations as Newton–Euler
# Two derivations that share no code — one balances forces link by link, one differentiates energies — give
# identical expressions. Your check of exercise 5.4 made that comparison: your Lagrangian equations against the
# Newton–Euler recursion on symbols, in an exact normal form.

# %% [markdown]
# (with the solutions only)
#
# The library's two derivations of example 6.5, compared:

# %%
# (with the solutions only)
by_lagrange = derive(load_robot("rp_arm"), ("m1", "m2", "l1", "Izz1", "Izz2", "g"), method="lagrange")
by_newton_euler = derive(load_robot("rp_arm"), ("m1", "m2", "l1", "Izz1", "Izz2", "g"), method="newton-euler")
same = all(sympy.expand(canonical(a, by_lagrange.q) - canonical(b, by_lagrange.q)) == 0
           for a, b in zip(by_lagrange.tau, by_newton_euler.tau))
print("τ by Lagrange equals τ by Newton–Euler:", same)
