// SPDX-License-Identifier: MIT
// The Python extension over gaussfilt's C library: compiled once per
// precision (GF_SINGLE_PRECISION or not) into gaussfilt._f32 and
// gaussfilt._f64 (python/CMakeLists.txt), each linked to the library built
// in that precision. Every step is one call of the library's prepared step
// on the object's own belief; nothing here computes a filter quantity.
//
// Conventions: arrays come in as anything numpy converts (rounded to
// gf_real: float32 in _f32) and go out as fresh arrays of gf_real. A status
// other than GF_OK raises the gaussfilt._errors class of that status; the
// library leaves the belief untouched then, and so does this layer. A
// Python callback's exception is passed on as it is: the trampoline returns
// GF_ERR_MODEL to the library, which drops the step, and the step's wrapper
// returns NULL with the callback's exception still set.
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <numpy/arrayobject.h>

#include <math.h>
#include <string.h>

#include "gaussfilt/cov2.h"
#include "gaussfilt/ekf.h"
#include "gaussfilt/ekf3.h"
#include "gaussfilt/kf.h"
#include "gaussfilt/kf2.h"

#ifdef GF_SINGLE_PRECISION
#define NPY_GF NPY_FLOAT32
#define GF_PREC_NAME "float32"
#else
#define NPY_GF NPY_FLOAT64
#define GF_PREC_NAME "float64"
#endif
#define NMAX GF_KF_NMAX

#define STR2(x) #x
#define STR(x) STR2(x)
#define MODNAME STR(GF_PY_MODULE)
#define CAT2(a, b) a##b
#define CAT(a, b) CAT2(a, b)

// gaussfilt._errors._from_status(status, message, innovation, nis): the
// exception instance for a status.
static PyObject *from_status;

// ---- errors -------------------------------------------------------------

// Raises the exception of status st with message "where: what"; y (m
// entries) and nis go on the exception when y is not NULL (a gated
// update). Returns NULL.
static PyObject *raise_status(gf_status st, const char *where, const char *what,
                              const gf_real *y, unsigned m, gf_real nis)
{
    PyObject *innov = Py_None, *exc;
    Py_INCREF(innov);
    if (y) {
        npy_intp dim = (npy_intp)m;
        PyObject *a = PyArray_SimpleNew(1, &dim, NPY_GF);
        if (!a) {
            Py_DECREF(innov);
            return NULL;
        }
        memcpy(PyArray_DATA((PyArrayObject *)a), y, m * sizeof(gf_real));
        Py_DECREF(innov);
        innov = a;
    }
    exc = PyObject_CallFunction(from_status, "isOd", (int)st,
                                what ? what : gf_status_str(st), innov,
                                y ? (double)nis : (double)NAN);
    Py_DECREF(innov);
    if (!exc) {
        return NULL;
    }
    if (where) {
        PyObject *msg = PyUnicode_FromFormat("%s: %s", where,
                                             what ? what : gf_status_str(st));
        if (msg) {
            PyObject *a = PyTuple_Pack(1, msg);
            if (a) {
                PyObject *old = ((PyBaseExceptionObject *)exc)->args;
                ((PyBaseExceptionObject *)exc)->args = a;
                Py_XDECREF(old);
            }
            Py_DECREF(msg);
        }
    }
    PyErr_SetObject((PyObject *)Py_TYPE(exc), exc);
    Py_DECREF(exc);
    return NULL;
}

// A wrong argument found here (a shape, a type): GF_ERR_ARG's exception.
static PyObject *bad_arg(const char *fmt, ...)
{
    char buf[256];
    va_list ap;
    va_start(ap, fmt);
    PyOS_vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    return raise_status(GF_ERR_ARG, NULL, buf, NULL, 0, 0);
}

// Puts step = k on the exception being raised (a batch's failed step).
static void set_step(npy_intp k)
{
    PyObject *type, *value, *tb, *step;
    PyErr_Fetch(&type, &value, &tb);
    PyErr_NormalizeException(&type, &value, &tb);
    step = PyLong_FromSsize_t(k);
    if (value && step) {
        PyObject_SetAttrString(value, "step", step);
    }
    Py_XDECREF(step);
    PyErr_Restore(type, value, tb);
}

// ---- arrays in and out --------------------------------------------------

static void shape_str(PyArrayObject *a, char *buf, size_t len)
{
    int nd = PyArray_NDIM(a);
    size_t k = 0;
    k += (size_t)PyOS_snprintf(buf + k, len - k, "(");
    for (int i = 0; i < nd && k < len; i++) {
        k += (size_t)PyOS_snprintf(buf + k, len - k, "%ld%s",
                                   (long)PyArray_DIM(a, i),
                                   (nd == 1 || i + 1 < nd) ? "," : "");
    }
    if (k < len) {
        PyOS_snprintf(buf + k, len - k, ")");
    }
}

// Reads obj into out (row-major gf_real): a vector of cols entries when
// rows == 0, else a rows x cols matrix; a 1 x cols matrix may also come as
// a vector, and one entry as a scalar. -1 with GF_ERR_ARG's exception
// (naming `name` and the shapes) when it is not that shape.
static int read_real(PyObject *obj, const char *name, npy_intp rows,
                     npy_intp cols, gf_real *out)
{
    PyArrayObject *a;
    npy_intp size = rows ? rows * cols : cols;
    int ok;
    if (PyArray_CheckExact(obj) &&
        PyArray_TYPE((PyArrayObject *)obj) == NPY_GF &&
        PyArray_ISCARRAY_RO((PyArrayObject *)obj)) {
        a = (PyArrayObject *)obj;
        Py_INCREF(a);
    } else if (PyFloat_CheckExact(obj) && size == 1) {
        out[0] = (gf_real)PyFloat_AS_DOUBLE(obj);
        return 0;
    } else {
        a = (PyArrayObject *)PyArray_FROMANY(
            obj, NPY_GF, 0, 0, NPY_ARRAY_CARRAY_RO | NPY_ARRAY_FORCECAST);
        if (!a) {
            if (PyErr_ExceptionMatches(PyExc_TypeError) ||
                PyErr_ExceptionMatches(PyExc_ValueError)) {
                PyErr_Clear();
                bad_arg("%s: not an array of numbers", name);
            }
            return -1;
        }
    }
    switch (PyArray_NDIM(a)) {
    case 0:
        ok = size == 1;
        break;
    case 1:
        ok = (rows <= 1) && PyArray_DIM(a, 0) == cols;
        break;
    case 2:
        ok = rows > 0 && PyArray_DIM(a, 0) == rows && PyArray_DIM(a, 1) == cols;
        break;
    default:
        ok = 0;
    }
    if (!ok) {
        char got[64];
        shape_str(a, got, sizeof got);
        if (rows) {
            bad_arg("%s must have shape (%ld, %ld), got %s", name, (long)rows,
                    (long)cols, got);
        } else {
            bad_arg("%s must have shape (%ld,), got %s", name, (long)cols, got);
        }
        Py_DECREF(a);
        return -1;
    }
    memcpy(out, PyArray_DATA(a), (size_t)size * sizeof(gf_real));
    Py_DECREF(a);
    return 0;
}

// The shape of obj as a gf_real array (1 or 2 dimensions): -1 with
// GF_ERR_ARG's exception otherwise. A 1-D array is 1 x its length when
// vec_is_row, else its length x 1; a scalar is 1 x 1.
static int shape_of(PyObject *obj, const char *name, int vec_is_row,
                    npy_intp *rows, npy_intp *cols)
{
    PyArrayObject *a = (PyArrayObject *)PyArray_FROMANY(
        obj, NPY_GF, 0, 0, NPY_ARRAY_CARRAY_RO | NPY_ARRAY_FORCECAST);
    if (!a) {
        if (PyErr_ExceptionMatches(PyExc_TypeError) ||
            PyErr_ExceptionMatches(PyExc_ValueError)) {
            PyErr_Clear();
            bad_arg("%s: not an array of numbers", name);
        }
        return -1;
    }
    int nd = PyArray_NDIM(a);
    if (nd == 0) {
        *rows = *cols = 1;
    } else if (nd == 1) {
        *rows = vec_is_row ? 1 : PyArray_DIM(a, 0);
        *cols = vec_is_row ? PyArray_DIM(a, 0) : 1;
    } else if (nd == 2) {
        *rows = PyArray_DIM(a, 0);
        *cols = PyArray_DIM(a, 1);
    } else {
        Py_DECREF(a);
        bad_arg("%s must be a vector or a matrix, got %d dimensions", name, nd);
        return -1;
    }
    Py_DECREF(a);
    return 0;
}

// A new gf_real array of shape (d0,) (d1 == 0) or (d0, d1), from src.
static PyObject *new_array(npy_intp d0, npy_intp d1, const gf_real *src)
{
    npy_intp dims[2] = {d0, d1};
    PyObject *a = PyArray_SimpleNew(d1 ? 2 : 1, dims, NPY_GF);
    if (a && src) {
        memcpy(PyArray_DATA((PyArrayObject *)a), src,
               (size_t)(d1 ? d0 * d1 : d0) * sizeof(gf_real));
    }
    return a;
}

// Fast-call arguments: fills out[0..nmax-1] from the positional ones and
// the keywords (by names[]); the first nreq are required, the others NULL
// when absent. -1 with TypeError otherwise.
static int get_args(const char *fname, PyObject *const *args, Py_ssize_t nargs,
                    PyObject *kwnames, const char *const *names, int nreq,
                    int nmax, PyObject **out)
{
    for (int i = 0; i < nmax; i++) {
        out[i] = NULL;
    }
    if (nargs > nmax) {
        PyErr_Format(PyExc_TypeError,
                     "%s() takes at most %d arguments (%zd given)", fname, nmax,
                     nargs);
        return -1;
    }
    for (Py_ssize_t i = 0; i < nargs; i++) {
        out[i] = args[i];
    }
    if (kwnames) {
        for (Py_ssize_t k = 0; k < PyTuple_GET_SIZE(kwnames); k++) {
            PyObject *key = PyTuple_GET_ITEM(kwnames, k);
            int j = 0;
            while (j < nmax && PyUnicode_CompareWithASCIIString(key, names[j]))
                j++;
            if (j == nmax) {
                PyErr_Format(PyExc_TypeError,
                             "%s() got an unexpected keyword argument '%U'",
                             fname, key);
                return -1;
            }
            if (out[j]) {
                PyErr_Format(PyExc_TypeError,
                             "%s() got multiple values for argument '%s'",
                             fname, names[j]);
                return -1;
            }
            out[j] = args[nargs + k];
        }
    }
    for (int i = 0; i < nreq; i++) {
        if (!out[i]) {
            PyErr_Format(PyExc_TypeError, "%s() missing required argument '%s'",
                         fname, names[i]);
            return -1;
        }
    }
    return 0;
}

// A non-negative number (a gate) from obj; -1 with an exception otherwise.
static int read_gate(PyObject *obj, const char *name, gf_real *gate)
{
    double g = obj ? PyFloat_AsDouble(obj) : 0.0;
    if (g == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        bad_arg("%s: gate must be a number", name);
        return -1;
    }
    *gate = (gf_real)g;
    return 0;
}

// ---- built-in EKF3 models ------------------------------------------------

typedef struct {
    PyObject_HEAD gf_ekf3_motion_fn g; // one of the two is set
    gf_ekf3_meas_fn h;
    unsigned m; // a measurement's measured quantities
    const char *name;
} BuiltinObj;

static PyTypeObject Builtin_Type;

static PyObject *Builtin_call(PyObject *self_, PyObject *args, PyObject *kw)
{
    BuiltinObj *self = (BuiltinObj *)self_;
    PyObject *mu_o, *u_o = Py_None, *out = NULL, *a = NULL, *b = NULL;
    gf_vec3 mu, mu_bar = {{0, 0, 0}};
    gf_mat3 J = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    gf_real u[2];
    gf_status st;
    (void)kw;
    if (self->g) {
        if (!PyArg_ParseTuple(args, "OO", &mu_o, &u_o)) {
            return NULL;
        }
        if (read_real(mu_o, "mu", 0, 3, mu.v) < 0 ||
            read_real(u_o, "u", 0, 2, u) < 0) {
            return NULL;
        }
        mu_bar = mu;
        st = self->g(NULL, &mu, u, &mu_bar, &J);
    } else {
        if (!PyArg_ParseTuple(args, "O", &mu_o)) {
            return NULL;
        }
        if (read_real(mu_o, "mu_bar", 0, 3, mu.v) < 0) {
            return NULL;
        }
        memset(&J, 0, sizeof J);
        st = self->h(NULL, &mu, &mu_bar, &J);
    }
    if (st != GF_OK) {
        return raise_status(st, self->name, NULL, NULL, 0, 0);
    }
    unsigned rows = self->g ? 3u : self->m;
    a = new_array(rows, 0, mu_bar.v);
    b = new_array(rows, 3, NULL);
    if (a && b) {
        gf_real *d = (gf_real *)PyArray_DATA((PyArrayObject *)b);
        for (unsigned i = 0; i < rows; i++) {
            memcpy(d + 3 * i, J.m[i], 3 * sizeof(gf_real));
        }
        out = PyTuple_Pack(2, a, b);
    }
    Py_XDECREF(a);
    Py_XDECREF(b);
    return out;
}

