"""Joint stops in the native run, what one stop does: the C of a stop's impulse through M and of the joints
held at their limits, written by hand after :mod:`~course_dynamics.tools.joint_stops` and shipped in the
native loop's library (``looped.c``); :mod:`~course_dynamics.core.compiled.stopping` takes the steps with them.

Each function is the Python one of the same name, operation for operation, on one state:

=======================  ==========================================================================
C                        what it does (``tools.joint_stops``)
=======================  ==========================================================================
``masked_solve``         a system in some joints only (``_masked_system`` and ``_solve``)
``held_accelerations``   Θ̈ with the held joints' Θ̈ zero, and their reaction λ
``hold``                 the joints held, by least-index principal pivoting (``_pivot``)
``stop_impulse``         Θ̇ after the impulse through M that stops the joints running into a limit
``record``               a stop, as a row of :data:`STOP_RECORD` (``Stop``)
=======================  ==========================================================================

The linear systems are solved by the LDLᵀ factorization the run's forward dynamics uses (numpy's LU in
Python), so the two paths agree to round-off, and their decisions (which joint is stopped or held) are the
same wherever a margin is wider than round-off.
"""
from __future__ import annotations

#: Pivots of a stop's or a hold's complementarity problem before its last solution is taken as it is.
MAXIMUM_PIVOTS = 64
#: A stop as the native run records it, one row of 4 + 2n doubles.
STOP_RECORD = ("t, s", "member", "kinetic energy before, J", "kinetic energy after, J",
               "n sides: +1 a joint stopped at its upper limit, −1 at its lower, 0 not stopped",
               "n joint positions Θ, rad (m)")

