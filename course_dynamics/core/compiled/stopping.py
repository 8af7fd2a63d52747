"""Joint stops in the native run, the steps: ``simulate(..., limits="stop")`` whole in C, written by hand after
:class:`~course_dynamics.tools.joint_stops.StopRun` and shipped in the native loop's library (``looped.c``),
around the run's accelerations and integrator steps (:mod:`~course_dynamics.core.compiled.rollout`) and the
impulses and holds of :mod:`~course_dynamics.core.compiled.impulses`.

Each function is the Python one of the same name, operation for operation, on one state:

=======================  ==========================================================================
C                        what it does (``tools.joint_stops.StopRun``, ``tools.simulation``)
=======================  ==========================================================================
``sides``, ``beyond``    dᵢ for the joints at a limit; how far beyond their limits the joints are
``contact``              ``contact``: Θ put on the limits, one impulse, the joints held, a stop recorded
``release``              ``release`` and ``holding``: the joints held from a state on, and their λ
``crossing``             ``crossing``: the first crossing of a limit within a step, by the Illinois
                         variant of regula falsi, each evaluation one integrator step
``substeps``             ``substeps``: a step taken up to each crossing, and on from it
``stopping``             ``_integrate_with_stops`` for one member, recording Θ, Θ̇, Θ̈, τ, the joints held
                         and their λ at every sample
=======================  ==========================================================================
"""
from __future__ import annotations

#: How far beyond a limit the located crossing may be, rad (m); the joint is then put on the limit.
POSITION_TOLERANCE = 1e-12
#: Contacts within one step before the rest of the step is taken as it comes (the joint put on its limit).
MAXIMUM_CONTACTS_PER_STEP = 64