static PyObject *Builtin_repr(PyObject *self)
{
    return PyUnicode_FromFormat("<gaussfilt.%s.%s (C)>", GF_PREC_NAME,
                                ((BuiltinObj *)self)->name);
}

static PyTypeObject Builtin_Type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name =
        "gaussfilt." GF_PREC_NAME ".Builtin",
    .tp_basicsize = sizeof(BuiltinObj),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "One of the library's built-in EKF3 models, as a C function.\n\n"
              "Passed as g or h to EKF3Motion / EKF3Meas, the library calls "
              "it directly (no Python in the step). Callable from Python as "
              "well: a motion as g(mu, u) -> (mu_bar, G), a measurement as "
              "h(mu_bar) -> (z_hat, H).",
    .tp_call = Builtin_call,
    .tp_repr = Builtin_repr,
};

static PyObject *new_builtin(gf_ekf3_motion_fn g, gf_ekf3_meas_fn h, unsigned m,
                             const char *name)
{
    BuiltinObj *b = PyObject_New(BuiltinObj, &Builtin_Type);
    if (b) {
        b->g = g;
        b->h = h;
        b->m = m;
        b->name = name;
    }
    return (PyObject *)b;
}

// ---- KF2 ------------------------------------------------------------------

typedef struct {
    PyObject_HEAD gf_kf2_pmodel pm;
} KF2ModelObj;

typedef struct {
    PyObject_HEAD gf_kf2_pmeas pq;
} KF2MeasObj;

typedef struct {
    PyObject_HEAD gf_kf2 kf;
    gf_innovation last; // the last accepted update's
    int has_last;
} KF2Obj;

static PyTypeObject KF2Model_Type, KF2Meas_Type, KF2_Type;

static int KF2Model_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"A", "R", "B", "c", NULL};
    PyObject *A, *R, *B = Py_None, *c = Py_None;
    gf_kf2_model m;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|OO:KF2Model", names, &A, &R,
                                     &B, &c)) {
        return -1;
    }
    memset(&m, 0, sizeof m);
    if (read_real(A, "KF2Model: A", 2, 2, &m.A.m[0][0]) < 0 ||
        read_real(R, "KF2Model: R", 2, 2, &m.R.m[0][0]) < 0 ||
        (B != Py_None && read_real(B, "KF2Model: B", 2, 2, &m.B.m[0][0]) < 0) ||
        (c != Py_None && read_real(c, "KF2Model: c", 0, 2, m.c.v) < 0)) {
        return -1;
    }
    gf_status st = gf_kf2_prepare_model(&((KF2ModelObj *)self_)->pm, &m);
    if (st != GF_OK) {
        raise_status(st, "KF2Model", NULL, NULL, 0, 0);
        return -1;
    }
    return 0;
}

static PyObject *KF2Model_get(PyObject *self_, void *which)
{
    const gf_kf2_model *m = &((KF2ModelObj *)self_)->pm.model;
    switch ((int)(size_t)which) {
    case 0:
        return new_array(2, 2, &m->A.m[0][0]);
    case 1:
        return new_array(2, 2, &m->R.m[0][0]);
    case 2:
        return new_array(2, 2, &m->B.m[0][0]);
    default:
        return new_array(2, 0, m->c.v);
    }
}

static PyGetSetDef KF2Model_getset[] = {
    {"A", KF2Model_get, NULL, "state transition (2, 2)", (void *)0},
    {"R", KF2Model_get, NULL, "process noise covariance (2, 2)", (void *)1},
    {"B", KF2Model_get, NULL, "control matrix (2, 2)", (void *)2},
    {"c", KF2Model_get, NULL, "constant motion term (2,)", (void *)3},
    {NULL, NULL, NULL, NULL, NULL},
};

static int KF2Meas_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"C", "Q", "c", "gate", NULL};
    PyObject *C, *Q, *c = Py_None, *gate = NULL;
    gf_kf2_meas m;
    npy_intp rows, cols;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|OO:KF2Meas", names, &C, &Q,
                                     &c, &gate)) {
        return -1;
    }
    memset(&m, 0, sizeof m);
    if (shape_of(C, "KF2Meas: C", 1, &rows, &cols) < 0) {
        return -1;
    }
    if (rows < 1 || rows > 2 || cols != 2) {
        bad_arg("KF2Meas: C must have shape (1, 2) or (2, 2), got (%ld, %ld)",
                (long)rows, (long)cols);
        return -1;
    }
    m.m = (unsigned)rows;
    gf_real Cv[4], Qv[4];
    if (read_real(C, "KF2Meas: C", rows, 2, Cv) < 0 ||
        read_real(Q, "KF2Meas: Q", rows, rows, Qv) < 0 ||
        (c != Py_None && read_real(c, "KF2Meas: c", 0, rows, m.c.v) < 0) ||
        read_gate(gate, "KF2Meas", &m.gate) < 0) {
        return -1;
    }
    for (unsigned i = 0; i < m.m; i++) {
        for (unsigned j = 0; j < 2; j++) {
            m.C.m[i][j] = Cv[2 * i + j];
        }
        for (unsigned j = 0; j < m.m; j++) {
            m.Q.m[i][j] = Qv[m.m * i + j];
        }
    }
    gf_status st = gf_kf2_prepare_meas(&((KF2MeasObj *)self_)->pq, &m);
    if (st != GF_OK) {
        raise_status(st, "KF2Meas", NULL, NULL, 0, 0);
        return -1;
    }
    return 0;
}

static PyObject *KF2Meas_get(PyObject *self_, void *which)
{
    const gf_kf2_meas *m = &((KF2MeasObj *)self_)->pq.meas;
    gf_real v[4];
    switch ((int)(size_t)which) {
    case 0:
        for (unsigned i = 0; i < m->m; i++) {
            v[2 * i] = m->C.m[i][0];
            v[2 * i + 1] = m->C.m[i][1];
        }
        return new_array(m->m, 2, v);
    case 1:
        for (unsigned i = 0; i < m->m; i++) {
            for (unsigned j = 0; j < m->m; j++) {
                v[m->m * i + j] = m->Q.m[i][j];
            }
        }
        return new_array(m->m, m->m, v);
    case 2:
        return new_array(m->m, 0, m->c.v);
    case 3:
        return PyFloat_FromDouble((double)m->gate);
    default:
        return PyLong_FromUnsignedLong(m->m);
    }
}

static PyGetSetDef KF2Meas_getset[] = {
    {"C", KF2Meas_get, NULL, "measurement matrix (m, 2)", (void *)0},
    {"Q", KF2Meas_get, NULL, "measurement noise covariance (m, m)", (void *)1},
    {"c", KF2Meas_get, NULL, "constant measurement term (m,)", (void *)2},
    {"gate", KF2Meas_get, NULL, "chi-square gate on the NIS (0: none)",
     (void *)3},
    {"m", KF2Meas_get, NULL, "measured quantities (1 or 2)", (void *)4},
    {NULL, NULL, NULL, NULL, NULL},
};

static int KF2_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"mu", "sigma", NULL};
    PyObject *mu, *sigma;
    gf_vec2 m;
    gf_mat2 s;
    KF2Obj *self = (KF2Obj *)self_;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO:KF2", names, &mu, &sigma)) {
        return -1;
    }
    if (read_real(mu, "KF2: mu", 0, 2, m.v) < 0 ||
        read_real(sigma, "KF2: sigma", 2, 2, &s.m[0][0]) < 0) {
        return -1;
    }
    gf_status st = gf_kf2_init(&self->kf, &m, &s);
    if (st != GF_OK) {
        raise_status(st, "KF2", NULL, NULL, 0, 0);
        return -1;
    }
    self->has_last = 0;
    return 0;
}

static PyObject *KF2_predict(PyObject *self_, PyObject *const *args,
                             Py_ssize_t nargs, PyObject *kwnames)
{
    static const char *const names[] = {"model", "u"};
    PyObject *a[2];
    gf_vec2 u;
    if (get_args("predict", args, nargs, kwnames, names, 1, 2, a) < 0) {
        return NULL;
    }
    if (!PyObject_TypeCheck(a[0], &KF2Model_Type)) {
        return bad_arg("KF2.predict: model must be a KF2Model, not %s",
                       Py_TYPE(a[0])->tp_name);
    }
    if (a[1] && a[1] != Py_None &&
        read_real(a[1], "KF2.predict: u", 0, 2, u.v) < 0) {
        return NULL;
    }
    gf_status st = gf_kf2_predict_prepared(
        &((KF2Obj *)self_)->kf, &((KF2ModelObj *)a[0])->pm,
        (a[1] && a[1] != Py_None) ? &u : NULL);
    if (st != GF_OK) {
        return raise_status(st, "KF2.predict", NULL, NULL, 0, 0);
    }
    Py_RETURN_NONE;
}

static PyObject *KF2_update(PyObject *self_, PyObject *const *args,
                            Py_ssize_t nargs, PyObject *kwnames)
{
    static const char *const names[] = {"meas", "z"};
    PyObject *a[2];
    KF2Obj *self = (KF2Obj *)self_;
    gf_vec2 z = {{0, 0}};
    gf_innovation info;
    if (get_args("update", args, nargs, kwnames, names, 2, 2, a) < 0) {
        return NULL;
    }
    if (!PyObject_TypeCheck(a[0], &KF2Meas_Type)) {
        return bad_arg("KF2.update: meas must be a KF2Meas, not %s",
                       Py_TYPE(a[0])->tp_name);
    }
    const gf_kf2_pmeas *pq = &((KF2MeasObj *)a[0])->pq;
    if (read_real(a[1], "KF2.update: z", 0, pq->meas.m, z.v) < 0) {
        return NULL;
    }
    gf_status st = gf_kf2_update_prepared(&self->kf, pq, &z, &info);
    if (st == GF_ERR_GATED) {
        return raise_status(st, "KF2.update", NULL, info.y, info.m, info.nis);
    }
    if (st != GF_OK) {
        return raise_status(st, "KF2.update", NULL, NULL, 0, 0);
    }
    self->last = info;
    self->has_last = 1;
    Py_RETURN_NONE;
}

// Sigma of a KF2 or EKF3 as an (n, n) array.
static PyObject *KF2_sigma(PyObject *self_, PyObject *unused)
{
    gf_mat2 s;
    (void)unused;
    gf_status st = gf_kf2_cov(&((KF2Obj *)self_)->kf, &s);
    if (st != GF_OK) {
        return raise_status(st, "KF2.sigma", NULL, NULL, 0, 0);
    }
    return new_array(2, 2, &s.m[0][0]);
}

static PyObject *KF2_get(PyObject *self_, void *which)
{
    KF2Obj *self = (KF2Obj *)self_;
    switch ((int)(size_t)which) {
    case 0:
        return new_array(2, 0, self->kf.mu.v);
    case 1:
        return PyFloat_FromDouble(self->has_last ? (double)self->last.nis
                                                 : (double)NAN);
    default:
        if (!self->has_last) {
            Py_RETURN_NONE;
        }
        return new_array(self->last.m, 0, self->last.y);
    }
}