#: The C of a run's stop state, and of the impulses and holds on one state.
C = r"""
/* ---- joint stops in the native run: what one stop does (written by hand after tools.joint_stops) ---- */

#define MAXIMUM_PIVOTS """ + str(MAXIMUM_PIVOTS) + r"""

struct stops_s {
    Py_ssize_t n;
    double dt;                       /* the run's step: a joint leaving more slowly than dt Θ̈ into it rests */
    double *lower, *upper;           /* the limits a stop holds (limit_bounds): ∓inf for a joint without */
    double *M, *inverse, *factor, *S;                                          /* n × n each */
    double *bias, *pivots, *Ds, *y, *z, *x, *drive, *tau, *unused, *qdd, *reaction, *impulse, *after;
    double *resting, *allowed, *leaving, *q, *qd, *q_end, *qd_end, *q_cross, *qd_cross, *q_try, *qd_try, *a1;
    int *side, *candidates, *active, *free, *all, *index, *now, *was;
    double *records;                 /* the stops found, 4 + 2n doubles each (STOP_RECORD) */
    Py_ssize_t count, capacity;
    int out_of_memory;
    double member;
};

static stops_t *stops_new(Py_ssize_t n, const double *bounds)
{
    stops_t *s = calloc(1, sizeof(stops_t));
    double *d = s == NULL ? NULL : malloc(sizeof(double) * (size_t)(4 * n * n + 27 * n));
    int *i = d == NULL ? NULL : malloc(sizeof(int) * (size_t)(8 * n));
    if (i == NULL) {
        free(d);
        free(s);
        return NULL;
    }
    double **doubles[] = {&s->lower, &s->upper, &s->bias, &s->pivots, &s->Ds, &s->y, &s->z, &s->x, &s->drive,
                          &s->tau, &s->unused, &s->qdd, &s->reaction, &s->impulse, &s->after, &s->resting,
                          &s->allowed, &s->leaving, &s->q, &s->qd, &s->q_end, &s->qd_end, &s->q_cross,
                          &s->qd_cross, &s->q_try, &s->qd_try, &s->a1};
    int **ints[] = {&s->side, &s->candidates, &s->active, &s->free, &s->all, &s->index, &s->now, &s->was};
    s->n = n, s->dt = bounds[0];
    s->M = d, s->inverse = d + n * n, s->factor = d + 2 * n * n, s->S = d + 3 * n * n;
    for (size_t k = 0; k < sizeof doubles / sizeof doubles[0]; k++)
        *doubles[k] = d + 4 * n * n + (Py_ssize_t)k * n;
    for (size_t k = 0; k < sizeof ints / sizeof ints[0]; k++)
        *ints[k] = i + (Py_ssize_t)k * n;
    memcpy(s->lower, bounds + 1, sizeof(double) * (size_t)n);
    memcpy(s->upper, bounds + 1 + n, sizeof(double) * (size_t)n);
    for (Py_ssize_t j = 0; j < n; j++)
        s->all[j] = 1;
    return s;
}

static void stops_free(stops_t *s)
{
    if (s == NULL)
        return;
    free(s->records);
    free(s->M);
    free(s->side);
    free(s);
}

/* The stops found appended to the list as bytes (STOP_RECORD rows); the run's code, or NULL */
static PyObject *stops_found(stops_t *s, PyObject *records, int code)
{
    if (s->out_of_memory)
        return PyErr_NoMemory();
    PyObject *found = PyBytes_FromStringAndSize((const char *)s->records,
                                                (Py_ssize_t)sizeof(double) * s->count * (4 + 2 * s->n));
    if (found == NULL || PyList_Append(records, found) != 0) {
        Py_XDECREF(found);
        return NULL;
    }
    Py_DECREF(found);
    return PyLong_FromLong(code);
}

/* What counts as zero beside the values of x: 1e-12 of the largest */
static double round_off(const double *x, Py_ssize_t n)
{
    double largest = 0.0;
    for (Py_ssize_t j = 0; j < n; j++)
        largest = fabs(x[j]) > largest ? fabs(x[j]) : largest;
    return 1e-12 * (1e-300 + largest);
}

/* x = the solution of A's rows and columns of the joints in mask with rhs's entries there, 0 elsewhere
   (_masked_system and _solve), by LDLᵀ of that principal block */
static void masked_solve(stops_t *s, const double *A, const int *mask, const double *rhs, double *x)
{
    const Py_ssize_t n = s->n;
    Py_ssize_t m = 0;
    for (Py_ssize_t j = 0; j < n; j++)
        if (mask[j])
            s->index[m++] = j;
    for (Py_ssize_t a = 0; a < m; a++) {
        for (Py_ssize_t b = 0; b < m; b++)
            s->S[a * m + b] = A[s->index[a] * n + s->index[b]];
        s->y[a] = rhs[s->index[a]];
    }
    ldl(s->S, s->Ds, m);
    ldl_solve(s->S, s->Ds, s->y, s->z, m);
    for (Py_ssize_t j = 0; j < n; j++)
        x[j] = 0.0;
    for (Py_ssize_t a = 0; a < m; a++)
        x[s->index[a]] = s->z[a];
}

/* held_accelerations: M Θ̈ + b = τ + E λ with Eᵀ Θ̈ = 0, the free joints' rows solved with the held joints' Θ̈
   zero, and λ what the held joints' rows then lack */
static void held_accelerations(stops_t *s, const double *M, const double *bias, const double *tau,
                               const int *held, double *qdd, double *reaction)
{
    const Py_ssize_t n = s->n;
    for (Py_ssize_t j = 0; j < n; j++) {
        s->x[j] = tau[j] - bias[j];
        s->free[j] = !held[j];
    }
    masked_solve(s, M, s->free, s->x, qdd);
    for (Py_ssize_t j = 0; j < n; j++) {
        double sum = 0.0;
        for (Py_ssize_t k = 0; held[j] && k < n; k++)
            sum = sum + M[j * n + k] * qdd[k];
        reaction[j] = held[j] ? sum - s->x[j] : 0.0;
    }
}

/* hold: of the candidates, the joints held (into held), with Θ̈ and λ: every held joint pushed by its reaction
   (dᵢ λᵢ ≤ 0), every other candidate accelerating away from its limit (dᵢ Θ̈ᵢ ≤ 0) */
static void hold(stops_t *s, const double *M, const double *bias, const double *tau, const int *candidates,
                 int *held, double *qdd, double *reaction)
{
    const Py_ssize_t n = s->n;
    double largest = 0.0;
    for (Py_ssize_t j = 0; j < n; j++)
        largest = fabs(tau[j] - bias[j]) > largest ? fabs(tau[j] - bias[j]) : largest;
    const double scale = 1e-12 * (1e-300 + largest);
    memcpy(held, candidates, sizeof(int) * (size_t)n);
    for (int p = 0; p < MAXIMUM_PIVOTS; p++) {
        held_accelerations(s, M, bias, tau, held, qdd, reaction);
        const double moving = round_off(qdd, n);
        Py_ssize_t bad = -1;
        for (Py_ssize_t j = 0; j < n && bad < 0; j++)
            if ((held[j] && s->side[j] * reaction[j] > scale)
                || (candidates[j] && !held[j] && s->side[j] * qdd[j] > moving))
                bad = j;
        if (bad < 0)
            break;
        held[bad] = !held[bad];
    }
}

/* stop_impulse: Θ̇⁺ (after) just after the impulse P (impulse) through M that stops the joints in stopped, of
   the candidates: each stopped joint's impulse pushing (dᵢ Pᵢ ≤ 0, a resting joint's pulling at most its rate's
   worth), every other candidate leaving its limit (dᵢ Θ̇⁺ᵢ ≤ 0) */
static void stop_impulse(stops_t *s, const double *M, const double *qd, const int *candidates,
                         const double *resting, double *after, int *stopped, double *impulse)
{
    const Py_ssize_t n = s->n;
    double *inverse = s->inverse;
    memcpy(s->factor, M, sizeof(double) * (size_t)(n * n));
    ldl(s->factor, s->pivots, n);
    for (Py_ssize_t c = 0; c < n; c++) {                                      /* M⁻¹, column by column */
        for (Py_ssize_t j = 0; j < n; j++)
            s->y[j] = j == c;
        ldl_solve(s->factor, s->pivots, s->y, s->z, n);
        for (Py_ssize_t j = 0; j < n; j++)
            inverse[j * n + c] = s->z[j];
    }
    const double small = round_off(qd, n);
    for (Py_ssize_t j = 0; j < n; j++) {
        s->leaving[j] = resting[j] > 0 ? -resting[j] : small;
        s->allowed[j] = (small + resting[j]) / inverse[j * n + j];
    }
    memcpy(stopped, candidates, sizeof(int) * (size_t)n);
    for (int p = 0; p < MAXIMUM_PIVOTS; p++) {
        for (Py_ssize_t j = 0; j < n; j++)
            s->x[j] = -qd[j];
        masked_solve(s, inverse, stopped, s->x, impulse);
        for (Py_ssize_t j = 0; j < n; j++) {
            double sum = 0.0;
            for (Py_ssize_t k = 0; !stopped[j] && k < n; k++)
                sum = sum + inverse[j * n + k] * impulse[k];
            after[j] = stopped[j] ? 0.0 : qd[j] + sum;
        }
        Py_ssize_t bad = -1;
        for (Py_ssize_t j = 0; j < n && bad < 0; j++)
            if ((stopped[j] && s->side[j] * impulse[j] > s->allowed[j])
                || (candidates[j] && !stopped[j] && s->side[j] * after[j] > s->leaving[j]))
                bad = j;
        if (bad < 0)
            break;
        stopped[bad] = !stopped[bad];
    }
}

/* ½ Θ̇ᵀ M Θ̇, J */
static double kinetic(const double *M, const double *qd, Py_ssize_t n)
{
    double energy = 0.0;
    for (Py_ssize_t i = 0; i < n; i++) {
        double row = 0.0;
        for (Py_ssize_t k = 0; k < n; k++)
            row = row + 0.5 * qd[k] * M[k * n + i];
        energy = energy + row * qd[i];
    }
    return energy;
}

/* A stop recorded (STOP_RECORD): the joints stopped now that were not held */
static void record(stops_t *s, double t, const double *q, const int *held, double before, double after)
{
    const Py_ssize_t n = s->n, width = 4 + 2 * n;
    if (s->count == s->capacity) {
        const Py_ssize_t capacity = s->capacity ? 2 * s->capacity : 16;
        double *grown = capacity > PY_SSIZE_T_MAX / (Py_ssize_t)sizeof(double) / width ? NULL
                        : realloc(s->records, sizeof(double) * (size_t)(capacity * width));
        if (grown == NULL) {
            s->out_of_memory = 1;
            return;
        }
        s->records = grown, s->capacity = capacity;
    }
    double *row = s->records + s->count * width;
    row[0] = t, row[1] = s->member, row[2] = before, row[3] = after;
    for (Py_ssize_t j = 0; j < n; j++) {
        row[4 + j] = s->active[j] && !held[j] ? (double)s->side[j] : 0.0;
        row[4 + n + j] = q[j];
    }
    s->count++;
}

"""

__all__ = ["C", "MAXIMUM_PIVOTS", "STOP_RECORD"]