#: The C of the steps of a run with joint stops.
C = r"""
/* ---- joint stops in the native run: the steps (written by hand after tools.joint_stops.StopRun) ---- */

#define POSITION_TOLERANCE """ + repr(POSITION_TOLERANCE) + r"""
#define MAXIMUM_CONTACTS_PER_STEP """ + str(MAXIMUM_CONTACTS_PER_STEP) + r"""

/* dᵢ into s->side: +1 at or beyond an upper limit, −1 at or beyond a lower one, 0 between; whether any is not 0 */
static int sides(stops_t *s, const double *q)
{
    int touching = 0;
    for (Py_ssize_t j = 0; j < s->n; j++) {
        s->side[j] = q[j] >= s->upper[j] ? 1 : (q[j] <= s->lower[j] ? -1 : 0);
        touching = touching || s->side[j] != 0;
    }
    return touching;
}

/* How far the joints not held are beyond their limits at most (negative inside), rad (m); −inf for none */
static double beyond(const stops_t *s, const double *q, const int *held)
{
    double most = -INFINITY;
    for (Py_ssize_t j = 0; j < s->n; j++) {
        const double above = q[j] - s->upper[j], below = s->lower[j] - q[j];
        const double out = above > below ? above : below;
        most = !held[j] && out > most ? out : most;
    }
    return most;
}

/* StopRun.contact: Θ put on the limits, the joints there that run into them stopped by one impulse, those pushed
   into them held (held, Θ and Θ̇ updated), the stop recorded; 0, or the code of a torque not finite */
static int contact(rollout_t *r, double t, double *q, double *qd, int *held)
{
    stops_t *s = r->stops;
    const Py_ssize_t n = r->n;
    for (Py_ssize_t j = 0; j < n; j++) {
        q[j] = q[j] < s->lower[j] ? s->lower[j] : q[j];
        q[j] = q[j] > s->upper[j] ? s->upper[j] : q[j];
    }
    sides(s, q);
    dynamics(r, q, qd, s->M, s->bias);
    if (!driving(r, t, qd, s->tau, s->drive))
        return failing(r, 3, t, q, qd, s->drive);
    /* leaving its limit more slowly than its acceleration into it would bring it back within a step: resting */
    for (Py_ssize_t j = 0; j < n; j++)
        s->impulse[j] = s->drive[j] - s->bias[j];
    masked_solve(s, s->M, s->all, s->impulse, s->resting);
    for (Py_ssize_t j = 0; j < n; j++) {
        const double into = s->side[j] * s->resting[j];
        s->resting[j] = s->dt * (into > 0.0 ? into : 0.0);
        s->candidates[j] = s->side[j] != 0;
    }
    stop_impulse(s, s->M, qd, s->candidates, s->resting, s->after, s->active, s->impulse);
    int new = 0;
    for (Py_ssize_t j = 0; j < n; j++)
        new = new || (s->active[j] && !held[j]);
    if (new)
        record(s, t, q, held, kinetic(s->M, qd, n), kinetic(s->M, s->after, n));
    const double small = round_off(qd, n);
    for (Py_ssize_t j = 0; j < n; j++)            /* not leaving its limit: held if pushed into it */
        s->candidates[j] = s->side[j] != 0 && s->side[j] * s->after[j] >= -small;
    bias_at(r, q, s->after, s->bias);             /* the bias at Θ̇⁺ (M is the same) */
    hold(s, s->M, s->bias, s->drive, s->candidates, s->was, s->qdd, s->reaction);
    for (Py_ssize_t j = 0; j < n; j++) {
        held[j] = s->was[j];
        qd[j] = held[j] ? 0.0 : s->after[j];
    }
    return 0;
}

/* StopRun.release and holding: the joints held from (t, Θ, Θ̇) on (held updated), of those held until now and
   those at a limit not leaving it, with their λ in s->reaction where *touched; 0, or a torque's code */
static int release(rollout_t *r, double t, const double *q, const double *qd, int *held, int *touched)
{
    stops_t *s = r->stops;
    const Py_ssize_t n = r->n;
    *touched = sides(s, q) || any(held, n);
    if (!*touched)
        return 0;
    if (!driving(r, t, qd, s->tau, s->drive))
        return failing(r, 3, t, q, qd, s->drive);
    const double small = round_off(qd, n);
    for (Py_ssize_t j = 0; j < n; j++)
        s->candidates[j] = held[j] || (s->side[j] != 0 && s->side[j] * qd[j] >= -small);
    dynamics(r, q, qd, s->M, s->bias);
    hold(s, s->M, s->bias, s->drive, s->candidates, held, s->qdd, s->reaction);
    return 0;
}

/* One integrator step h from (t, Θ, Θ̇) with the joints in r->held held: 0, or a failing code */
static int step_held(rollout_t *r, int scheme, double t, const double *q, const double *qd, double h, double *q1,
                     double *qd1, double *stage)
{
    stops_t *s = r->stops;
    const int code = accelerations(r, t, q, qd, s->a1, s->unused);
    return code != 0 ? code : advance(r, scheme, t, q, qd, s->a1, h, q1, qd1, stage);
}

/* StopRun.crossing: the first time (*when, after t) within (0, h] at which a joint not held reaches its limit,
   and the state then (into q_at, qd_at), at or just beyond it by at most POSITION_TOLERANCE */
static int crossing(rollout_t *r, int scheme, double t, const double *q, const double *qd, double h,
                    const double *q_end, const double *qd_end, double *when, double *q_at, double *qd_at,
                    double *stage)
{
    stops_t *s = r->stops;
    const Py_ssize_t n = r->n;
    const size_t size = sizeof(double) * (size_t)n;
    int code;
    double a = 0.0, f_a = beyond(s, q, r->held);
    for (int k = 1; f_a >= 0 && k < 30; k++) {    /* a joint starting on its limit: find where it is inside */
        if ((code = step_held(r, scheme, t, q, qd, h * ldexp(1.0, -k), s->q_try, s->qd_try, stage)) != 0)
            return code;
        const double g = beyond(s, s->q_try, r->held);
        if (g < 0) {
            a = h * ldexp(1.0, -k), f_a = g;
            break;
        }
    }
    if (f_a >= 0) {
        *when = 0.0;
        memcpy(q_at, q, size);
        memcpy(qd_at, qd, size);
        return 0;
    }
    double b = h, f_b = beyond(s, q_end, r->held), beyond_b = f_b;
    int last = 0;
    memcpy(q_at, q_end, size);
    memcpy(qd_at, qd_end, size);
    for (int i = 0; i < 200; i++) {
        if (beyond_b <= POSITION_TOLERANCE || b - a <= 1e-15 * h)
            break;
        double c = (a * f_b - b * f_a) / (f_b - f_a);
        if (!(a < c && c < b))
            c = 0.5 * (a + b);
        if ((code = step_held(r, scheme, t, q, qd, c, s->q_try, s->qd_try, stage)) != 0)
            return code;
        const double g = beyond(s, s->q_try, r->held);
        if (g > 0) {
            b = c, f_b = g, beyond_b = g;
            memcpy(q_at, s->q_try, size);
            memcpy(qd_at, s->qd_try, size);
            f_a = last > 0 ? 0.5 * f_a : f_a, last = 1;
        } else {
            a = c, f_a = g;
            f_b = last < 0 ? 0.5 * f_b : f_b, last = -1;
        }
    }
    *when = b;
    return 0;
}

/* StopRun.substeps: the step h from (t, Θ, Θ̇) with the joints in held held, stopping joints at the limits they
   reach within it; the state at t + h into (q1, qd1), held updated */
static int substeps(rollout_t *r, int scheme, double t, const double *q, const double *qd, double h, int *held,
                    double *q1, double *qd1, double *stage)
{
    stops_t *s = r->stops;
    const size_t size = sizeof(double) * (size_t)r->n;
    const double end = t + h;
    int code, touched;
    memcpy(s->q, q, size);
    memcpy(s->qd, qd, size);
    r->held = held;
    for (int i = 0; i < MAXIMUM_CONTACTS_PER_STEP; i++) {
        if ((code = step_held(r, scheme, t, s->q, s->qd, end - t, s->q_end, s->qd_end, stage)) != 0)
            return code;
        if (beyond(s, s->q_end, held) <= 0) {
            memcpy(q1, s->q_end, size);
            memcpy(qd1, s->qd_end, size);
            return 0;
        }
        double when;
        if ((code = crossing(r, scheme, t, s->q, s->qd, end - t, s->q_end, s->qd_end, &when, s->q_cross,
                             s->qd_cross, stage)) != 0)
            return code;
        t = t + when;
        memcpy(s->q, s->q_cross, size);
        memcpy(s->qd, s->qd_cross, size);
        if ((code = contact(r, t, s->q, s->qd, held)) != 0)
            return code;
        if (t >= end) {
            memcpy(q1, s->q, size);
            memcpy(qd1, s->qd, size);
            return 0;
        }
        if ((code = release(r, t, s->q, s->qd, held, &touched)) != 0)
            return code;
    }
    if ((code = step_held(r, scheme, t, s->q, s->qd, end - t, s->q_end, s->qd_end, stage)) != 0)
        return code;                               /* more contacts than a step can hold: the rest as it comes */
    if ((code = contact(r, end, s->q_end, s->qd_end, held)) != 0)
        return code;
    memcpy(q1, s->q_end, size);
    memcpy(qd1, s->qd_end, size);
    return 0;
}

/* _integrate_with_stops for one member's samples k0 … k1: a start on a limit a contact at the first sample;
   each step from the joints the state releases, taken whole or to each crossing and on; Θ, Θ̇ after k0, and Θ̈,
   τ, λ at each sample, the joints held (1.0 or 0.0) as each step ended. 0, or the failing code. */
static int stopping(rollout_t *r, int scheme, const double *times, Py_ssize_t stride, double *q, double *qd,
                    double *qdd, double *tau, double *held, double *reaction, Py_ssize_t member, Py_ssize_t k0,
                    Py_ssize_t k1, double *stage)
{
    stops_t *s = r->stops;
    const Py_ssize_t n = r->n;
    int code, touched;
    s->member = (double)member;
    for (Py_ssize_t j = 0; j < n; j++)
        s->now[j] = held[k0 * stride + j] != 0.0;
    if (k0 == 0 && sides(s, q)) {
        if ((code = contact(r, times[0], q, qd, s->now)) != 0)
            return code;
        for (Py_ssize_t j = 0; j < n; j++)
            held[j] = s->now[j];
    }
    for (Py_ssize_t k = k0; k <= k1; k++) {
        double *x = q + k * stride, *v = qd + k * stride, *a1 = qdd + k * stride, *lambda = reaction + k * stride;
        for (Py_ssize_t j = 0; j < n; j++)
            s->now[j] = held[k * stride + j] != 0.0;
        if ((code = release(r, times[k], x, v, s->now, &touched)) != 0)
            return code;
        for (Py_ssize_t j = 0; j < n; j++)
            lambda[j] = touched ? s->reaction[j] : 0.0;
        r->held = s->now;
        if ((code = accelerations(r, times[k], x, v, a1, tau + k * stride)) != 0 || k == k1)
            return code;
        double *x1 = q + (k + 1) * stride, *v1 = qd + (k + 1) * stride;
        const double h = times[k + 1] - times[k];
        if ((code = advance(r, scheme, times[k], x, v, a1, h, x1, v1, stage)) != 0)
            return code;
        if (beyond(s, x1, s->now) > 0 && (code = substeps(r, scheme, times[k], x, v, h, s->now, x1, v1, stage)))
            return code;
        for (Py_ssize_t j = 0; j < n; j++)
            held[(k + 1) * stride + j] = s->now[j];
    }
    return 0;
}
"""

__all__ = ["C", "MAXIMUM_CONTACTS_PER_STEP", "POSITION_TOLERANCE"]