// run(): the batch entry of KF2, see its docstring. On a failure other
// than a gate the belief is put back as it was before the call.
static PyObject *KF2_run(PyObject *self_, PyObject *const *args,
                         Py_ssize_t nargs, PyObject *kwnames)
{
    static const char *const names[] = {"model", "meas", "u", "z", "steps"};
    PyObject *a[5], *U = NULL, *Z = NULL, *mu_o = NULL, *sg_o = NULL,
                    *nis_o = NULL, *st_o = NULL, *out = NULL;
    KF2Obj *self = (KF2Obj *)self_;
    const gf_kf2_pmodel *pm = NULL;
    const gf_kf2_pmeas *pq = NULL;
    npy_intp N = -1;
    unsigned m = 0;
    if (get_args("run", args, nargs, kwnames, names, 0, 5, a) < 0) {
        return NULL;
    }
    if (a[0] && a[0] != Py_None) {
        if (!PyObject_TypeCheck(a[0], &KF2Model_Type)) {
            return bad_arg("KF2.run: model must be a KF2Model or None");
        }
        pm = &((KF2ModelObj *)a[0])->pm;
    }
    if (a[1] && a[1] != Py_None) {
        if (!PyObject_TypeCheck(a[1], &KF2Meas_Type)) {
            return bad_arg("KF2.run: meas must be a KF2Meas or None");
        }
        pq = &((KF2MeasObj *)a[1])->pq;
        m = pq->meas.m;
    }
    if (a[4] && a[4] != Py_None) {
        N = (npy_intp)PyLong_AsSsize_t(a[4]);
        if (N == -1 && PyErr_Occurred()) {
            return NULL;
        }
        if (N < 0) {
            return bad_arg("KF2.run: steps must be >= 0");
        }
    }
    if (a[2] && a[2] != Py_None) {
        U = PyArray_FROMANY(a[2], NPY_GF, 2, 2,
                            NPY_ARRAY_CARRAY_RO | NPY_ARRAY_FORCECAST);
        if (!U) {
            PyErr_Clear();
            return bad_arg("KF2.run: u must be an (N, 2) array");
        }
        if (PyArray_DIM((PyArrayObject *)U, 1) != 2 ||
            (N >= 0 && PyArray_DIM((PyArrayObject *)U, 0) != N)) {
            Py_DECREF(U);
            return bad_arg("KF2.run: u must have shape (steps, 2)");
        }
        N = PyArray_DIM((PyArrayObject *)U, 0);
    }
    if (a[3] && a[3] != Py_None) {
        if (!pq) {
            Py_XDECREF(U);
            return bad_arg("KF2.run: z without meas");
        }
        Z = PyArray_FROMANY(a[3], NPY_GF, 1, 2,
                            NPY_ARRAY_CARRAY_RO | NPY_ARRAY_FORCECAST);
        if (!Z) {
            PyErr_Clear();
            Py_XDECREF(U);
            return bad_arg("KF2.run: z must be an (N, m) array");
        }
        npy_intp zc = PyArray_NDIM((PyArrayObject *)Z) == 2
                          ? PyArray_DIM((PyArrayObject *)Z, 1)
                          : 1;
        if (zc != (npy_intp)m ||
            (PyArray_NDIM((PyArrayObject *)Z) == 1 && m != 1) ||
            (N >= 0 && PyArray_DIM((PyArrayObject *)Z, 0) != N)) {
            Py_XDECREF(U);
            Py_DECREF(Z);
            return bad_arg("KF2.run: z must have shape (steps, %u)", m);
        }
        N = PyArray_DIM((PyArrayObject *)Z, 0);
    }
    if (N < 0) {
        return bad_arg("KF2.run: give u, z or steps");
    }
    npy_intp d3[3] = {N, 2, 2};
    mu_o = PyArray_SimpleNew(2, d3, NPY_GF);
    sg_o = PyArray_SimpleNew(3, d3, NPY_GF);
    nis_o = PyArray_SimpleNew(1, d3, NPY_GF);
    st_o = PyArray_SimpleNew(1, d3, NPY_INT8);
    if (!mu_o || !sg_o || !nis_o || !st_o) {
        goto done;
    }
    {
        const gf_real *u =
            U ? (const gf_real *)PyArray_DATA((PyArrayObject *)U) : NULL;
        const gf_real *z =
            Z ? (const gf_real *)PyArray_DATA((PyArrayObject *)Z) : NULL;
        gf_real *mo = (gf_real *)PyArray_DATA((PyArrayObject *)mu_o);
        gf_real *so = (gf_real *)PyArray_DATA((PyArrayObject *)sg_o);
        gf_real *no = (gf_real *)PyArray_DATA((PyArrayObject *)nis_o);
        signed char *sto = (signed char *)PyArray_DATA((PyArrayObject *)st_o);
        const gf_kf2 saved = self->kf;
        const gf_innovation saved_last = self->last;
        const int saved_has = self->has_last;
        for (npy_intp k = 0; k < N; k++) {
            gf_status st = GF_OK;
            gf_innovation info;
            no[k] = (gf_real)NAN;
            if (pm) {
                st = gf_kf2_predict_prepared(
                    &self->kf, pm, u ? (const gf_vec2 *)(u + 2 * k) : NULL);
            }
            if (st == GF_OK && z) {
                const gf_real *zk = z + (npy_intp)m * k;
                int present = 1;
                for (unsigned i = 0; i < m; i++) {
                    present &= !isnan(zk[i]);
                }
                if (present) {
                    gf_vec2 zv = {{zk[0], m > 1 ? zk[1] : GF_R(0.0)}};
                    st = gf_kf2_update_prepared(&self->kf, pq, &zv, &info);
                    if (st == GF_OK || st == GF_ERR_GATED) {
                        no[k] = info.nis;
                    }
                    if (st == GF_OK) {
                        self->last = info;
                        self->has_last = 1;
                    }
                }
            }
            if (st != GF_OK && st != GF_ERR_GATED) {
                self->kf = saved;
                self->last = saved_last;
                self->has_last = saved_has;
                raise_status(st, "KF2.run", NULL, NULL, 0, 0);
                set_step(k);
                goto done;
            }
            sto[k] = (signed char)st;
            memcpy(mo + 2 * k, self->kf.mu.v, 2 * sizeof(gf_real));
            gf_kf2_cov(&self->kf, (gf_mat2 *)(so + 4 * k));
        }
    }
    out = PyTuple_Pack(4, mu_o, sg_o, nis_o, st_o);
done:
    Py_XDECREF(U);
    Py_XDECREF(Z);
    Py_XDECREF(mu_o);
    Py_XDECREF(sg_o);
    Py_XDECREF(nis_o);
    Py_XDECREF(st_o);
    return out;
}

static PyMethodDef KF2_methods[] = {
    {"predict", (PyCFunction)(void (*)(void))KF2_predict,
     METH_FASTCALL | METH_KEYWORDS,
     "predict(model, u=None)\n\n"
     "Prediction (Table 3.1, lines 2-3):\n"
     "    mu_bar = A mu + B u + c,   Sigma_bar = A Sigma A^T + R\n"
     "on the factors U D U^T of Sigma. u None: no control. Raises the\n"
     "status's GaussfiltError (NonFinite: u not finite); the belief is\n"
     "unchanged then."},
    {"update", (PyCFunction)(void (*)(void))KF2_update,
     METH_FASTCALL | METH_KEYWORDS,
     "update(meas, z)\n\n"
     "Correction (Table 3.1, lines 4-6) with m = meas.m values z:\n"
     "    y = z - c - C mu_bar,   S = C Sigma_bar C^T + Q,\n"
     "    K = Sigma_bar C^T S^-1,  mu = mu_bar + K y,  Sigma = (I - K C) "
     "Sigma_bar\n"
     "(Bierman's scalar updates on the whitened rows), NIS = y^T S^-1 y.\n"
     "Gated (NIS > meas.gate) carries the innovation and NIS; every error\n"
     "leaves the belief unchanged."},
    {"sigma", KF2_sigma, METH_NOARGS,
     "sigma() -> (2, 2) array: Sigma = U D U^T, exactly symmetric."},
    {"run", (PyCFunction)(void (*)(void))KF2_run, METH_FASTCALL | METH_KEYWORDS,
     "run(model=None, meas=None, u=None, z=None, steps=None)\n"
     "    -> (mu (N, 2), sigma (N, 2, 2), nis (N,), status (N,))\n\n"
     "N steps in one call, each predict(model, u[k]) (when model is given)\n"
     "then update(meas, z[k]) (when z is given and z[k] has no NaN: a NaN\n"
     "row is a step without a measurement). A gated update is recorded\n"
     "(status -5 and its NIS) and the run goes on from the prediction;\n"
     "nis is NaN where no update ran. Any other failure raises with\n"
     "exc.step = k and puts the belief back as it was before the call."},
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef KF2_getset[] = {
    {"mu", KF2_get, NULL, "the mean, a (2,) copy", (void *)0},
    {"nis", KF2_get, NULL,
     "NIS = y^T S^-1 y of the last accepted update (nan before any)",
     (void *)1},
    {"innovation", KF2_get, NULL,
     "y = z - c - C mu_bar of the last accepted update (None before any)",
     (void *)2},
    {NULL, NULL, NULL, NULL, NULL},
};

// ---- EKF3 -----------------------------------------------------------------

typedef struct {
    PyObject_HEAD gf_ekf3_pmotion pm;
    PyObject *g;     // the callable (a Builtin: its C function is in pm)
    PyObject *cur_u; // the step's u, while the step runs
} EKF3MotionObj;

typedef struct {
    PyObject_HEAD gf_ekf3_pmeas pq;
    PyObject *h;
} EKF3MeasObj;

typedef struct {
    PyObject_HEAD gf_ekf3 ekf;
    gf_innovation last;
    int has_last;
    int busy; // a step is running (its callback may not step this filter)
} EKF3Obj;

static PyTypeObject EKF3Motion_Type, EKF3Meas_Type, EKF3_Type;

// The Python motion g(mu, u) -> (mu_bar, G) behind EKF3's C callback.
static gf_status ekf3_g_py(void *ctx, const gf_vec3 *mu, const gf_real *u,
                           gf_vec3 *mu_bar, gf_mat3 *G)
{
    EKF3MotionObj *mo = (EKF3MotionObj *)ctx;
    PyObject *mu_a = new_array(3, 0, mu->v), *r, *seq;
    (void)u;
    if (!mu_a) {
        return GF_ERR_MODEL;
    }
    r = PyObject_CallFunctionObjArgs(mo->g, mu_a,
                                     mo->cur_u ? mo->cur_u : Py_None, NULL);
    Py_DECREF(mu_a);
    if (!r) {
        return GF_ERR_MODEL;
    }
    seq = PySequence_Fast(r, "");
    Py_DECREF(r);
    if (!seq || PySequence_Fast_GET_SIZE(seq) != 2) {
        Py_XDECREF(seq);
        PyErr_Clear();
        bad_arg("EKF3 motion g must return (mu_bar, G)");
        return GF_ERR_MODEL;
    }
    int bad = read_real(PySequence_Fast_GET_ITEM(seq, 0), "g's mu_bar", 0, 3,
                        mu_bar->v) < 0 ||
              read_real(PySequence_Fast_GET_ITEM(seq, 1), "g's G", 3, 3,
                        &G->m[0][0]) < 0;
    Py_DECREF(seq);
    return bad ? GF_ERR_MODEL : GF_OK;
}

// The Python measurement h(mu_bar) -> (z_hat, H) behind EKF3's callback.
static gf_status ekf3_h_py(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                           gf_mat3 *H)
{
    EKF3MeasObj *me = (EKF3MeasObj *)ctx;
    unsigned m = me->pq.meas.m;
    gf_real Hv[9];
    PyObject *mu_a = new_array(3, 0, mu_bar->v), *r, *seq;
    if (!mu_a) {
        return GF_ERR_MODEL;
    }
    r = PyObject_CallFunctionObjArgs(me->h, mu_a, NULL);
    Py_DECREF(mu_a);
    if (!r) {
        return GF_ERR_MODEL;
    }
    seq = PySequence_Fast(r, "");
    Py_DECREF(r);
    if (!seq || PySequence_Fast_GET_SIZE(seq) != 2) {
        Py_XDECREF(seq);
        PyErr_Clear();
        bad_arg("EKF3 measurement h must return (z_hat, H)");
        return GF_ERR_MODEL;
    }
    int bad =
        read_real(PySequence_Fast_GET_ITEM(seq, 0), "h's z_hat", 0, m,
                  z_hat->v) < 0 ||
        read_real(PySequence_Fast_GET_ITEM(seq, 1), "h's H", m, 3, Hv) < 0;
    Py_DECREF(seq);
    if (bad) {
        return GF_ERR_MODEL;
    }
    for (unsigned i = 0; i < m; i++) {
        memcpy(H->m[i], Hv + 3 * i, 3 * sizeof(gf_real));
    }
    return GF_OK;
}

static int EKF3Motion_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"g", "R", NULL};
    EKF3MotionObj *self = (EKF3MotionObj *)self_;
    PyObject *g, *R;
    gf_ekf3_motion mo;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO:EKF3Motion", names, &g,
                                     &R)) {
        return -1;
    }
    if (!PyCallable_Check(g)) {
        bad_arg("EKF3Motion: g must be callable");
        return -1;
    }
    memset(&mo, 0, sizeof mo);
    if (read_real(R, "EKF3Motion: R", 3, 3, &mo.R.m[0][0]) < 0) {
        return -1;
    }
    if (PyObject_TypeCheck(g, &Builtin_Type)) {
        if (!((BuiltinObj *)g)->g) {
            bad_arg("EKF3Motion: %s is a measurement", ((BuiltinObj *)g)->name);
            return -1;
        }
        mo.g = ((BuiltinObj *)g)->g;
    } else {
        mo.g = ekf3_g_py;
        mo.ctx = self;
    }
    gf_status st = gf_ekf3_prepare_motion(&self->pm, &mo);
    if (st != GF_OK) {
        raise_status(st, "EKF3Motion", NULL, NULL, 0, 0);
        return -1;
    }
    Py_INCREF(g);
    Py_XSETREF(self->g, g);
    return 0;
}

