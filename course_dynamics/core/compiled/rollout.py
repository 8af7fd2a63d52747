"""The whole simulation in one native call: the C of the fixed-step integrators, written by hand around the
mass matrix and the bias, and shipped in the native loop's library (``looped.c``).

:func:`~course_dynamics.tools.simulation.simulate` hands a run to this C when nothing in it needs Python (a
torque that is zero, constant or a :class:`~course_dynamics.tools.simulation.TorqueTable`; a fixed-step
integrator; our dynamics); :func:`~course_dynamics.core.compiled.looped.rollout` calls it, in chunks of
steps. Every step is the one :mod:`~course_dynamics.tools.simulation` takes in Python, operation for
operation:

====================  =============================================================================
part                  what the C does at a time t and a state (Θ, Θ̇)
====================  =============================================================================
torque                τ(t) from the table's rows (t, τ): linear in t between rows, held outside them
                      (as ``numpy.interp``)
friction              F(Θ̇) = c sgn(Θ̇) + v Θ̇ (6.112), or c tanh(Θ̇ / smoothing) + v Θ̇
terms                 M(Θ) and V(Θ, Θ̇) + G(Θ): a compiled model's own C (through :data:`TERMS`) or
                      the native loop's ``crba`` and ``rnea`` over the model array
accelerations         Θ̈ = (M + diag(Iₐ))⁻¹ (τ − F − (V + G + τ₀)) (6.114)–(6.115), by the LDLᵀ
                      factorization the compiled models unroll (``tracing``), its pivots tested as
                      ``forward_dynamics.SINGULAR_PIVOT_RATIO`` says
integrators           ``euler`` (6.116)–(6.117), ``semi-implicit``, ``rk4``, as :data:`SCHEMES`
recording             Θ and Θ̇ at every sample, and Θ̈ and τ at each step's start (and the last sample)
joint stops           with ``limits="stop"``, the steps, crossings, impulses and held joints of
                      :mod:`~course_dynamics.core.compiled.stopping` around these accelerations
====================  =============================================================================

A run stops at the first state (or its terms, or Θ̈) that is not finite, a torque that is not, or a mass matrix
its pivots show singular, and says where in its status (:data:`STATUS`); an ensemble's members all run, so
that the failure it gives is the earliest in time however the members are shared over threads; the caller
names the problem (the checked path raises
:class:`~course_dynamics.core.forward_dynamics.SingularMassMatrixError`, naming the joint).

A compiled model's library (:mod:`~course_dynamics.core.compiled.native`) holds its M and bias functions in a
capsule, ``terms``, whose layout is :data:`TERMS`, the same C text in both libraries.
"""
from __future__ import annotations

from ..forward_dynamics import SINGULAR_PIVOT_RATIO

#: The integrators the native run offers, by the code the C takes.
SCHEMES = {"euler": 0, "semi-implicit": 1, "rk4": 2}
#: What the first entry of a run's status means.
STATUS = {0: "done", 1: "not finite", 2: "singular", 3: "torque not finite"}
#: The name of the capsule that carries a compiled model's programs for one state.
CAPSULE = "course_dynamics.terms"

#: The layout of the capsule, a compiled model's programs for one state with the scratch the largest needs.
TERMS = r"""
typedef struct {
    int version;                 /* 2 */
    Py_ssize_t n, bodies;        /* coordinates, moving bodies */
    void (*tau)(const double *restrict q, const double *restrict qd, const double *restrict qdd,
                double *restrict scratch, double *restrict out);
    void (*mass_matrix)(const double *restrict q, double *restrict scratch, double *restrict out);
    void (*bias)(const double *restrict q, const double *restrict qd, double *restrict scratch,
                 double *restrict out);
    void (*forward_dynamics)(const double *restrict q, const double *restrict qd, const double *restrict tau,
                             double *restrict scratch, double *restrict out);   /* Θ̈, then the n pivots */
    void (*regressor)(const double *restrict q, const double *restrict qd, const double *restrict qdd,
                      double *restrict scratch, double *restrict out);           /* NULL: over its bound */
    Py_ssize_t scratch;          /* doubles, for any of them */
} course_dynamics_terms;
"""

