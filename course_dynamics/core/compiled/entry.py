"""The one-state entry: a model's one-state call checked, dispatched and computed in one native call.

A user's loop of one-state calls, ``inverse_dynamics(model, q, qd, qdd)`` and the rest, spends more time in
Python deciding what runs and checking the arguments than in the arithmetic: the evaluator
(:mod:`~course_dynamics.core.evaluator`) remembers, for a model whose choice runs native code, the C that runs
it; this C, in the native loop's library (``looped.c``), then takes each later one-state call whole:

====================  =============================================================================
part                  what the C does, in the order it does it
====================  =============================================================================
the model             finds the entry the evaluator remembered for this very model object (by its
                      identity, behind a weak reference), else gives None
the choice            gives None unless every environment variable the choice was made under (the
                      cache folder's and ``COURSE_DYNAMICS_NATIVE``) and the cache's count of writes
                      are what they were (the same objects), so that the choice depends on the call
                      and the environment now, never on what ran before
the arguments         gives None unless each is a C-contiguous float64 buffer of one state, n finite
                      values (anything else, a list, a batch, a NaN, is the checked path's to refuse)
the program           runs a compiled model's own C (its library's capsule, ``terms``:
                      :data:`~course_dynamics.core.compiled.rollout.TERMS`), or the native loop over a
                      copy of the model array checked when the entry was made
the result            a new numpy array: τ (n,), M (n, n), Θ̈ (n,) (None where its pivots show M
                      singular: the checked solve names the joint), Y (n, 10 bodies)
====================  =============================================================================

None is never an answer to the user: it sends the call down the checked path, which gives the same numbers
or the error. The GIL is held throughout (one state is too little work to share), and the output is made
before the work (making it may run Python code, and so another thread), so an entry's scratch is the call's
own while it computes; an entry holds what it was made from (the capsule or the array, and the
implementation), and a call holds its entry, so nothing it points into goes away under it.
"""
from __future__ import annotations

#: The programs the entry runs, by the code the C takes (the loop has the first two).
PROGRAMS = {"tau": 0, "mass_matrix": 1, "forward_dynamics": 2, "regressor": 3}
#: The name of the capsule that holds a remembered entry.
CAPSULE = "course_dynamics.entry"
#: The environment variables an entry is made under, at most (the C's bound).
NAMES = 8