static int EKF3Meas_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"h", "Q", "angle_mask", "gate", NULL};
    EKF3MeasObj *self = (EKF3MeasObj *)self_;
    PyObject *h, *Q, *gate = NULL;
    unsigned angle_mask = 0;
    gf_ekf3_meas me;
    npy_intp rows, cols;
    gf_real Qv[9];
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|IO:EKF3Meas", names, &h, &Q,
                                     &angle_mask, &gate)) {
        return -1;
    }
    if (!PyCallable_Check(h)) {
        bad_arg("EKF3Meas: h must be callable");
        return -1;
    }
    memset(&me, 0, sizeof me);
    if (shape_of(Q, "EKF3Meas: Q", 1, &rows, &cols) < 0) {
        return -1;
    }
    if (rows != cols || rows < 1 || rows > 3) {
        bad_arg("EKF3Meas: Q must be m x m with m = 1..3, got (%ld, %ld)",
                (long)rows, (long)cols);
        return -1;
    }
    me.m = (unsigned)rows;
    if (read_real(Q, "EKF3Meas: Q", rows, rows, Qv) < 0 ||
        read_gate(gate, "EKF3Meas", &me.gate) < 0) {
        return -1;
    }
    for (unsigned i = 0; i < me.m; i++) {
        for (unsigned j = 0; j < me.m; j++) {
            me.Q.m[i][j] = Qv[me.m * i + j];
        }
    }
    me.angle_mask = angle_mask;
    if (PyObject_TypeCheck(h, &Builtin_Type)) {
        BuiltinObj *b = (BuiltinObj *)h;
        if (!b->h) {
            bad_arg("EKF3Meas: %s is a motion", b->name);
            return -1;
        }
        if (b->m != me.m) {
            bad_arg("EKF3Meas: %s measures %u quantities, Q is %u x %u",
                    b->name, b->m, me.m, me.m);
            return -1;
        }
        me.h = b->h;
    } else {
        me.h = ekf3_h_py;
        me.ctx = self;
    }
    gf_status st = gf_ekf3_prepare_meas(&self->pq, &me);
    if (st != GF_OK) {
        raise_status(st, "EKF3Meas", NULL, NULL, 0, 0);
        return -1;
    }
    Py_INCREF(h);
    Py_XSETREF(self->h, h);
    return 0;
}

static int EKF3Motion_traverse(PyObject *self, visitproc visit, void *arg)
{
    Py_VISIT(((EKF3MotionObj *)self)->g);
    return 0;
}
static int EKF3Motion_clear(PyObject *self)
{
    Py_CLEAR(((EKF3MotionObj *)self)->g);
    return 0;
}
static void EKF3Motion_dealloc(PyObject *self)
{
    PyObject_GC_UnTrack(self);
    EKF3Motion_clear(self);
    Py_TYPE(self)->tp_free(self);
}
static int EKF3Meas_traverse(PyObject *self, visitproc visit, void *arg)
{
    Py_VISIT(((EKF3MeasObj *)self)->h);
    return 0;
}
static int EKF3Meas_clear(PyObject *self)
{
    Py_CLEAR(((EKF3MeasObj *)self)->h);
    return 0;
}
static void EKF3Meas_dealloc(PyObject *self)
{
    PyObject_GC_UnTrack(self);
    EKF3Meas_clear(self);
    Py_TYPE(self)->tp_free(self);
}

static PyObject *EKF3Motion_get(PyObject *self_, void *which)
{
    EKF3MotionObj *self = (EKF3MotionObj *)self_;
    if (which) {
        return new_array(3, 3, &self->pm.motion.R.m[0][0]);
    }
    if (!self->g) {
        Py_RETURN_NONE;
    }
    Py_INCREF(self->g);
    return self->g;
}

static PyObject *EKF3Meas_get(PyObject *self_, void *which)
{
    EKF3MeasObj *self = (EKF3MeasObj *)self_;
    const gf_ekf3_meas *me = &self->pq.meas;
    gf_real v[9];
    switch ((int)(size_t)which) {
    case 0:
        if (!self->h) {
            Py_RETURN_NONE;
        }
        Py_INCREF(self->h);
        return self->h;
    case 1:
        for (unsigned i = 0; i < me->m; i++) {
            for (unsigned j = 0; j < me->m; j++) {
                v[me->m * i + j] = me->Q.m[i][j];
            }
        }
        return new_array(me->m, me->m, v);
    case 2:
        return PyLong_FromUnsignedLong(me->m);
    case 3:
        return PyLong_FromUnsignedLong(me->angle_mask);
    default:
        return PyFloat_FromDouble((double)me->gate);
    }
}

static PyGetSetDef EKF3Motion_getset[] = {
    {"g", EKF3Motion_get, NULL, "the motion g(mu, u) -> (mu_bar, G)", NULL},
    {"R", EKF3Motion_get, NULL, "process noise covariance (3, 3)", (void *)1},
    {NULL, NULL, NULL, NULL, NULL},
};

static PyGetSetDef EKF3Meas_getset[] = {
    {"h", EKF3Meas_get, NULL, "the measurement h(mu_bar) -> (z_hat, H)",
     (void *)0},
    {"Q", EKF3Meas_get, NULL, "measurement noise covariance (m, m)", (void *)1},
    {"m", EKF3Meas_get, NULL, "measured quantities (1..3)", (void *)2},
    {"angle_mask", EKF3Meas_get, NULL, "bit i: residual i is an angle",
     (void *)3},
    {"gate", EKF3Meas_get, NULL, "chi-square gate on the NIS (0: none)",
     (void *)4},
    {NULL, NULL, NULL, NULL, NULL},
};

static int EKF3_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"mu", "sigma", NULL};
    PyObject *mu, *sigma;
    gf_vec3 m;
    gf_mat3 s;
    EKF3Obj *self = (EKF3Obj *)self_;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO:EKF3", names, &mu, &sigma)) {
        return -1;
    }
    if (self->busy) {
        PyErr_SetString(PyExc_RuntimeError,
                        "EKF3: re-initialised from its own callback");
        return -1;
    }
    if (read_real(mu, "EKF3: mu", 0, 3, m.v) < 0 ||
        read_real(sigma, "EKF3: sigma", 3, 3, &s.m[0][0]) < 0) {
        return -1;
    }
    gf_status st = gf_ekf3_init(&self->ekf, &m, &s);
    if (st != GF_OK) {
        raise_status(st, "EKF3", NULL, NULL, 0, 0);
        return -1;
    }
    self->has_last = 0;
    return 0;
}

static PyObject *EKF3_predict(PyObject *self_, PyObject *const *args,
                              Py_ssize_t nargs, PyObject *kwnames)
{
    static const char *const names[] = {"motion", "u"};
    PyObject *a[2], *U = NULL;
    EKF3Obj *self = (EKF3Obj *)self_;
    if (get_args("predict", args, nargs, kwnames, names, 1, 2, a) < 0) {
        return NULL;
    }
    if (!PyObject_TypeCheck(a[0], &EKF3Motion_Type)) {
        return bad_arg("EKF3.predict: motion must be an EKF3Motion, not %s",
                       Py_TYPE(a[0])->tp_name);
    }
    EKF3MotionObj *mo = (EKF3MotionObj *)a[0];
    if (self->busy) {
        PyErr_SetString(PyExc_RuntimeError,
                        "EKF3.predict called from this filter's own callback");
        return NULL;
    }
    int builtin = mo->pm.motion.g != ekf3_g_py;
    if (a[1] && a[1] != Py_None) {
        U = PyArray_FROMANY(a[1], NPY_GF, 0, 1,
                            NPY_ARRAY_CARRAY | NPY_ARRAY_FORCECAST |
                                NPY_ARRAY_ENSURECOPY);
        if (!U) {
            PyErr_Clear();
            return bad_arg("EKF3.predict: u must be a vector of numbers");
        }
    }
    if (builtin && (!U || PyArray_SIZE((PyArrayObject *)U) != 2)) {
        Py_XDECREF(U);
        return bad_arg("EKF3.predict: u must have 2 entries for %s",
                       ((BuiltinObj *)mo->g)->name);
    }
    PyObject *prev_u = mo->cur_u;
    mo->cur_u = U;
    self->busy = 1;
    gf_status st = gf_ekf3_predict_prepared(
        &self->ekf, &mo->pm,
        U ? (const gf_real *)PyArray_DATA((PyArrayObject *)U) : NULL);
    self->busy = 0;
    mo->cur_u = prev_u;
    Py_XDECREF(U);
    if (st != GF_OK) {
        if (PyErr_Occurred()) {
            return NULL;
        }
        return raise_status(st, "EKF3.predict", NULL, NULL, 0, 0);
    }
    Py_RETURN_NONE;
}

static PyObject *EKF3_update(PyObject *self_, PyObject *const *args,
                             Py_ssize_t nargs, PyObject *kwnames)
{
    static const char *const names[] = {"meas", "z"};
    PyObject *a[2];
    EKF3Obj *self = (EKF3Obj *)self_;
    gf_vec3 z = {{0, 0, 0}};
    gf_innovation info;
    if (get_args("update", args, nargs, kwnames, names, 2, 2, a) < 0) {
        return NULL;
    }
    if (!PyObject_TypeCheck(a[0], &EKF3Meas_Type)) {
        return bad_arg("EKF3.update: meas must be an EKF3Meas, not %s",
                       Py_TYPE(a[0])->tp_name);
    }
    if (self->busy) {
        PyErr_SetString(PyExc_RuntimeError,
                        "EKF3.update called from this filter's own callback");
        return NULL;
    }
    const gf_ekf3_pmeas *pq = &((EKF3MeasObj *)a[0])->pq;
    if (read_real(a[1], "EKF3.update: z", 0, pq->meas.m, z.v) < 0) {
        return NULL;
    }
    self->busy = 1;
    gf_status st = gf_ekf3_update_prepared(&self->ekf, pq, &z, &info);
    self->busy = 0;
    if (st != GF_OK) {
        if (PyErr_Occurred()) {
            return NULL;
        }
        return raise_status(st, "EKF3.update", NULL,
                            st == GF_ERR_GATED ? info.y : NULL, info.m,
                            info.nis);
    }
    self->last = info;
    self->has_last = 1;
    Py_RETURN_NONE;
}

static PyObject *EKF3_sigma(PyObject *self_, PyObject *unused)
{
    gf_mat3 s;
    (void)unused;
    gf_status st = gf_ekf3_cov(&((EKF3Obj *)self_)->ekf, &s);
    if (st != GF_OK) {
        return raise_status(st, "EKF3.sigma", NULL, NULL, 0, 0);
    }
    return new_array(3, 3, &s.m[0][0]);
}

static PyObject *EKF3_get(PyObject *self_, void *which)
{
    EKF3Obj *self = (EKF3Obj *)self_;
    switch ((int)(size_t)which) {
    case 0:
        return new_array(3, 0, self->ekf.mu.v);
    case 1:
        return PyFloat_FromDouble(self->has_last ? (double)self->last.nis
                                                 : (double)NAN);
    default:
        if (!self->has_last) {
            Py_RETURN_NONE;
        }
        return new_array(self->last.m, 0, self->last.y);
    }
}

