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
from course_dynamics.teaching.exercises import check, symbols
from course_dynamics.output.render import derivation_text
from course_dynamics.tools.simulation import simulate
from course_dynamics.core.parameters import joint_symbols, symbolic_model
from course_dynamics.core.symbolic import canonical, derive

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
# Apply (6.77): `tau_pendulum`, the torque at the pivot, in m, l, g, θ, θ̈. (Treat θ and θ̇ as independent when
# taking ∂/∂θ and ∂/∂θ̇; then d/dt of an expression in θ̇ replaces θ̇ by θ̈, here.)

# %%
### BEGIN SOLUTION
L = m * (l * theta_dot) ** 2 / 2 - m * g * l * (1 - sympy.cos(theta))
tau_pendulum = sympy.diff(L, theta_dot).subs(theta_dot, theta_ddot) - sympy.diff(L, theta)
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
# Link 1 turns by θ₁ (from the horizontal); link 2 slides along it by d₂. The library's Lagrangian path computes
# each link's kinetic energy from its Jacobians; with the notes' symbols:

# %%
rp, parameters = symbolic_model(load_robot("rp_arm"), ("m1", "m2", "l1", "Izz1", "Izz2", "g"))
q, qd, qdd = joint_symbols(rp)
k1, k2 = lagrange.link_kinetic_energies(rp, q, qd)
display(Markdown(f"$k_1 = {sympy.latex(sympy.simplify(k1))}$, $\\quad k_2 = {sympy.latex(sympy.simplify(k2))}$"))

# %% [markdown]
# and (6.77) gives the equations of motion, here with M, V, G and Craig's B and C read off:

# %%
by_lagrange = derive(load_robot("rp_arm"), ("m1", "m2", "l1", "Izz1", "Izz2", "g"), method="lagrange")
display(Markdown(derivation_text(by_lagrange, "markdown")))

# %% [markdown]
# ## The same equations as Newton–Euler
# Two derivations that share no code — one balances forces link by link, one differentiates energies — give
# identical expressions (compared in an exact normal form):

# %%
by_newton_euler = derive(load_robot("rp_arm"), ("m1", "m2", "l1", "Izz1", "Izz2", "g"), method="newton-euler")
same = all(sympy.expand(canonical(a, by_lagrange.q) - canonical(b, by_lagrange.q)) == 0
           for a, b in zip(by_lagrange.tau, by_newton_euler.tau))
print("τ by Lagrange equals τ by Newton–Euler:", same)