#: The entry, written by hand around the programs (the dispatch, not the dynamics).
C = r"""
/* ---- the one-state entry (written by hand: the evaluator's remembered dispatch, not the dynamics) ---- */

#define ENTRY_NAMES """ + str(NAMES) + r"""

typedef struct {
    PyObject *model;                       /* a weak reference to the model the entry is for */
    PyObject *owner, *source;              /* the implementation, and the capsule or model array (held) */
    PyObject *environ;                     /* os.environ's dict, the names, and their values then (or None) */
    PyObject *names[ENTRY_NAMES], *values[ENTRY_NAMES];
    Py_ssize_t count;
    PyObject *writes, *written;            /* the cache's list of writes, and its first item then */
    PyObject *empty, *vector, *matrix, *rows;  /* numpy.empty; the shapes (n,), (n, n), (n, 10 bodies) */
    const course_dynamics_terms *terms;    /* a compiled model's own C, or NULL: the loop over model */
    double *model_array, *work;            /* the loop's checked copy, and the scratch of either */
    Py_ssize_t bodies, n;
} entry_t;

static PyObject *entries = NULL;           /* id(model) -> the capsule of its entry_t */

static void entry_free(PyObject *capsule)
{
    entry_t *e = PyCapsule_GetPointer(capsule, """ + f'"{CAPSULE}"' + r""");
    if (e == NULL)
        return;
    Py_XDECREF(e->model);
    Py_XDECREF(e->owner);
    Py_XDECREF(e->source);
    Py_XDECREF(e->environ);
    for (Py_ssize_t i = 0; i < ENTRY_NAMES; i++) {
        Py_XDECREF(e->names[i]);
        Py_XDECREF(e->values[i]);
    }
    Py_XDECREF(e->writes);
    Py_XDECREF(e->written);
    Py_XDECREF(e->empty);
    Py_XDECREF(e->vector);
    Py_XDECREF(e->matrix);
    Py_XDECREF(e->rows);
    free(e->model_array);
    free(e->work);
    free(e);
}

/* remember(model, owner, source, environ, names, writes, empty): the entry for model's one-state calls, made
   from the values the environment and the cache's writes have now. */
static PyObject *remember(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs != 7 || !PyDict_Check(args[3]) || !PyTuple_Check(args[4]) || PyTuple_GET_SIZE(args[4]) > ENTRY_NAMES
        || !PyList_Check(args[5]) || PyList_GET_SIZE(args[5]) < 1) {
        PyErr_SetString(PyExc_TypeError, "remember takes the model, its implementation, the terms capsule or model "
                        "array, os.environ's dict, a tuple of names, the cache's writes and numpy.empty");
        return NULL;
    }
    if (entries == NULL && (entries = PyDict_New()) == NULL)
        return NULL;
    entry_t *e = calloc(1, sizeof(entry_t));
    if (e == NULL)
        return PyErr_NoMemory();
    PyObject *capsule = PyCapsule_New(e, """ + f'"{CAPSULE}"' + r""", entry_free), *key = NULL, *result = NULL;
    if (capsule == NULL) {
        free(e);
        return NULL;
    }
    if ((e->model = PyWeakref_NewRef(args[0], NULL)) == NULL)
        goto done;
    e->owner = Py_NewRef(args[1]);
    e->source = Py_NewRef(args[2]);
    e->environ = Py_NewRef(args[3]);
    e->count = PyTuple_GET_SIZE(args[4]);
    for (Py_ssize_t i = 0; i < e->count; i++) {
        PyObject *name = PyTuple_GET_ITEM(args[4], i), *value = PyDict_GetItemWithError(args[3], name);
        if (value == NULL && PyErr_Occurred())
            goto done;
        e->names[i] = Py_NewRef(name);
        e->values[i] = Py_NewRef(value != NULL ? value : Py_None);
    }
    e->writes = Py_NewRef(args[5]);
    e->written = Py_NewRef(PyList_GET_ITEM(args[5], 0));
    e->empty = Py_NewRef(args[6]);
    size_t scratch;
    if (PyCapsule_CheckExact(args[2])) {       /* a compiled model's own C */
        if ((e->terms = PyCapsule_GetPointer(args[2], """ + '"course_dynamics.terms"' + r""")) == NULL)
            goto done;
        if (e->terms->version != 2 || e->terms->n < 1 || e->terms->n > 100000 || e->terms->scratch < 0
            || e->terms->bodies < 0) {
            PyErr_SetString(PyExc_ValueError, "remember: the compiled model's terms are not ones the library made");
            goto done;
        }
        e->n = e->terms->n, e->bodies = e->terms->bodies;
        scratch = (size_t)e->terms->scratch + 2 * (size_t)e->n;  /* and Θ̈ with its pivots */
    } else {                                   /* the loop: the model array copied, then checked */
        Py_buffer view;
        if (PyObject_GetBuffer(args[2], &view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) != 0)
            goto done;
        int fits = view.itemsize == 8 && strcmp(view.format, "d") == 0;
        if (fits && (e->model_array = malloc(view.len ? (size_t)view.len : 1)) != NULL)
            memcpy(e->model_array, view.buf, (size_t)view.len);
        const Py_ssize_t length = view.len / 8;
        PyBuffer_Release(&view);
        if (!fits) {
            PyErr_SetString(PyExc_TypeError, "remember takes a float64 model array");
            goto done;
        }
        if (e->model_array == NULL) {
            PyErr_NoMemory();
            goto done;
        }
        if (check_model(e->model_array, length, &e->bodies, &e->n) != 0)
            goto done;
        scratch = (size_t)e->bodies * (RNEA_BLOCK > CRBA_BLOCK ? RNEA_BLOCK : CRBA_BLOCK);
    }
    if ((e->work = malloc(sizeof(double) * (scratch + 1))) == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    if ((e->vector = Py_BuildValue("(n)", e->n)) == NULL || (e->matrix = Py_BuildValue("(nn)", e->n, e->n)) == NULL
        || (e->rows = Py_BuildValue("(nn)", e->n, 10 * e->bodies)) == NULL)
        goto done;
    if ((key = PyLong_FromVoidPtr(args[0])) == NULL || PyDict_SetItem(entries, key, capsule) != 0)
        goto done;
    result = Py_NewRef(Py_None);
done:
    Py_XDECREF(key);
    Py_DECREF(capsule);
    return result;
}

/* forget(model_id): the entry for the model of that id, if any, no more. */
static PyObject *forget(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs != 1 || !PyLong_Check(args[0])) {
        PyErr_SetString(PyExc_TypeError, "forget takes a model's id");
        return NULL;
    }
    if (entries != NULL && PyDict_DelItem(entries, args[0]) != 0) {
        if (!PyErr_ExceptionMatches(PyExc_KeyError))
            return NULL;
        PyErr_Clear();
    }
    Py_RETURN_NONE;
}

/* The entry remembered for this model object, or NULL (no error) for none: its capsule, a new reference. */
static PyObject *entry_of(PyObject *model)
{
    if (entries == NULL)
        return NULL;
    PyObject *key = PyLong_FromVoidPtr(model);
    if (key == NULL) {
        PyErr_Clear();
        return NULL;
    }
    PyObject *capsule = PyDict_GetItemWithError(entries, key);
    Py_DECREF(key);
    if (capsule == NULL) {
        PyErr_Clear();
        return NULL;
    }
    return Py_NewRef(capsule);
}

/* remembered(model): the implementation the model's entry was made for, or None. */
static PyObject *remembered(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs != 1) {
        PyErr_SetString(PyExc_TypeError, "remembered takes a model");
        return NULL;
    }
    PyObject *capsule = entry_of(args[0]);
    if (capsule == NULL)
        Py_RETURN_NONE;
    entry_t *e = PyCapsule_GetPointer(capsule, """ + f'"{CAPSULE}"' + r""");
    PyObject *owner = Py_NewRef(e != NULL ? e->owner : Py_None);
    Py_DECREF(capsule);
    return owner;
}

/* Whether the entry's model is this object and the environment and the cache's writes are as they were. */
static int entry_holds(const entry_t *e, PyObject *model)
{
#if PY_VERSION_HEX >= 0x030D0000
    PyObject *alive = NULL;
    if (PyWeakref_GetRef(e->model, &alive) < 0)
        PyErr_Clear();
    Py_XDECREF(alive);                     /* the caller holds the model: comparing the pointer is enough */
    if (alive != model)
        return 0;
#else
    if (PyWeakref_GetObject(e->model) != model)
        return 0;
#endif
    for (Py_ssize_t i = 0; i < e->count; i++) {
        PyObject *value = PyDict_GetItemWithError(e->environ, e->names[i]);
        if (value == NULL) {
            if (PyErr_Occurred()) {
                PyErr_Clear();
                return 0;
            }
            value = Py_None;
        }
        if (value != e->values[i])
            return 0;
    }
    return PyList_Check(e->writes) && PyList_GET_SIZE(e->writes) > 0 && PyList_GET_ITEM(e->writes, 0) == e->written;
}

/* An argument as one state: a C-contiguous float64 buffer of n finite values, or 0 (no error). */
static int one_state(PyObject *a, Py_ssize_t n, Py_buffer *view)
{
    if (PyObject_GetBuffer(a, view, PyBUF_ND | PyBUF_FORMAT | PyBUF_C_CONTIGUOUS) != 0) {
        PyErr_Clear();
        return 0;
    }
    const double *x = view->buf;
    int fits = view->ndim == 1 && view->shape[0] == n && view->itemsize == 8 && strcmp(view->format, "d") == 0;
    for (Py_ssize_t j = 0; j < n && fits; j++)
        fits = isfinite(x[j]);
    if (!fits)
        PyBuffer_Release(view);
    return fits;
}

/* one(model, code, *arrays): the program of PROGRAMS' code on one state, a new array; None where the entry does
   not take the call (the checked path then does). */
static PyObject *one(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    static const Py_ssize_t inputs[4] = {3, 1, 3, 3};
    if (nargs < 2 || !PyLong_CheckExact(args[1]))
        Py_RETURN_NONE;
    const long code = PyLong_AsLong(args[1]);
    if (code == -1 && PyErr_Occurred())
        PyErr_Clear();
    if (code < 0 || code > 3 || nargs != 2 + inputs[code])
        Py_RETURN_NONE;
    PyObject *capsule = entry_of(args[0]), *out = NULL;
    if (capsule == NULL)
        Py_RETURN_NONE;
    entry_t *e = PyCapsule_GetPointer(capsule, """ + f'"{CAPSULE}"' + r""");
    Py_buffer views[3], result;
    Py_ssize_t got = 0;
    if (e == NULL) {
        PyErr_Clear();
        goto none;
    }
    const course_dynamics_terms *t = e->terms;
    if (!entry_holds(e, args[0]) || (t == NULL && code > 1) || (t != NULL && code == 3 && t->regressor == NULL))
        goto none;
    const Py_ssize_t n = e->n;
    for (; got < inputs[code]; got++)
        if (!one_state(args[2 + got], n, &views[got]))
            goto none;
    const double *a = views[0].buf, *b = got > 1 ? views[1].buf : NULL, *c = got > 2 ? views[2].buf : NULL;
    PyObject *shape = code == 1 ? e->matrix : code == 3 ? e->rows : e->vector;
    if ((out = PyObject_Vectorcall(e->empty, &shape, 1, NULL)) == NULL)  /* before the work: it may run Python */
        goto done;
    if (PyObject_GetBuffer(out, &result, PyBUF_WRITABLE | PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) != 0) {
        Py_CLEAR(out);
        goto done;
    }
    const Py_ssize_t width = code == 1 ? n * n : code == 3 ? 10 * n * e->bodies : n;
    if (result.len != 8 * width || strcmp(result.format, "d") != 0) {  /* what numpy.empty makes, and no other */
        PyBuffer_Release(&result);
        Py_CLEAR(out);
        PyErr_SetString(PyExc_TypeError, "one: the entry's output is not the float64 array of the program's size");
        goto done;
    }
    double *o = result.buf;
    if (code == 2) {                       /* Θ̈ only where the pivots show M regular, as the checked path tests */
        double *solved = e->work + t->scratch;
        t->forward_dynamics(a, b, c, e->work, solved);
        if (!regular(solved + n, n)) {     /* the rollout's test of the pivots */
            PyBuffer_Release(&result);
            Py_CLEAR(out);
            goto none;
        }
        memcpy(o, solved, sizeof(double) * (size_t)n);
    } else if (t == NULL && code == 0)
        rnea(e->model_array, e->bodies, n, a, b, c, e->work, o);
    else if (t == NULL)
        crba(e->model_array, e->bodies, n, a, e->work, o);
    else if (code == 0)
        t->tau(a, b, c, e->work, o);
    else if (code == 1)
        t->mass_matrix(a, e->work, o);
    else
        t->regressor(a, b, c, e->work, o);
    PyBuffer_Release(&result);
    goto done;
none:
    out = Py_NewRef(Py_None);
done:
    for (Py_ssize_t i = 0; i < got; i++)
        PyBuffer_Release(&views[i]);
    Py_DECREF(capsule);
    return out;
}
"""

__all__ = ["C", "CAPSULE", "NAMES", "PROGRAMS"]