static PyMethodDef EKF3_methods[] = {
    {"predict", (PyCFunction)(void (*)(void))EKF3_predict,
     METH_FASTCALL | METH_KEYWORDS,
     "predict(motion, u=None)\n\n"
     "Prediction (Table 3.3, lines 2-3), G = dg/dx at mu:\n"
     "    mu_bar = g(u, mu),   Sigma_bar = G Sigma G^T + R\n"
     "on the factors; the heading mu[2] is kept in (-pi, pi]. u is handed\n"
     "to g as is (forward_turn: u = (d, phi)). A callback's exception\n"
     "propagates; every failure leaves the belief unchanged."},
    {"update", (PyCFunction)(void (*)(void))EKF3_update,
     METH_FASTCALL | METH_KEYWORDS,
     "update(meas, z)\n\n"
     "Correction (Table 3.3, lines 4-6), H = dh/dx at mu_bar:\n"
     "    y = z - h(mu_bar) (angles in meas.angle_mask wrapped),\n"
     "    S = H Sigma_bar H^T + Q,  K = Sigma_bar H^T S^-1,\n"
     "    mu = mu_bar + K y,  Sigma = (I - K H) Sigma_bar,  NIS = y^T S^-1 y.\n"
     "Gated carries the innovation and NIS; every failure leaves the\n"
     "belief unchanged."},
    {"sigma", EKF3_sigma, METH_NOARGS,
     "sigma() -> (3, 3) array: Sigma = U D U^T, exactly symmetric."},
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef EKF3_getset[] = {
    {"mu", EKF3_get, NULL, "the mean (x, y, theta), a (3,) copy", (void *)0},
    {"nis", EKF3_get, NULL,
     "NIS = y^T S^-1 y of the last accepted update (nan before any)",
     (void *)1},
    {"innovation", EKF3_get, NULL,
     "y = z - h(mu_bar) of the last accepted update (None before any)",
     (void *)2},
    {NULL, NULL, NULL, NULL, NULL},
};

// ---- KF and EKF: n states -------------------------------------------------

typedef struct {
    PyObject_HEAD gf_kf_pmodel pm;
    gf_real A[NMAX * NMAX], B[NMAX * NMAX], R[NMAX * NMAX], c[NMAX];
} KFModelObj;

typedef struct {
    PyObject_HEAD gf_kf_pmeas pq;
    gf_real C[NMAX * NMAX], Q[NMAX * NMAX], c[NMAX];
} KFMeasObj;

typedef struct {
    PyObject_HEAD gf_ekf_pmotion pm;
    gf_real R[NMAX * NMAX];
    PyObject *g;
    PyObject *cur_u;
} EKFMotionObj;

typedef struct {
    PyObject_HEAD gf_ekf_pmeas pq;
    gf_real Q[NMAX * NMAX];
    PyObject *h;
} EKFMeasObj;

// KF and EKF share it: the belief, the workspace its steps use (its own,
// so that a callback may step another filter) and the last update's.
typedef struct {
    PyObject_HEAD gf_kf kf;
    gf_kf_work work;
    gf_kf_innovation last;
    int has_last;
    int busy;
} KFObj;

typedef KFObj EKFObj;

static PyTypeObject KFModel_Type, KFMeas_Type, KF_Type;
static PyTypeObject EKFMotion_Type, EKFMeas_Type, EKF_Type;

// An n x n (or m x m) square matrix's size, 1..NMAX.
static int square_size(PyObject *obj, const char *name, npy_intp *n)
{
    npy_intp r, c;
    if (shape_of(obj, name, 1, &r, &c) < 0) {
        return -1;
    }
    if (r != c || r < 1 || r > NMAX) {
        bad_arg("%s must be n x n with n = 1..%d, got (%ld, %ld)", name, NMAX,
                (long)r, (long)c);
        return -1;
    }
    *n = r;
    return 0;
}

static int KFModel_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"A", "R", "B", "c", NULL};
    KFModelObj *self = (KFModelObj *)self_;
    PyObject *A, *R, *B = Py_None, *c = Py_None;
    gf_kf_model m;
    npy_intp n, nu = 0, br;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|OO:KFModel", names, &A, &R,
                                     &B, &c)) {
        return -1;
    }
    if (square_size(A, "KFModel: A", &n) < 0 ||
        read_real(A, "KFModel: A", n, n, self->A) < 0 ||
        read_real(R, "KFModel: R", n, n, self->R) < 0) {
        return -1;
    }
    if (B != Py_None) {
        if (shape_of(B, "KFModel: B", 0, &br, &nu) < 0) {
            return -1;
        }
        if (br != n || nu < 1 || nu > NMAX) {
            bad_arg("KFModel: B must have shape (%ld, nu), nu = 1..%d, got "
                    "(%ld, %ld)",
                    (long)n, NMAX, (long)br, (long)nu);
            return -1;
        }
        if (read_real(B, "KFModel: B", n, nu, self->B) < 0) {
            return -1;
        }
    }
    if (c != Py_None && read_real(c, "KFModel: c", 0, n, self->c) < 0) {
        return -1;
    }
    m.nu = (unsigned)nu;
    m.A = self->A;
    m.B = nu ? self->B : NULL;
    m.R = self->R;
    m.c = c != Py_None ? self->c : NULL;
    gf_kf_work *w = PyMem_Malloc(sizeof *w);
    if (!w) {
        PyErr_NoMemory();
        return -1;
    }
    gf_status st = gf_kf_prepare_model(&self->pm, (unsigned)n, &m, w);
    PyMem_Free(w);
    if (st != GF_OK) {
        raise_status(st, "KFModel", NULL, NULL, 0, 0);
        return -1;
    }
    return 0;
}

static PyObject *KFModel_get(PyObject *self_, void *which)
{
    KFModelObj *self = (KFModelObj *)self_;
    npy_intp n = self->pm.n, nu = self->pm.model.nu;
    switch ((int)(size_t)which) {
    case 0:
        return new_array(n, n, self->A);
    case 1:
        return new_array(n, n, self->R);
    case 2:
        if (!nu) {
            Py_RETURN_NONE;
        }
        return new_array(n, nu, self->B);
    case 3:
        if (!self->pm.model.c) {
            Py_RETURN_NONE;
        }
        return new_array(n, 0, self->c);
    case 4:
        return PyLong_FromSsize_t(n);
    default:
        return PyLong_FromSsize_t(nu);
    }
}

static PyGetSetDef KFModel_getset[] = {
    {"A", KFModel_get, NULL, "state transition (n, n)", (void *)0},
    {"R", KFModel_get, NULL, "process noise covariance (n, n)", (void *)1},
    {"B", KFModel_get, NULL, "control matrix (n, nu), or None", (void *)2},
    {"c", KFModel_get, NULL, "constant motion term (n,), or None", (void *)3},
    {"n", KFModel_get, NULL, "states", (void *)4},
    {"nu", KFModel_get, NULL, "controls (0: none)", (void *)5},
    {NULL, NULL, NULL, NULL, NULL},
};

static int KFMeas_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"C", "Q", "c", "gate", NULL};
    KFMeasObj *self = (KFMeasObj *)self_;
    PyObject *C, *Q, *c = Py_None, *gate = NULL;
    gf_kf_meas me;
    npy_intp m, n;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|OO:KFMeas", names, &C, &Q,
                                     &c, &gate)) {
        return -1;
    }
    if (shape_of(C, "KFMeas: C", 1, &m, &n) < 0) {
        return -1;
    }
    if (n < 1 || n > NMAX || m < 1 || m > n) {
        bad_arg("KFMeas: C must be m x n with 1 <= m <= n <= %d, got "
                "(%ld, %ld)",
                NMAX, (long)m, (long)n);
        return -1;
    }
    memset(&me, 0, sizeof me);
    if (read_real(C, "KFMeas: C", m, n, self->C) < 0 ||
        read_real(Q, "KFMeas: Q", m, m, self->Q) < 0 ||
        (c != Py_None && read_real(c, "KFMeas: c", 0, m, self->c) < 0) ||
        read_gate(gate, "KFMeas", &me.gate) < 0) {
        return -1;
    }
    me.m = (unsigned)m;
    me.C = self->C;
    me.Q = self->Q;
    me.c = c != Py_None ? self->c : NULL;
    gf_kf_work *w = PyMem_Malloc(sizeof *w);
    if (!w) {
        PyErr_NoMemory();
        return -1;
    }
    gf_status st = gf_kf_prepare_meas(&self->pq, (unsigned)n, &me, w);
    PyMem_Free(w);
    if (st != GF_OK) {
        raise_status(st, "KFMeas", NULL, NULL, 0, 0);
        return -1;
    }
    return 0;
}

static PyObject *KFMeas_get(PyObject *self_, void *which)
{
    KFMeasObj *self = (KFMeasObj *)self_;
    npy_intp n = self->pq.n, m = self->pq.meas.m;
    switch ((int)(size_t)which) {
    case 0:
        return new_array(m, n, self->C);
    case 1:
        return new_array(m, m, self->Q);
    case 2:
        if (!self->pq.meas.c) {
            Py_RETURN_NONE;
        }
        return new_array(m, 0, self->c);
    case 3:
        return PyFloat_FromDouble((double)self->pq.meas.gate);
    case 4:
        return PyLong_FromSsize_t(m);
    default:
        return PyLong_FromSsize_t(n);
    }
}

static PyGetSetDef KFMeas_getset[] = {
    {"C", KFMeas_get, NULL, "measurement matrix (m, n)", (void *)0},
    {"Q", KFMeas_get, NULL, "measurement noise covariance (m, m)", (void *)1},
    {"c", KFMeas_get, NULL, "constant measurement term (m,), or None",
     (void *)2},
    {"gate", KFMeas_get, NULL, "chi-square gate on the NIS (0: none)",
     (void *)3},
    {"m", KFMeas_get, NULL, "measured quantities", (void *)4},
    {"n", KFMeas_get, NULL, "states", (void *)5},
    {NULL, NULL, NULL, NULL, NULL},
};

// The Python motion g(mu, u) -> (mu_bar, G) behind gf_ekf's callback.
static gf_status ekf_g_py(void *ctx, unsigned n, const gf_real *mu,
                          const gf_real *u, gf_real *mu_bar, gf_real *G)
{
    EKFMotionObj *mo = (EKFMotionObj *)ctx;
    PyObject *mu_a = new_array(n, 0, mu), *r, *seq;
    (void)u;
    if (!mu_a) {
        return GF_ERR_MODEL;
    }
    r = PyObject_CallFunctionObjArgs(mo->g, mu_a,
                                     mo->cur_u ? mo->cur_u : Py_None, NULL);
    Py_DECREF(mu_a);
    if (!r) {
        return GF_ERR_MODEL;
    }
    seq = PySequence_Fast(r, "");
    Py_DECREF(r);
    if (!seq || PySequence_Fast_GET_SIZE(seq) != 2) {
        Py_XDECREF(seq);
        PyErr_Clear();
        bad_arg("EKF motion g must return (mu_bar, G)");
        return GF_ERR_MODEL;
    }
    int bad = read_real(PySequence_Fast_GET_ITEM(seq, 0), "g's mu_bar", 0, n,
                        mu_bar) < 0 ||
              read_real(PySequence_Fast_GET_ITEM(seq, 1), "g's G", n, n, G) < 0;
    Py_DECREF(seq);
    return bad ? GF_ERR_MODEL : GF_OK;
}

// The Python measurement h(mu_bar) -> (z_hat, H) behind gf_ekf's callback.
static gf_status ekf_h_py(void *ctx, unsigned n, unsigned m,
                          const gf_real *mu_bar, gf_real *z_hat, gf_real *H)
{
    EKFMeasObj *me = (EKFMeasObj *)ctx;
    PyObject *mu_a = new_array(n, 0, mu_bar), *r, *seq;
    if (!mu_a) {
        return GF_ERR_MODEL;
    }
    r = PyObject_CallFunctionObjArgs(me->h, mu_a, NULL);
    Py_DECREF(mu_a);
    if (!r) {
        return GF_ERR_MODEL;
    }
    seq = PySequence_Fast(r, "");
    Py_DECREF(r);
    if (!seq || PySequence_Fast_GET_SIZE(seq) != 2) {
        Py_XDECREF(seq);
        PyErr_Clear();
        bad_arg("EKF measurement h must return (z_hat, H)");
        return GF_ERR_MODEL;
    }
    int bad = read_real(PySequence_Fast_GET_ITEM(seq, 0), "h's z_hat", 0, m,
                        z_hat) < 0 ||
              read_real(PySequence_Fast_GET_ITEM(seq, 1), "h's H", m, n, H) < 0;
    Py_DECREF(seq);
    return bad ? GF_ERR_MODEL : GF_OK;
}

static int EKFMotion_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"g", "R", NULL};
    EKFMotionObj *self = (EKFMotionObj *)self_;
    PyObject *g, *R;
    gf_ekf_motion mo;
    npy_intp n;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO:EKFMotion", names, &g, &R)) {
        return -1;
    }
    if (!PyCallable_Check(g)) {
        bad_arg("EKFMotion: g must be callable");
        return -1;
    }
    if (square_size(R, "EKFMotion: R", &n) < 0 ||
        read_real(R, "EKFMotion: R", n, n, self->R) < 0) {
        return -1;
    }
    mo.g = ekf_g_py;
    mo.ctx = self;
    mo.R = self->R;
    gf_kf_work *w = PyMem_Malloc(sizeof *w);
    if (!w) {
        PyErr_NoMemory();
        return -1;
    }
    gf_status st = gf_ekf_prepare_motion(&self->pm, (unsigned)n, &mo, w);
    PyMem_Free(w);
    if (st != GF_OK) {
        raise_status(st, "EKFMotion", NULL, NULL, 0, 0);
        return -1;
    }
    Py_INCREF(g);
    Py_XSETREF(self->g, g);
    return 0;
}