#: The run, written by hand around the terms (the integrators of :mod:`~course_dynamics.tools.simulation`).
C = r"""
/* ---- the whole simulation in one call (written by hand: the integrators, not their equations) ---- */

#define SINGULAR_PIVOT_RATIO """ + repr(SINGULAR_PIVOT_RATIO) + "\n" + TERMS + r"""
typedef struct stops_s stops_t;          /* joint stops (limits="stop"): stopping.C */
typedef struct {
    Py_ssize_t n, bodies;
    const course_dynamics_terms *terms;  /* a compiled model's own C, or NULL: the loop over model */
    const double *model;
    double *work;                        /* the loop's blocks, or the compiled functions' scratch */
    const double *table;                 /* rows of (t, τ) */
    Py_ssize_t rows;
    const double *smoothing, *viscous, *coulomb, *armature, *offset;
    double *M, *saved, *D, *rhs, *driving, *bias;  /* n × n twice (M before its factorization), then n each */
    stops_t *stops;                      /* NULL without joint stops */
    const int *held;                     /* the joints held during a step (stops), or NULL */
    double *reaction;                    /* their reaction λ at the last accelerations */
    double when, *failed;                /* the last evaluation that failed: its time; Θ, Θ̇ and τ − F there */
} rollout_t;

static void held_accelerations(stops_t *s, const double *M, const double *bias, const double *tau,
                               const int *held, double *qdd, double *reaction);

static int all_finite(const double *x, Py_ssize_t n)
{
    for (Py_ssize_t j = 0; j < n; j++)
        if (!isfinite(x[j]))
            return 0;
    return 1;
}

/* τ(t) as numpy.interp gives it: linear in t between the table's rows (a row's own value at its time, the other
   end's line where one overflows), held at the first and last row outside them; 0 where a value is not finite. */
static int applied(const rollout_t *r, double t, double *tau)
{
    const Py_ssize_t n = r->n, w = n + 1, last = r->rows - 1;
    const double *T = r->table;
    if (r->rows == 1 || t <= T[0]) {
        memcpy(tau, T + 1, sizeof(double) * n);
        return 1;
    }
    if (t >= T[last * w]) {
        memcpy(tau, T + last * w + 1, sizeof(double) * n);
        return 1;
    }
    Py_ssize_t lo = 0, hi = last;  /* T[lo] <= t < T[hi] */
    while (hi - lo > 1) {
        Py_ssize_t mid = lo + (hi - lo) / 2;
        if (T[mid * w] <= t)
            lo = mid;
        else
            hi = mid;
    }
    const double *a = T + lo * w, *b = T + hi * w;
    for (Py_ssize_t j = 0; j < n; j++) {
        if (a[0] == t) {
            tau[j] = a[1 + j];
            continue;
        }
        const double slope = (b[1 + j] - a[1 + j]) / (b[0] - a[0]);
        tau[j] = slope * (t - a[0]) + a[1 + j];
        if (isnan(tau[j])) {
            tau[j] = slope * (t - b[0]) + b[1 + j];
            if (isnan(tau[j]) && a[1 + j] == b[1 + j])
                tau[j] = a[1 + j];
        }
    }
    return all_finite(tau, n);
}

/* Whether an LDLᵀ factorization's pivots show M regular, as the checked solve tests them: the smallest above
   SINGULAR_PIVOT_RATIO times the largest in size. */
static int regular(const double *pivots, Py_ssize_t n)
{
    double largest = 0.0, smallest = INFINITY;
    for (Py_ssize_t j = 0; j < n; j++) {
        largest = fabs(pivots[j]) > largest ? fabs(pivots[j]) : largest;
        smallest = pivots[j] < smallest ? pivots[j] : smallest;
    }
    return smallest > SINGULAR_PIVOT_RATIO * largest;
}

/* V(Θ, Θ̇) + G(Θ) + τ₀ into bias: the run's bias, its drives' offsets added as drives.Driven adds them */
static void bias_at(const rollout_t *r, const double *q, const double *qd, double *bias)
{
    if (r->terms != NULL)
        r->terms->bias(q, qd, r->work, bias);
    else
        rnea(r->model, r->bodies, r->n, q, qd, NULL, r->work, bias);
    for (Py_ssize_t j = 0; j < r->n; j++)
        bias[j] = bias[j] + r->offset[j];
}

/* M(Θ) + diag(Iₐ) into M and bias_at's bias: the run's mass matrix and bias, its drives added as Driven adds them */
static void dynamics(const rollout_t *r, const double *q, const double *qd, double *M, double *bias)
{
    const Py_ssize_t n = r->n;
    if (r->terms != NULL)
        r->terms->mass_matrix(q, r->work, M);
    else
        crba(r->model, r->bodies, n, q, r->work, M);
    bias_at(r, q, qd, bias);
    for (Py_ssize_t j = 0; j < n; j++)
        M[j * n + j] = M[j * n + j] + r->armature[j];
}

/* τ(t) into tau and the driving torques τ − F(Θ̇) (6.114) into drive (τ itself where τ is not finite: 0) */
static int driving(const rollout_t *r, double t, const double *qd, double *tau, double *drive)
{
    const Py_ssize_t n = r->n;
    if (!applied(r, t, tau)) {
        memcpy(drive, tau, sizeof(double) * n);
        return 0;
    }
    const double s = r->smoothing[0];
    for (Py_ssize_t j = 0; j < n; j++) {
        const double sign = s > 0 ? tanh(qd[j] / s) : (double)((qd[j] > 0) - (qd[j] < 0));
        drive[j] = tau[j] - (r->coulomb[j] * sign + r->viscous[j] * qd[j]);
    }
    return 1;
}

/* M = L D Lᵀ, L unit lower triangular (kept in M's lower triangle), as tracing's _ldl_solve */
static void ldl(double *M, double *D, Py_ssize_t n)
{
    for (Py_ssize_t j = 0; j < n; j++) {
        double sum = 0.0;
        for (Py_ssize_t k = 0; k < j; k++)
            sum = sum + M[j * n + k] * M[j * n + k] * D[k];
        D[j] = M[j * n + j] - sum;
        for (Py_ssize_t i = j + 1; i < n; i++) {
            double part = 0.0;
            for (Py_ssize_t k = 0; k < j; k++)
                part = part + M[i * n + k] * M[j * n + k] * D[k];
            M[i * n + j] = (M[i * n + j] - part) / D[j];
        }
    }
}

/* x = (L D Lᵀ)⁻¹ rhs from ldl's factors (rhs overwritten) */
static void ldl_solve(const double *M, const double *D, double *rhs, double *x, Py_ssize_t n)
{
    for (Py_ssize_t i = 0; i < n; i++) {
        double sum = 0.0;
        for (Py_ssize_t k = 0; k < i; k++)
            sum = sum + M[i * n + k] * rhs[k];
        rhs[i] = rhs[i] - sum;
    }
    for (Py_ssize_t i = n - 1; i >= 0; i--) {
        double sum = 0.0;
        for (Py_ssize_t k = i + 1; k < n; k++)
            sum = sum + M[k * n + i] * x[k];
        x[i] = rhs[i] / D[i] - sum;
    }
}

/* An evaluation that failed: its code, with its time and state kept for the caller (τ − F, or τ for code 3) */
static int failing(rollout_t *r, int code, double t, const double *q, const double *qd, const double *drive)
{
    r->when = t;
    memcpy(r->failed, q, sizeof(double) * r->n);
    memcpy(r->failed + r->n, qd, sizeof(double) * r->n);
    memcpy(r->failed + 2 * r->n, drive, sizeof(double) * r->n);
    return code;
}

static int any(const int *x, Py_ssize_t n)
{
    for (Py_ssize_t j = 0; j < n; j++)
        if (x[j])
            return 1;
    return 0;
}

/* Θ̈ at (t, Θ, Θ̇), and τ(t): 0, or the code of STATUS: 1 for a state, its terms or Θ̈ not finite, 2 for a
   singular mass matrix, 3 for a torque not finite. With joints held (r->held), Θ̈ is the constrained one after
   the free one is found regular (as StopRun.accelerations), and r->reaction their reaction. */
static int accelerations(rollout_t *r, double t, const double *q, const double *qd, double *qdd, double *tau)
{
    const Py_ssize_t n = r->n;
    double *M = r->M, *rhs = r->rhs;
    if (!all_finite(q, n) || !all_finite(qd, n))
        return failing(r, 1, t, q, qd, r->driving);
    if (!driving(r, t, qd, tau, r->driving))
        return failing(r, 3, t, q, qd, r->driving);
    dynamics(r, q, qd, M, r->bias);
    for (Py_ssize_t j = 0; j < n; j++)
        rhs[j] = r->driving[j] - r->bias[j];                                 /* (6.115) */
    if (!all_finite(M, n * n) || !all_finite(rhs, n))
        return failing(r, 1, t, q, qd, r->driving);
    const int holding = r->held != NULL && any(r->held, n);
    if (holding)
        memcpy(r->saved, M, sizeof(double) * (size_t)(n * n));
    ldl(M, r->D, n);
    if (!regular(r->D, n))
        return failing(r, 2, t, q, qd, r->driving);
    ldl_solve(M, r->D, rhs, qdd, n);
    if (holding)
        held_accelerations(r->stops, r->saved, r->bias, r->driving, r->held, qdd, r->reaction);
    return all_finite(qdd, n) ? 0 : failing(r, 1, t, q, qd, r->driving);
}

/* Θ and Θ̇ (x1, v1) a step h after (t, x, v), whose Θ̈ a1 is known, by the scheme: 0, or the code of the
   evaluation that failed */
static int advance(rollout_t *r, int scheme, double t, const double *x, const double *v, const double *a1,
                   double h, double *x1, double *v1, double *stage)
{
    const Py_ssize_t n = r->n;
    double *q2 = stage, *qd2 = stage + n, *q3 = stage + 2 * n, *qd3 = stage + 3 * n, *q4 = stage + 4 * n;
    double *qd4 = stage + 5 * n, *a2 = stage + 6 * n, *a3 = stage + 7 * n, *a4 = stage + 8 * n;
    double *unused = stage + 9 * n;
    int code;
    if (scheme == 0) {                                                       /* (6.116)–(6.117) */
        for (Py_ssize_t j = 0; j < n; j++) {
            v1[j] = v[j] + a1[j] * h;
            x1[j] = x[j] + v[j] * h + 0.5 * a1[j] * (h * h);
        }
        return 0;
    }
    if (scheme == 1) {                                                       /* semi-implicit */
        for (Py_ssize_t j = 0; j < n; j++) {
            v1[j] = v[j] + a1[j] * h;
            x1[j] = x[j] + v1[j] * h;
        }
        return 0;
    }
    for (Py_ssize_t j = 0; j < n; j++) {                                     /* rk4 */
        q2[j] = x[j] + 0.5 * h * v[j];
        qd2[j] = v[j] + 0.5 * h * a1[j];
    }
    if ((code = accelerations(r, t + 0.5 * h, q2, qd2, a2, unused)) != 0)
        return code;
    for (Py_ssize_t j = 0; j < n; j++) {
        q3[j] = x[j] + 0.5 * h * qd2[j];
        qd3[j] = v[j] + 0.5 * h * a2[j];
    }
    if ((code = accelerations(r, t + 0.5 * h, q3, qd3, a3, unused)) != 0)
        return code;
    for (Py_ssize_t j = 0; j < n; j++) {
        q4[j] = x[j] + h * qd3[j];
        qd4[j] = v[j] + h * a3[j];
    }
    if ((code = accelerations(r, t + h, q4, qd4, a4, unused)) != 0)
        return code;
    const double sixth = h / 6;
    for (Py_ssize_t j = 0; j < n; j++) {
        x1[j] = x[j] + sixth * (v[j] + 2 * qd2[j] + 2 * qd3[j] + qd4[j]);
        v1[j] = v[j] + sixth * (a1[j] + 2 * a2[j] + 2 * a3[j] + a4[j]);
    }
    return 0;
}

/* One member's samples k0 … k1 (Θ and Θ̇ at k0 given): Θ and Θ̇ after k0, Θ̈ and τ at each. 0, or the code of
   the evaluation that failed (its time and state in r->when and r->failed). */
static int integrate(rollout_t *r, int scheme, const double *times, Py_ssize_t stride, double *q, double *qd,
                     double *qdd, double *tau, Py_ssize_t k0, Py_ssize_t k1, double *stage)
{
    int code = 0;
    for (Py_ssize_t k = k0; k <= k1; k++) {
        double *x = q + k * stride, *v = qd + k * stride, *a1 = qdd + k * stride;
        if ((code = accelerations(r, times[k], x, v, a1, tau + k * stride)) != 0 || k == k1)
            break;
        if ((code = advance(r, scheme, times[k], x, v, a1, times[k + 1] - times[k], q + (k + 1) * stride,
                            qd + (k + 1) * stride, stage)) != 0)
            break;
    }
    return code;
}

static int stopping(rollout_t *r, int scheme, const double *times, Py_ssize_t stride, double *q, double *qd,
                    double *qdd, double *tau, double *held, double *reaction, Py_ssize_t member, Py_ssize_t k0,
                    Py_ssize_t k1, double *stage);
static stops_t *stops_new(Py_ssize_t n, const double *bounds);
static PyObject *stops_found(stops_t *s, PyObject *records, int code);
static void stops_free(stops_t *s);

/* rollout(terms, times, q, qd, qdd, tau, table, parameters, status, scheme, k0, k1, m0, m1
           [, held, reaction, bounds, records]): members m0 … m1 − 1 from sample k0 to k1, the GIL released; the
   code (STATUS) of the earliest failure (the first member of those failing at once), with status = (code,
   member or −1, t, Θ, Θ̇, τ − F or τ). With joint stops (the four last): the joints held at each sample (1.0 or
   0.0), their reaction λ, the bounds (dt, lower, upper) and a list the stops found are appended to (as bytes,
   rows of STOP_RECORD). */
static PyObject *rollout(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    Py_buffer views[12];
    Py_ssize_t first = 0, got = 0, integers[5];
    PyObject *result = NULL;
    double *model = NULL, *work = NULL, *scratch = NULL;
    const course_dynamics_terms *terms = NULL;
    stops_t *stops = NULL;
    rollout_t r;
    memset(&r, 0, sizeof r);
    if (nargs != 14 && nargs != 18) {
        PyErr_SetString(PyExc_TypeError, "rollout takes the terms, eight arrays and five integers (and, with "
                                         "joint stops, three arrays and a list)");
        return NULL;
    }
    const Py_ssize_t views_wanted = nargs == 18 ? 12 : 9;
    if (nargs == 18 && !PyList_CheckExact(args[17])) {
        PyErr_SetString(PyExc_TypeError, "rollout: the stops found go to a list");
        return NULL;
    }
    for (Py_ssize_t i = 0; i < 5; i++) {
        integers[i] = PyLong_AsSsize_t(args[9 + i]);
        if (integers[i] == -1 && PyErr_Occurred())
            return NULL;
    }
    if (PyCapsule_CheckExact(args[0])) {           /* a compiled model's own C */
        if ((terms = PyCapsule_GetPointer(args[0], "course_dynamics.terms")) == NULL)
            return NULL;
        if (terms->version != 2 || terms->n < 1 || terms->n > 100000 || terms->scratch < 0) {
            PyErr_SetString(PyExc_ValueError, "rollout: the compiled model's terms are not ones the library made");
            return NULL;
        }
        first = got = 1;
    }
    for (; got < views_wanted; got++) {            /* the model array (the loop), times … status, held … bounds */
        const int writable = (got >= 2 && got <= 5) || got == 8 || got == 9 || got == 10;
        if (PyObject_GetBuffer(args[got < 9 ? got : got + 5], &views[got], PyBUF_C_CONTIGUOUS | PyBUF_FORMAT
                               | (writable ? PyBUF_WRITABLE : 0)) != 0)
            goto done;
        if (views[got].itemsize != 8 || strcmp(views[got].format, "d") != 0) {
            PyErr_SetString(PyExc_TypeError, "rollout takes C-contiguous float64 arrays");
            got++;
            goto done;
        }
    }
    size_t size;
    if (terms) {
        r.n = terms->n;
        size = (size_t)terms->scratch + 1;
    } else {                                       /* copied before it is checked, as the loops' wrappers do */
        if ((model = malloc(views[0].len ? (size_t)views[0].len : 1)) == NULL) {
            PyErr_NoMemory();
            goto done;
        }
        memcpy(model, views[0].buf, (size_t)views[0].len);
        if (check_model(model, views[0].len / 8, &r.bodies, &r.n) != 0)
            goto done;
        size = (size_t)r.bodies * (RNEA_BLOCK > CRBA_BLOCK ? RNEA_BLOCK : CRBA_BLOCK);
    }
    if ((work = malloc(sizeof(double) * size)) == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    const Py_ssize_t n = r.n, T = views[1].len / 8;
    const Py_ssize_t scheme = integers[0], k0 = integers[1], k1 = integers[2], m0 = integers[3], m1 = integers[4];
    const double *times = views[1].buf, *parameters = views[7].buf;
    const Py_ssize_t K = T > 0 ? views[2].len / (8 * T * n) : 0;
    int bad = T < 2 || K < 1 || scheme < 0 || scheme > 2 || k0 < 0 || k1 < k0 || k1 > T - 1 || m0 < 0 || m1 < m0
              || m1 > K || views[7].len != 8 * (4 * n + 1) || views[6].len % (8 * (n + 1)) != 0
              || views[6].len == 0 || views[8].len != 8 * (3 + 3 * n)
              || (views_wanted == 12 && views[11].len != 8 * (1 + 2 * n));
    for (Py_ssize_t i = 2; i <= 5 && !bad; i++)
        bad = views[i].len != 8 * T * K * n;
    for (Py_ssize_t i = 9; i <= 10 && i < views_wanted && !bad; i++)
        bad = views[i].len != 8 * T * K * n;
    if (bad) {
        PyErr_SetString(PyExc_ValueError, "rollout: the arrays' sizes do not fit one another");
        goto done;
    }
    r.rows = views[6].len / (8 * (n + 1));
    r.table = views[6].buf;
    int ordered = all_finite(times, T) && all_finite(r.table, r.rows * (n + 1)) && all_finite(parameters, 4 * n + 1)
                  && parameters[0] >= 0;
    for (Py_ssize_t k = 1; k < T && ordered; k++)
        ordered = times[k] > times[k - 1];
    for (Py_ssize_t k = 1; k < r.rows && ordered; k++)
        ordered = r.table[k * (n + 1)] > r.table[(k - 1) * (n + 1)];
    if (views_wanted == 12) {                      /* dt finite and positive, each joint's lower below its upper */
        const double *bounds = views[11].buf;
        ordered = ordered && isfinite(bounds[0]) && bounds[0] > 0;
        for (Py_ssize_t j = 0; j < n && ordered; j++)
            ordered = bounds[1 + j] < bounds[1 + n + j];
    }
    if (!ordered) {
        PyErr_SetString(PyExc_ValueError, "rollout: the times, the table, the parameters or the bounds are not in "
                                          "order");
        goto done;
    }
    if ((scratch = malloc(sizeof(double) * (size_t)(2 * n * n + 20 * n))) == NULL
        || (views_wanted == 12 && (stops = stops_new(n, views[11].buf)) == NULL)) {
        PyErr_NoMemory();
        goto done;
    }
    r.terms = terms, r.model = model, r.work = work, r.stops = stops;
    r.smoothing = parameters, r.viscous = parameters + 1, r.coulomb = parameters + 1 + n;
    r.armature = parameters + 1 + 2 * n, r.offset = parameters + 1 + 3 * n;
    r.M = scratch, r.saved = scratch + n * n, r.D = r.saved + n * n, r.rhs = r.D + n, r.driving = r.rhs + n;
    r.bias = r.driving + n, r.reaction = r.bias + n, r.failed = r.reaction + n;
    double *stage = r.failed + 3 * n, *status = views[8].buf, when = 0.0;
    double *q = views[2].buf, *qd = views[3].buf, *qdd = views[4].buf, *tau = views[5].buf;
    int code = 0;
    Py_ssize_t member = -1;
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t m = m0; m < m1; m++) {         /* every member, so that the earliest failure is found */
        const int c = stops == NULL
            ? integrate(&r, (int)scheme, times, K * n, q + m * n, qd + m * n, qdd + m * n, tau + m * n, k0, k1, stage)
            : stopping(&r, (int)scheme, times, K * n, q + m * n, qd + m * n, qdd + m * n, tau + m * n,
                       (double *)views[9].buf + m * n, (double *)views[10].buf + m * n, m, k0, k1, stage);
        if (c != 0 && (code == 0 || r.when < when)) {
            code = c, member = m, when = r.when;
            memcpy(status + 3, r.failed, sizeof(double) * 3 * (size_t)n);
        }
    }
    Py_END_ALLOW_THREADS
    status[0] = code, status[1] = (double)member, status[2] = when;
    result = stops == NULL ? PyLong_FromLong(code) : stops_found(stops, args[17], code);
done:
    stops_free(stops);
    free(scratch);
    free(work);
    free(model);
    for (Py_ssize_t i = first; i < got; i++)
        PyBuffer_Release(&views[i]);
    return result;
}
"""

__all__ = ["C", "CAPSULE", "SCHEMES", "STATUS", "TERMS"]