static int EKFMeas_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"h", "Q", "n", "angle_mask", "gate", NULL};
    EKFMeasObj *self = (EKFMeasObj *)self_;
    PyObject *h, *Q, *gate = NULL;
    unsigned n, angle_mask = 0;
    gf_ekf_meas me;
    npy_intp m;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OOI|IO:EKFMeas", names, &h, &Q,
                                     &n, &angle_mask, &gate)) {
        return -1;
    }
    if (!PyCallable_Check(h)) {
        bad_arg("EKFMeas: h must be callable");
        return -1;
    }
    if (square_size(Q, "EKFMeas: Q", &m) < 0 ||
        read_real(Q, "EKFMeas: Q", m, m, self->Q) < 0 ||
        read_gate(gate, "EKFMeas", &me.gate) < 0) {
        return -1;
    }
    me.m = (unsigned)m;
    me.h = ekf_h_py;
    me.ctx = self;
    me.Q = self->Q;
    me.angle_mask = angle_mask;
    gf_kf_work *w = PyMem_Malloc(sizeof *w);
    if (!w) {
        PyErr_NoMemory();
        return -1;
    }
    gf_status st = gf_ekf_prepare_meas(&self->pq, n, &me, w);
    PyMem_Free(w);
    if (st != GF_OK) {
        raise_status(st, "EKFMeas", NULL, NULL, 0, 0);
        return -1;
    }
    Py_INCREF(h);
    Py_XSETREF(self->h, h);
    return 0;
}

static int EKFMotion_traverse(PyObject *self, visitproc visit, void *arg)
{
    Py_VISIT(((EKFMotionObj *)self)->g);
    return 0;
}
static int EKFMotion_clear(PyObject *self)
{
    Py_CLEAR(((EKFMotionObj *)self)->g);
    return 0;
}
static void EKFMotion_dealloc(PyObject *self)
{
    PyObject_GC_UnTrack(self);
    EKFMotion_clear(self);
    Py_TYPE(self)->tp_free(self);
}
static int EKFMeas_traverse(PyObject *self, visitproc visit, void *arg)
{
    Py_VISIT(((EKFMeasObj *)self)->h);
    return 0;
}
static int EKFMeas_clear(PyObject *self)
{
    Py_CLEAR(((EKFMeasObj *)self)->h);
    return 0;
}
static void EKFMeas_dealloc(PyObject *self)
{
    PyObject_GC_UnTrack(self);
    EKFMeas_clear(self);
    Py_TYPE(self)->tp_free(self);
}

static PyObject *EKFMotion_get(PyObject *self_, void *which)
{
    EKFMotionObj *self = (EKFMotionObj *)self_;
    switch ((int)(size_t)which) {
    case 0:
        if (!self->g) {
            Py_RETURN_NONE;
        }
        Py_INCREF(self->g);
        return self->g;
    case 1:
        return new_array(self->pm.n, self->pm.n, self->R);
    default:
        return PyLong_FromUnsignedLong(self->pm.n);
    }
}

static PyObject *EKFMeas_get(PyObject *self_, void *which)
{
    EKFMeasObj *self = (EKFMeasObj *)self_;
    const gf_ekf_meas *me = &self->pq.meas;
    switch ((int)(size_t)which) {
    case 0:
        if (!self->h) {
            Py_RETURN_NONE;
        }
        Py_INCREF(self->h);
        return self->h;
    case 1:
        return new_array(me->m, me->m, self->Q);
    case 2:
        return PyLong_FromUnsignedLong(me->m);
    case 3:
        return PyLong_FromUnsignedLong(self->pq.n);
    case 4:
        return PyLong_FromUnsignedLong(me->angle_mask);
    default:
        return PyFloat_FromDouble((double)me->gate);
    }
}

static PyGetSetDef EKFMotion_getset[] = {
    {"g", EKFMotion_get, NULL, "the motion g(mu, u) -> (mu_bar, G)", (void *)0},
    {"R", EKFMotion_get, NULL, "process noise covariance (n, n)", (void *)1},
    {"n", EKFMotion_get, NULL, "states", (void *)2},
    {NULL, NULL, NULL, NULL, NULL},
};

static PyGetSetDef EKFMeas_getset[] = {
    {"h", EKFMeas_get, NULL, "the measurement h(mu_bar) -> (z_hat, H)",
     (void *)0},
    {"Q", EKFMeas_get, NULL, "measurement noise covariance (m, m)", (void *)1},
    {"m", EKFMeas_get, NULL, "measured quantities", (void *)2},
    {"n", EKFMeas_get, NULL, "states", (void *)3},
    {"angle_mask", EKFMeas_get, NULL, "bit i: residual i is an angle",
     (void *)4},
    {"gate", EKFMeas_get, NULL, "chi-square gate on the NIS (0: none)",
     (void *)5},
    {NULL, NULL, NULL, NULL, NULL},
};

static int KF_init_common(KFObj *self, PyObject *mu, PyObject *sigma,
                          unsigned angles, int ekf, const char *who)
{
    gf_real m[NMAX], s[NMAX * NMAX];
    npy_intp n, r;
    if (self->busy) {
        PyErr_Format(PyExc_RuntimeError,
                     "%s: re-initialised from its own "
                     "callback",
                     who);
        return -1;
    }
    if (shape_of(mu, who, 0, &n, &r) < 0) {
        return -1;
    }
    if (r != 1 || n < 1 || n > NMAX) {
        bad_arg("%s: mu must have shape (n,), n = 1..%d", who, NMAX);
        return -1;
    }
    char name[64];
    PyOS_snprintf(name, sizeof name, "%s: mu", who);
    if (read_real(mu, name, 0, n, m) < 0) {
        return -1;
    }
    PyOS_snprintf(name, sizeof name, "%s: sigma", who);
    if (read_real(sigma, name, n, n, s) < 0) {
        return -1;
    }
    gf_status st =
        ekf ? gf_ekf_init(&self->kf, (unsigned)n, m, s, angles, &self->work)
            : gf_kf_init(&self->kf, (unsigned)n, m, s, &self->work);
    if (st != GF_OK) {
        raise_status(st, who, NULL, NULL, 0, 0);
        return -1;
    }
    self->has_last = 0;
    return 0;
}

static int KF_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"mu", "sigma", NULL};
    PyObject *mu, *sigma;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO:KF", names, &mu, &sigma)) {
        return -1;
    }
    return KF_init_common((KFObj *)self_, mu, sigma, 0, 0, "KF");
}

static int EKF_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"mu", "sigma", "angles", NULL};
    PyObject *mu, *sigma;
    unsigned angles = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|I:EKF", names, &mu, &sigma,
                                     &angles)) {
        return -1;
    }
    return KF_init_common((KFObj *)self_, mu, sigma, angles, 1, "EKF");
}

static PyObject *KF_predict(PyObject *self_, PyObject *const *args,
                            Py_ssize_t nargs, PyObject *kwnames)
{
    static const char *const names[] = {"model", "u"};
    PyObject *a[2];
    KFObj *self = (KFObj *)self_;
    gf_real u[NMAX];
    if (get_args("predict", args, nargs, kwnames, names, 1, 2, a) < 0) {
        return NULL;
    }
    if (!PyObject_TypeCheck(a[0], &KFModel_Type)) {
        return bad_arg("KF.predict: model must be a KFModel, not %s",
                       Py_TYPE(a[0])->tp_name);
    }
    const gf_kf_pmodel *pm = &((KFModelObj *)a[0])->pm;
    if (pm->n != self->kf.n) {
        return bad_arg("KF.predict: the model is for %u states, the filter "
                       "has %u",
                       pm->n, self->kf.n);
    }
    int has_u = a[1] && a[1] != Py_None;
    if (has_u && !pm->model.nu) {
        return bad_arg("KF.predict: u given, the model has no B");
    }
    if (has_u && read_real(a[1], "KF.predict: u", 0, pm->model.nu, u) < 0) {
        return NULL;
    }
    gf_status st =
        gf_kf_predict_prepared(&self->kf, pm, has_u ? u : NULL, &self->work);
    if (st != GF_OK) {
        return raise_status(st, "KF.predict", NULL, NULL, 0, 0);
    }
    Py_RETURN_NONE;
}

static PyObject *KF_update(PyObject *self_, PyObject *const *args,
                           Py_ssize_t nargs, PyObject *kwnames)
{
    static const char *const names[] = {"meas", "z"};
    PyObject *a[2];
    KFObj *self = (KFObj *)self_;
    gf_real z[NMAX];
    gf_kf_innovation info;
    if (get_args("update", args, nargs, kwnames, names, 2, 2, a) < 0) {
        return NULL;
    }
    if (!PyObject_TypeCheck(a[0], &KFMeas_Type)) {
        return bad_arg("KF.update: meas must be a KFMeas, not %s",
                       Py_TYPE(a[0])->tp_name);
    }
    const gf_kf_pmeas *pq = &((KFMeasObj *)a[0])->pq;
    if (pq->n != self->kf.n) {
        return bad_arg("KF.update: the measurement is for %u states, the "
                       "filter has %u",
                       pq->n, self->kf.n);
    }
    if (read_real(a[1], "KF.update: z", 0, pq->meas.m, z) < 0) {
        return NULL;
    }
    gf_status st = gf_kf_update_prepared(&self->kf, pq, z, &info, &self->work);
    if (st != GF_OK) {
        return raise_status(st, "KF.update", NULL,
                            st == GF_ERR_GATED ? info.y : NULL, info.m,
                            info.nis);
    }
    self->last = info;
    self->has_last = 1;
    Py_RETURN_NONE;
}

static PyObject *KF_run(PyObject *self_, PyObject *const *args,
                        Py_ssize_t nargs, PyObject *kwnames)
{
    static const char *const names[] = {"model", "meas", "u", "z", "steps"};
    PyObject *a[5], *U = NULL, *Z = NULL, *mu_o = NULL, *sg_o = NULL,
                    *nis_o = NULL, *st_o = NULL, *out = NULL;
    KFObj *self = (KFObj *)self_;
    const gf_kf_pmodel *pm = NULL;
    const gf_kf_pmeas *pq = NULL;
    npy_intp N = -1, n = self->kf.n, nu = 0, m = 0;
    if (get_args("run", args, nargs, kwnames, names, 0, 5, a) < 0) {
        return NULL;
    }
    if (a[0] && a[0] != Py_None) {
        if (!PyObject_TypeCheck(a[0], &KFModel_Type)) {
            return bad_arg("KF.run: model must be a KFModel or None");
        }
        pm = &((KFModelObj *)a[0])->pm;
        if ((npy_intp)pm->n != n) {
            return bad_arg("KF.run: the model is for %u states, the filter "
                           "has %ld",
                           pm->n, (long)n);
        }
        nu = pm->model.nu;
    }
    if (a[1] && a[1] != Py_None) {
        if (!PyObject_TypeCheck(a[1], &KFMeas_Type)) {
            return bad_arg("KF.run: meas must be a KFMeas or None");
        }
        pq = &((KFMeasObj *)a[1])->pq;
        if ((npy_intp)pq->n != n) {
            return bad_arg("KF.run: the measurement is for %u states, the "
                           "filter has %ld",
                           pq->n, (long)n);
        }
        m = pq->meas.m;
    }
    if (a[4] && a[4] != Py_None) {
        N = (npy_intp)PyLong_AsSsize_t(a[4]);
        if (N == -1 && PyErr_Occurred()) {
            return NULL;
        }
        if (N < 0) {
            return bad_arg("KF.run: steps must be >= 0");
        }
    }
    if (a[2] && a[2] != Py_None) {
        if (!nu) {
            return bad_arg("KF.run: u given, the model has no B");
        }
        U = PyArray_FROMANY(a[2], NPY_GF, 1, 2,
                            NPY_ARRAY_CARRAY_RO | NPY_ARRAY_FORCECAST);
        if (!U) {
            PyErr_Clear();
            return bad_arg("KF.run: u must be an (N, nu) array");
        }
        npy_intp uc = PyArray_NDIM((PyArrayObject *)U) == 2
                          ? PyArray_DIM((PyArrayObject *)U, 1)
                          : 1;
        if (uc != nu || (PyArray_NDIM((PyArrayObject *)U) == 1 && nu != 1) ||
            (N >= 0 && PyArray_DIM((PyArrayObject *)U, 0) != N)) {
            Py_DECREF(U);
            return bad_arg("KF.run: u must have shape (steps, %ld)", (long)nu);
        }
        N = PyArray_DIM((PyArrayObject *)U, 0);
    }
    if (a[3] && a[3] != Py_None) {
        if (!pq) {
            Py_XDECREF(U);
            return bad_arg("KF.run: z without meas");
        }
        Z = PyArray_FROMANY(a[3], NPY_GF, 1, 2,
                            NPY_ARRAY_CARRAY_RO | NPY_ARRAY_FORCECAST);
        if (!Z) {
            PyErr_Clear();
            Py_XDECREF(U);
            return bad_arg("KF.run: z must be an (N, m) array");
        }
        npy_intp zc = PyArray_NDIM((PyArrayObject *)Z) == 2
                          ? PyArray_DIM((PyArrayObject *)Z, 1)
                          : 1;
        if (zc != m || (PyArray_NDIM((PyArrayObject *)Z) == 1 && m != 1) ||
            (N >= 0 && PyArray_DIM((PyArrayObject *)Z, 0) != N)) {
            Py_XDECREF(U);
            Py_DECREF(Z);
            return bad_arg("KF.run: z must have shape (steps, %ld)", (long)m);
        }
        N = PyArray_DIM((PyArrayObject *)Z, 0);
    }
    if (N < 0) {
        return bad_arg("KF.run: give u, z or steps");
    }
    npy_intp d3[3] = {N, n, n};
    mu_o = PyArray_SimpleNew(2, d3, NPY_GF);
    sg_o = PyArray_SimpleNew(3, d3, NPY_GF);
    nis_o = PyArray_SimpleNew(1, d3, NPY_GF);
    st_o = PyArray_SimpleNew(1, d3, NPY_INT8);
    gf_kf *saved = PyMem_Malloc(sizeof *saved);
    if (!mu_o || !sg_o || !nis_o || !st_o || !saved) {
        if (!saved) {
            PyErr_NoMemory();
        }
        goto done;
    }
    {
        const gf_real *u =
            U ? (const gf_real *)PyArray_DATA((PyArrayObject *)U) : NULL;
        const gf_real *z =
            Z ? (const gf_real *)PyArray_DATA((PyArrayObject *)Z) : NULL;
        gf_real *mo = (gf_real *)PyArray_DATA((PyArrayObject *)mu_o);
        gf_real *so = (gf_real *)PyArray_DATA((PyArrayObject *)sg_o);
        gf_real *no = (gf_real *)PyArray_DATA((PyArrayObject *)nis_o);
        signed char *sto = (signed char *)PyArray_DATA((PyArrayObject *)st_o);
        const gf_kf_innovation saved_last = self->last;
        const int saved_has = self->has_last;
        *saved = self->kf;
        for (npy_intp k = 0; k < N; k++) {
            gf_status st = GF_OK;
            gf_kf_innovation info;
            no[k] = (gf_real)NAN;
            if (pm) {
                st = gf_kf_predict_prepared(&self->kf, pm,
                                            u ? u + nu * k : NULL, &self->work);
            }
            if (st == GF_OK && z) {
                const gf_real *zk = z + m * k;
                int present = 1;
                for (npy_intp i = 0; i < m; i++) {
                    present &= !isnan(zk[i]);
                }
                if (present) {
                    st = gf_kf_update_prepared(&self->kf, pq, zk, &info,
                                               &self->work);
                    if (st == GF_OK || st == GF_ERR_GATED) {
                        no[k] = info.nis;
                    }
                    if (st == GF_OK) {
                        self->last = info;
                        self->has_last = 1;
                    }
                }
            }
            if (st != GF_OK && st != GF_ERR_GATED) {
                self->kf = *saved;
                self->last = saved_last;
                self->has_last = saved_has;
                raise_status(st, "KF.run", NULL, NULL, 0, 0);
                set_step(k);
                goto done;
            }
            sto[k] = (signed char)st;
            memcpy(mo + n * k, self->kf.mu, (size_t)n * sizeof(gf_real));
            gf_kf_cov(&self->kf, so + n * n * k);
        }
    }
    out = PyTuple_Pack(4, mu_o, sg_o, nis_o, st_o);
done:
    PyMem_Free(saved);
    Py_XDECREF(U);
    Py_XDECREF(Z);
    Py_XDECREF(mu_o);
    Py_XDECREF(sg_o);
    Py_XDECREF(nis_o);
    Py_XDECREF(st_o);
    return out;
}

static PyObject *EKF_predict(PyObject *self_, PyObject *const *args,
                             Py_ssize_t nargs, PyObject *kwnames)
{
    static const char *const names[] = {"motion", "u"};
    PyObject *a[2], *U = NULL;
    KFObj *self = (KFObj *)self_;
    if (get_args("predict", args, nargs, kwnames, names, 1, 2, a) < 0) {
        return NULL;
    }
    if (!PyObject_TypeCheck(a[0], &EKFMotion_Type)) {
        return bad_arg("EKF.predict: motion must be an EKFMotion, not %s",
                       Py_TYPE(a[0])->tp_name);
    }
    EKFMotionObj *mo = (EKFMotionObj *)a[0];
    if (mo->pm.n != self->kf.n) {
        return bad_arg("EKF.predict: the motion is for %u states, the filter "
                       "has %u",
                       mo->pm.n, self->kf.n);
    }
    if (self->busy) {
        PyErr_SetString(PyExc_RuntimeError,
                        "EKF.predict called from this filter's own callback");
        return NULL;
    }
    if (a[1] && a[1] != Py_None) {
        U = PyArray_FROMANY(a[1], NPY_GF, 0, 1,
                            NPY_ARRAY_CARRAY | NPY_ARRAY_FORCECAST |
                                NPY_ARRAY_ENSURECOPY);
        if (!U) {
            PyErr_Clear();
            return bad_arg("EKF.predict: u must be a vector of numbers");
        }
    }
    PyObject *prev_u = mo->cur_u;
    mo->cur_u = U;
    self->busy = 1;
    gf_status st = gf_ekf_predict_prepared(
        &self->kf, &mo->pm,
        U ? (const gf_real *)PyArray_DATA((PyArrayObject *)U) : NULL,
        &self->work);
    self->busy = 0;
    mo->cur_u = prev_u;
    Py_XDECREF(U);
    if (st != GF_OK) {
        if (PyErr_Occurred()) {
            return NULL;
        }
        return raise_status(st, "EKF.predict", NULL, NULL, 0, 0);
    }
    Py_RETURN_NONE;
}

static PyObject *EKF_update(PyObject *self_, PyObject *const *args,
                            Py_ssize_t nargs, PyObject *kwnames)
{
    static const char *const names[] = {"meas", "z"};
    PyObject *a[2];
    KFObj *self = (KFObj *)self_;
    gf_real z[NMAX];
    gf_kf_innovation info;
    if (get_args("update", args, nargs, kwnames, names, 2, 2, a) < 0) {
        return NULL;
    }
    if (!PyObject_TypeCheck(a[0], &EKFMeas_Type)) {
        return bad_arg("EKF.update: meas must be an EKFMeas, not %s",
                       Py_TYPE(a[0])->tp_name);
    }
    const gf_ekf_pmeas *pq = &((EKFMeasObj *)a[0])->pq;
    if (pq->n != self->kf.n) {
        return bad_arg("EKF.update: the measurement is for %u states, the "
                       "filter has %u",
                       pq->n, self->kf.n);
    }
    if (self->busy) {
        PyErr_SetString(PyExc_RuntimeError,
                        "EKF.update called from this filter's own callback");
        return NULL;
    }
    if (read_real(a[1], "EKF.update: z", 0, pq->meas.m, z) < 0) {
        return NULL;
    }
    self->busy = 1;
    gf_status st = gf_ekf_update_prepared(&self->kf, pq, z, &info, &self->work);
    self->busy = 0;
    if (st != GF_OK) {
        if (PyErr_Occurred()) {
            return NULL;
        }
        return raise_status(st, "EKF.update", NULL,
                            st == GF_ERR_GATED ? info.y : NULL, info.m,
                            info.nis);
    }
    self->last = info;
    self->has_last = 1;
    Py_RETURN_NONE;
}

static PyObject *KF_sigma(PyObject *self_, PyObject *unused)
{
    KFObj *self = (KFObj *)self_;
    (void)unused;
    PyObject *a = new_array(self->kf.n, self->kf.n, NULL);
    if (a) {
        gf_kf_cov(&self->kf, (gf_real *)PyArray_DATA((PyArrayObject *)a));
    }
    return a;
}

static PyObject *KF_get(PyObject *self_, void *which)
{
    KFObj *self = (KFObj *)self_;
    switch ((int)(size_t)which) {
    case 0:
        return new_array(self->kf.n, 0, self->kf.mu);
    case 1:
        return PyFloat_FromDouble(self->has_last ? (double)self->last.nis
                                                 : (double)NAN);
    case 2:
        if (!self->has_last) {
            Py_RETURN_NONE;
        }
        return new_array(self->last.m, 0, self->last.y);
    case 3:
        return PyLong_FromUnsignedLong(self->kf.n);
    default:
        return PyLong_FromUnsignedLong(self->kf.angles);
    }
}

static PyMethodDef KF_methods[] = {
    {"predict", (PyCFunction)(void (*)(void))KF_predict,
     METH_FASTCALL | METH_KEYWORDS,
     "predict(model, u=None)\n\n"
     "Prediction: mu_bar = A mu + B u + c,  Sigma_bar = A Sigma A^T + R,\n"
     "on the factors (Thornton's time update). u: model.nu entries, or\n"
     "None for no control. Every failure leaves the belief unchanged."},
    {"update", (PyCFunction)(void (*)(void))KF_update,
     METH_FASTCALL | METH_KEYWORDS,
     "update(meas, z)\n\n"
     "Correction with m = meas.m values z:\n"
     "    y = z - c - C mu_bar,  S = C Sigma_bar C^T + Q,  K = Sigma_bar C^T "
     "S^-1,\n"
     "    mu = mu_bar + K y,  Sigma = (I - K C) Sigma_bar,  NIS = y^T S^-1 "
     "y\n"
     "(Q whitened, Bierman's scalar updates). Gated carries the\n"
     "innovation and NIS; every failure leaves the belief unchanged."},
    {"sigma", KF_sigma, METH_NOARGS,
     "sigma() -> (n, n) array: Sigma = P U D U^T P^T, exactly symmetric."},
    {"run", (PyCFunction)(void (*)(void))KF_run, METH_FASTCALL | METH_KEYWORDS,
     "run(model=None, meas=None, u=None, z=None, steps=None)\n"
     "    -> (mu (N, n), sigma (N, n, n), nis (N,), status (N,))\n\n"
     "N steps in one call, as KF2.run: predict(model, u[k]) then\n"
     "update(meas, z[k]) unless z[k] has a NaN; a gated update is recorded\n"
     "and skipped; any other failure raises with exc.step and puts the\n"
     "belief back as it was before the call."},
    {NULL, NULL, 0, NULL},
};

static PyMethodDef EKF_methods[] = {
    {"predict", (PyCFunction)(void (*)(void))EKF_predict,
     METH_FASTCALL | METH_KEYWORDS,
     "predict(motion, u=None)\n\n"
     "Prediction (Table 3.3, lines 2-3), G = dg/dx at mu:\n"
     "    mu_bar = g(u, mu),  Sigma_bar = G Sigma G^T + R,\n"
     "on the factors; the states in `angles` kept in (-pi, pi]. g gets\n"
     "(mu, u) and returns (mu_bar, G). A callback's exception propagates;\n"
     "every failure leaves the belief unchanged."},
    {"update", (PyCFunction)(void (*)(void))EKF_update,
     METH_FASTCALL | METH_KEYWORDS,
     "update(meas, z)\n\n"
     "Correction (Table 3.3, lines 4-6), H = dh/dx at mu_bar:\n"
     "    y = z - h(mu_bar),  S = H Sigma_bar H^T + Q,  K = Sigma_bar H^T "
     "S^-1,\n"
     "    mu = mu_bar + K y,  Sigma = (I - K H) Sigma_bar,  NIS = y^T S^-1 "
     "y.\n"
     "h gets mu_bar and returns (z_hat, H). Gated carries the innovation\n"
     "and NIS; every failure leaves the belief unchanged."},
    {"sigma", KF_sigma, METH_NOARGS,
     "sigma() -> (n, n) array: Sigma = P U D U^T P^T, exactly symmetric."},
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef KF_getset[] = {
    {"mu", KF_get, NULL, "the mean, an (n,) copy", (void *)0},
    {"nis", KF_get, NULL,
     "NIS = y^T S^-1 y of the last accepted update (nan before any)",
     (void *)1},
    {"innovation", KF_get, NULL,
     "the innovation y of the last accepted update (None before any)",
     (void *)2},
    {"n", KF_get, NULL, "states", (void *)3},
    {"angles", KF_get, NULL, "bit i: state i is an angle (EKF)", (void *)4},
    {NULL, NULL, NULL, NULL, NULL},
};

// ---- Sigma's 2x2 helpers (cov2.h) -----------------------------------------

static PyObject *py_ellipse(PyObject *mod, PyObject *args, PyObject *kw)
{
    static char *names[] = {"sigma", "p", NULL};
    PyObject *s_o;
    double p = 0.68;
    gf_mat2 s;
    gf_ellipse e;
    (void)mod;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|d:ellipse", names, &s_o,
                                     &p) ||
        read_real(s_o, "ellipse: sigma", 2, 2, &s.m[0][0]) < 0) {
        return NULL;
    }
    gf_status st = gf_cov2_ellipse(&s, (gf_real)p, &e);
    if (st != GF_OK) {
        return raise_status(st, "ellipse", NULL, NULL, 0, 0);
    }
    return Py_BuildValue("ddd", (double)e.a, (double)e.b, (double)e.angle);
}

static PyObject *py_correlation(PyObject *mod, PyObject *arg)
{
    gf_mat2 s;
    gf_real rho;
    (void)mod;
    if (read_real(arg, "correlation: sigma", 2, 2, &s.m[0][0]) < 0) {
        return NULL;
    }
    gf_status st = gf_cov2_correlation(&s, &rho);
    if (st != GF_OK) {
        return raise_status(st, "correlation", NULL, NULL, 0, 0);
    }
    return PyFloat_FromDouble((double)rho);
}

static PyObject *py_marginal(PyObject *mod, PyObject *args)
{
    PyObject *s_o;
    unsigned i, j;
    gf_mat3 s;
    gf_mat2 out;
    (void)mod;
    if (!PyArg_ParseTuple(args, "OII:marginal", &s_o, &i, &j) ||
        read_real(s_o, "marginal: sigma", 3, 3, &s.m[0][0]) < 0) {
        return NULL;
    }
    gf_status st = gf_cov2_marginal(&s, i, j, &out);
    if (st != GF_OK) {
        return raise_status(st, "marginal", NULL, NULL, 0, 0);
    }
    return new_array(2, 2, &out.m[0][0]);
}

static PyMethodDef module_methods[] = {
    {"ellipse", (PyCFunction)(void (*)(void))py_ellipse,
     METH_VARARGS | METH_KEYWORDS,
     "ellipse(sigma, p=0.68) -> (a, b, angle)\n\n"
     "The p-probability ellipse of N(mu, sigma), sigma 2x2 PSD:\n"
     "semi-axes a >= b = sqrt(k2 lambda_i), k2 = -2 ln(1 - p), lambda_i\n"
     "sigma's eigenvalues; angle of the a axis from x (gf_cov2_ellipse)."},
    {"correlation", py_correlation, METH_O,
     "correlation(sigma) -> rho = sigma_xy / sqrt(sigma_xx sigma_yy)\n\n"
     "Undefined (a zero variance) raises Undefined (gf_cov2_correlation)."},
    {"marginal", py_marginal, METH_VARARGS,
     "marginal(sigma, i, j) -> the 2x2 block of states i and j of a 3x3 "
     "sigma\n(gf_cov2_marginal)."},
    {NULL, NULL, 0, NULL},
};

// ---- types and module -----------------------------------------------------

#define GF_TYPE(T, name, doc, init, methods, getset)                           \
    static PyTypeObject T##_Type = {                                           \
        PyVarObject_HEAD_INIT(NULL, 0).tp_name =                               \
            "gaussfilt." GF_PREC_NAME "." name,                                \
        .tp_basicsize = sizeof(T##Obj),                                        \
        .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,                  \
        .tp_doc = doc,                                                         \
        .tp_new = PyType_GenericNew,                                           \
        .tp_init = init,                                                       \
        .tp_methods = methods,                                                 \
        .tp_getset = getset,                                                   \
    }

#define GF_GC_TYPE(T, name, doc, init, getset)                                 \
    static PyTypeObject T##_Type = {                                           \
        PyVarObject_HEAD_INIT(NULL, 0).tp_name =                               \
            "gaussfilt." GF_PREC_NAME "." name,                                \
        .tp_basicsize = sizeof(T##Obj),                                        \
        .tp_flags =                                                            \
            Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE | Py_TPFLAGS_HAVE_GC,     \
        .tp_doc = doc,                                                         \
        .tp_new = PyType_GenericNew,                                           \
        .tp_init = init,                                                       \
        .tp_getset = getset,                                                   \
        .tp_traverse = T##_traverse,                                           \
        .tp_clear = T##_clear,                                                 \
        .tp_dealloc = T##_dealloc,                                             \
    }

GF_TYPE(KF2Model, "KF2Model",
        "KF2Model(A, R, B=None, c=None)\n\n"
        "KF2's motion x_t = A x_{t-1} + B u_t + c + eps, eps ~ N(0, R)\n"
        "(book names: R is the process noise; FilterPy's F and Q). A, B, R\n"
        "2x2, c (2,); B and c default to zero. Checked and factored once\n"
        "(gf_kf2_prepare_model): NonFinite, NotPSD (R) raise here.",
        KF2Model_init, NULL, KF2Model_getset);
GF_TYPE(KF2Meas, "KF2Meas",
        "KF2Meas(C, Q, c=None, gate=0.0)\n\n"
        "KF2's measurement z = C x + c + delta, delta ~ N(0, Q) of m = 1 or\n"
        "2 quantities (book names: Q is the measurement noise; FilterPy's H\n"
        "and R). C (m, 2), Q (m, m), c (m,). gate: reject an update whose\n"
        "NIS exceeds it (raises Gated); 0: no gate. Checked and factored\n"
        "once (gf_kf2_prepare_meas).",
        KF2Meas_init, NULL, KF2Meas_getset);
GF_TYPE(KF2, "KF2",
        "KF2(mu, sigma)\n\n"
        "The 2-state Kalman filter's belief N(mu, Sigma) (gf_kf2), Sigma\n"
        "kept as its factors U D U^T. sigma 2x2 symmetric PSD (zero is\n"
        "fine). Every step is the C library's; a failed one raises and\n"
        "changes nothing.",
        KF2_init, KF2_methods, KF2_getset);
GF_GC_TYPE(EKF3Motion, "EKF3Motion",
           "EKF3Motion(g, R)\n\n"
           "EKF3's motion x_t = g(u_t, x_{t-1}) + eps, eps ~ N(0, R), R 3x3\n"
           "(book names). g(mu, u) -> (mu_bar (3,), G (3, 3)), G = dg/dx at\n"
           "mu; or the built-in forward_turn (C, no Python in the step).",
           EKF3Motion_init, EKF3Motion_getset);
GF_GC_TYPE(EKF3Meas, "EKF3Meas",
           "EKF3Meas(h, Q, angle_mask=0, gate=0.0)\n\n"
           "EKF3's measurement z = h(x) + delta, delta ~ N(0, Q), Q m x m,\n"
           "m = 1..3. h(mu_bar) -> (z_hat (m,), H (m, 3)); or the built-in\n"
           "meas_x (m = 1) or meas_xy (m = 2). angle_mask bit i: residual i\n"
           "is an angle, wrapped into (-pi, pi].",
           EKF3Meas_init, EKF3Meas_getset);
GF_TYPE(EKF3, "EKF3",
        "EKF3(mu, sigma)\n\n"
        "The EKF's belief over (x, y, theta) (gf_ekf3), the heading kept in\n"
        "(-pi, pi]. sigma 3x3 symmetric PSD.",
        EKF3_init, EKF3_methods, EKF3_getset);
GF_TYPE(KFModel, "KFModel",
        "KFModel(A, R, B=None, c=None)\n\n"
        "gf_kf's motion of n states: x_t = A x_{t-1} + B u_t + c + eps,\n"
        "eps ~ N(0, R). A, R (n, n); B (n, nu) or None; c (n,) or None.",
        KFModel_init, NULL, KFModel_getset);
GF_TYPE(KFMeas, "KFMeas",
        "KFMeas(C, Q, c=None, gate=0.0)\n\n"
        "gf_kf's measurement of m quantities: z = C x + c + delta,\n"
        "delta ~ N(0, Q). C (m, n), Q (m, m), c (m,) or None.",
        KFMeas_init, NULL, KFMeas_getset);
GF_TYPE(KF, "KF",
        "KF(mu, sigma)\n\n"
        "The linear Kalman filter of n = len(mu) states (gf_kf, n up to\n"
        "GF_KF_NMAX), Sigma kept as P U D U^T P^T.",
        KF_init, KF_methods, KF_getset);
GF_GC_TYPE(EKFMotion, "EKFMotion",
           "EKFMotion(g, R)\n\n"
           "gf_ekf's motion of n states (n from R): g(mu, u) -> (mu_bar (n,),\n"
           "G (n, n)), G = dg/dx at mu; u is predict's u as given.",
           EKFMotion_init, EKFMotion_getset);
GF_GC_TYPE(EKFMeas, "EKFMeas",
           "EKFMeas(h, Q, n, angle_mask=0, gate=0.0)\n\n"
           "gf_ekf's measurement of m quantities (m from Q) for n states:\n"
           "h(mu_bar) -> (z_hat (m,), H (m, n)).",
           EKFMeas_init, EKFMeas_getset);
GF_TYPE(EKF, "EKF",
        "EKF(mu, sigma, angles=0)\n\n"
        "The extended Kalman filter of n states (gf_ekf); bit i of angles\n"
        "keeps state i in (-pi, pi].",
        EKF_init, EKF_methods, KF_getset);

static struct PyModuleDef moddef = {
    PyModuleDef_HEAD_INIT,
    MODNAME,
    "gaussfilt's C library in " GF_PREC_NAME " (use gaussfilt." GF_PREC_NAME
    ").",
    -1,
    module_methods,
    NULL,
    NULL,
    NULL,
    NULL,
};

PyMODINIT_FUNC CAT(PyInit_, GF_PY_MODULE)(void)
{
    PyObject *m, *errors;
    PyTypeObject *types[] = {&Builtin_Type, &KF2Model_Type,   &KF2Meas_Type,
                             &KF2_Type,     &EKF3Motion_Type, &EKF3Meas_Type,
                             &EKF3_Type,    &KFModel_Type,    &KFMeas_Type,
                             &KF_Type,      &EKFMotion_Type,  &EKFMeas_Type,
                             &EKF_Type};
    import_array();
    errors = PyImport_ImportModule("gaussfilt._errors");
    if (!errors) {
        return NULL;
    }
    from_status = PyObject_GetAttrString(errors, "_from_status");
    Py_DECREF(errors);
    if (!from_status) {
        return NULL;
    }
    m = PyModule_Create(&moddef);
    if (!m) {
        return NULL;
    }
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++) {
        if (PyType_Ready(types[i]) < 0) {
            goto fail;
        }
        if (i > 0) {
            const char *dot = strrchr(types[i]->tp_name, '.');
            Py_INCREF(types[i]);
            if (PyModule_AddObject(m, dot + 1, (PyObject *)types[i]) < 0) {
                Py_DECREF(types[i]);
                goto fail;
            }
        }
    }
    if (PyModule_AddObject(m, "forward_turn",
                           new_builtin(gf_ekf3_motion_forward_turn, NULL, 0,
                                       "forward_turn")) < 0 ||
        PyModule_AddObject(
            m, "meas_x", new_builtin(NULL, gf_ekf3_meas_x, 1, "meas_x")) < 0 ||
        PyModule_AddObject(m, "meas_xy",
                           new_builtin(NULL, gf_ekf3_meas_xy, 2, "meas_xy")) <
            0 ||
        PyModule_AddIntConstant(m, "NMAX", NMAX) < 0 ||
        PyModule_AddIntConstant(m, "REAL_SIZE", (long)sizeof(gf_real)) < 0 ||
        PyModule_AddObject(m, "PD_RTOL",
                           PyFloat_FromDouble((double)GF_PD_RTOL)) < 0) {
        goto fail;
    }
    return m;
fail:
    Py_DECREF(m);
    return NULL;
}
