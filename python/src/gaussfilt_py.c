// SPDX-License-Identifier: MIT
// The Python extension over gaussfilt's C library: compiled once per
// precision (GF_SINGLE_PRECISION or not) into gaussfilt._f32 and
// gaussfilt._f64 (python/CMakeLists.txt), each linked to the library built
// in that precision. Built for CPython 3.11 or later it uses only the
// limited API of 3.11 (Py_LIMITED_API, set by python/CMakeLists.txt): one
// module for every later CPython; for 3.9 and 3.10 the same source is
// compiled against that minor's full API. Every step is one call of the
// library's step on the object's own belief; nothing here computes a step.
// The last update's S, K and log-likelihood, which the library never
// forms, are computed here when read (last_update), from what the update
// kept (UKF3's S and Sigma^xz, and PF3's likelihood, summed in double as
// the library's update calls h: ukf3_update, pf3_update).
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
#include <structmember.h>
#include <numpy/arrayobject.h>
#include <numpy/arrayscalars.h>

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "gaussfilt/cov2.h"
#include "gaussfilt/ekf.h"
#include "gaussfilt/ekf3.h"
#include "gaussfilt/kf.h"
#include "gaussfilt/kf2.h"
#include "gaussfilt/pf3.h"
#include "gaussfilt/ukf3.h"

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
            if (a && PyObject_SetAttrString(exc, "args", a) < 0) {
                PyErr_Clear();
            }
            Py_XDECREF(a);
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

// The name of the class cls as Python's messages print it, into buf
// (len bytes): __module__.__qualname__, without the module for a builtin
// ("str", "numpy.ndarray", "gaussfilt.float64.KF2"). Returns buf.
static const char *class_name(PyObject *cls, char *buf, size_t len)
{
    PyObject *mod = PyObject_GetAttrString(cls, "__module__");
    PyObject *qual = PyObject_GetAttrString(cls, "__qualname__");
    PyObject *s = NULL;
    if (mod && qual && PyUnicode_Check(mod) && PyUnicode_Check(qual) &&
        PyUnicode_CompareWithASCIIString(mod, "builtins") != 0) {
        s = PyUnicode_FromFormat("%U.%U", mod, qual);
    } else if (qual && PyUnicode_Check(qual)) {
        s = qual;
        Py_INCREF(s);
    }
    const char *u = s ? PyUnicode_AsUTF8AndSize(s, NULL) : NULL;
    if (!u) {
        PyErr_Clear();
    }
    PyOS_snprintf(buf, len, "%s", u ? u : "?");
    Py_XDECREF(s);
    Py_XDECREF(qual);
    Py_XDECREF(mod);
    return buf;
}

// obj's type for a message, into buf: "None", "str", "complex".
static const char *type_name(PyObject *obj, char *buf, size_t len)
{
    if (obj == Py_None) {
        PyOS_snprintf(buf, len, "None");
        return buf;
    }
    return class_name((PyObject *)Py_TYPE(obj), buf, len);
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

// a's shape as numpy prints it: (3,), (2, 2).
static void shape_str(PyArrayObject *a, char *buf, size_t len)
{
    int nd = PyArray_NDIM(a);
    size_t k = 0;
    k += (size_t)PyOS_snprintf(buf + k, len - k, "(");
    for (int i = 0; i < nd && k < len; i++) {
        k += (size_t)PyOS_snprintf(buf + k, len - k, "%s%ld", i ? ", " : "",
                                   (long)PyArray_DIM(a, i));
    }
    if (k < len) {
        PyOS_snprintf(buf + k, len - k, nd == 1 ? ",)" : ")");
    }
}

// obj as a C-contiguous gf_real array, when it is numbers: an array or
// sequence of booleans, integers or real floating-point numbers, or one
// of them. None, text, bytes, complex numbers and objects are refused
// (BadArgument naming `name`), not parsed or truncated. NULL then.
static PyArrayObject *numeric_array(PyObject *obj, const char *name)
{
    if (obj == Py_None || PyUnicode_Check(obj) || PyBytes_Check(obj) ||
        PyByteArray_Check(obj)) {
        char tn[96];
        bad_arg("%s: not an array of numbers (%s)", name,
                type_name(obj, tn, sizeof tn));
        return NULL;
    }
    PyArrayObject *raw =
        (PyArrayObject *)PyArray_FromAny(obj, NULL, 0, 0, 0, NULL);
    if (!raw) {
        if (PyErr_ExceptionMatches(PyExc_TypeError) ||
            PyErr_ExceptionMatches(PyExc_ValueError)) {
            PyErr_Clear();
            bad_arg("%s: not an array of numbers", name);
        }
        return NULL;
    }
    const char kind = PyArray_DESCR(raw)->kind;
    if (!strchr("biuf", kind)) {
        bad_arg("%s: not an array of real numbers (%s)", name,
                kind == 'c'                  ? "complex"
                : kind == 'U' || kind == 'S' ? "text"
                                             : "objects");
        Py_DECREF(raw);
        return NULL;
    }
    PyArrayObject *a = (PyArrayObject *)PyArray_FROMANY(
        (PyObject *)raw, NPY_GF, 0, 0,
        NPY_ARRAY_CARRAY_RO | NPY_ARRAY_FORCECAST);
    Py_DECREF(raw);
    return a;
}

// 0 when obj is numbers as numeric_array takes them; else its BadArgument
// and -1.
static int numbers_only(PyObject *obj, const char *name)
{
    if (PyArray_Check(obj) &&
        strchr("biuf", PyArray_DESCR((PyArrayObject *)obj)->kind)) {
        return 0;
    }
    PyArrayObject *a = numeric_array(obj, name);
    Py_XDECREF((PyObject *)a);
    return a ? 0 : -1;
}

// 1 when x is a Python float, a numpy.float64 or numpy.float32, or a
// Python or numpy integer (not a bool) of at most 2^53 in magnitude, read
// into *out rounded once to gf_real as numpy's cast rounds it; else 0
// (numpy reads it: a larger integer would be rounded twice here), *out
// unspecified.
static int read_float_item(PyObject *x, gf_real *out)
{
    double v;
    if (PyFloat_CheckExact(x)) {
        *out = (gf_real)PyFloat_AsDouble(x);
        return 1;
    }
    // numpy's structs of its scalars (PyObject_HEAD, then the value):
    // arrayscalars.h declares them for the limited API too, only their
    // accessor PyArrayScalar_VAL is left out
    if (PyArray_IsScalar(x, Double)) {
        *out = (gf_real)((PyDoubleScalarObject *)x)->obval;
        return 1;
    }
    if (PyArray_IsScalar(x, Float)) {
        *out = (gf_real)((PyFloatScalarObject *)x)->obval;
        return 1;
    }
    if (PyLong_CheckExact(x)) {
        v = PyLong_AsDouble(x);
    } else if (PyArray_IsScalar(x, Integer)) {
        v = PyFloat_AsDouble(x);
    } else {
        return 0;
    }
    if (v == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        return 0;
    }
    if (fabs(v) > 9007199254740992.0) {
        return 0;
    }
    *out = (gf_real)v;
    return 1;
}

// 1 when seq (a list or tuple of n items) holds only numbers
// read_float_item reads, read into out; else 0, out unspecified.
static int read_flat_floats(PyObject *seq, npy_intp n, gf_real *out)
{
    const int list = PyList_CheckExact(seq);
    for (npy_intp i = 0; i < n; i++) {
        PyObject *x = list ? PyList_GetItem(seq, i) : PyTuple_GetItem(seq, i);
        if (!read_float_item(x, &out[i])) {
            return 0;
        }
    }
    return 1;
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
        (PyArray_TYPE((PyArrayObject *)obj) == NPY_GF ||
         PyArray_TYPE((PyArrayObject *)obj) == NPY_DOUBLE ||
         PyArray_TYPE((PyArrayObject *)obj) == NPY_FLOAT) &&
        PyArray_ISCARRAY_RO((PyArrayObject *)obj)) {
        // the module's type, or the other precision's: rounded entry by
        // entry below, as numpy's cast rounds them
        a = (PyArrayObject *)obj;
        Py_INCREF(obj);
    } else if (size == 1 && read_float_item(obj, out)) {
        return 0; // a Python or numpy scalar
    } else if ((PyList_CheckExact(obj) || PyTuple_CheckExact(obj)) &&
               rows <= 1 &&
               (PyList_CheckExact(obj) ? PyList_Size(obj)
                                       : PyTuple_Size(obj)) == cols &&
               read_flat_floats(obj, cols, out)) {
        return 0; // a list or tuple of such scalars
    } else {
        a = numeric_array(obj, name);
        if (!a) {
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
    if (PyArray_TYPE(a) == NPY_GF) {
        memcpy(out, PyArray_DATA(a), (size_t)size * sizeof(gf_real));
    } else if (PyArray_TYPE(a) == NPY_DOUBLE) {
        const double *d = (const double *)PyArray_DATA(a);
        for (npy_intp i = 0; i < size; i++) {
            out[i] = (gf_real)d[i];
        }
    } else {
        const float *d = (const float *)PyArray_DATA(a);
        for (npy_intp i = 0; i < size; i++) {
            out[i] = (gf_real)d[i];
        }
    }
    Py_DECREF(a);
    return 0;
}

// The shape of obj as a gf_real array (1 or 2 dimensions), and in got
// (GOT_LEN) as numpy prints it: -1 with GF_ERR_ARG's exception otherwise.
// A 1-D array is 1 x its length when vec_is_row, else its length x 1; a
// scalar is 1 x 1.
enum { GOT_LEN = 64 };
static int shape_of(PyObject *obj, const char *name, int vec_is_row,
                    npy_intp *rows, npy_intp *cols, char *got)
{
    PyArrayObject *a = numeric_array(obj, name);
    if (!a) {
        return -1;
    }
    shape_str(a, got, GOT_LEN);
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
        bad_arg("%s must be a vector or a matrix, got %s", name, got);
        return -1;
    }
    Py_DECREF(a);
    return 0;
}

// A new gf_real array of shape (d0,) (d1 == 0) or (d0, d1), from src.
// gaussfilt._sigma.SigmaArray: what the sigma properties return (an
// ndarray that can still be called as the sigma() method it was).
static PyTypeObject *sigma_type;

// A new (n, n) array of sigma_type, filled from src when src is not NULL.
static PyObject *new_sigma(npy_intp n, const gf_real *src)
{
    npy_intp dims[2] = {n, n};
    PyObject *a =
        PyArray_New(sigma_type, 2, dims, NPY_GF, NULL, NULL, 0, 0, NULL);
    if (a && src) {
        memcpy(PyArray_DATA((PyArrayObject *)a), src,
               (size_t)(n * n) * sizeof(gf_real));
    }
    return a;
}

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
        for (Py_ssize_t k = 0; k < PyTuple_Size(kwnames); k++) {
            PyObject *key = PyTuple_GetItem(kwnames, k);
            int j = 0;
            while (j < nmax &&
                   PyUnicode_CompareWithASCIIString(key, names[j])) {
                j++;
            }
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

// A real number from obj: a Python or numpy bool, integer or float, or a
// 0-d array of one. Else (text, bytes, None, complex, an array) GF_ERR_ARG's
// exception naming `name` and -1.
static int read_number(PyObject *obj, const char *name, double *out)
{
    const int real =
        PyFloat_Check(obj) || PyLong_Check(obj) ||
        PyArray_IsScalar(obj, Floating) || PyArray_IsScalar(obj, Integer) ||
        PyArray_IsScalar(obj, Bool) ||
        (PyArray_Check(obj) && PyArray_NDIM((PyArrayObject *)obj) == 0 &&
         strchr("biuf", PyArray_DESCR((PyArrayObject *)obj)->kind));
    if (real) {
        const double v = PyFloat_AsDouble(obj);
        if (!(v == -1.0 && PyErr_Occurred())) {
            *out = v;
            return 0;
        }
        PyErr_Clear(); // an integer beyond a double's range
    }
    char tn[96];
    bad_arg("%s: not a real number (%s)", name, type_name(obj, tn, sizeof tn));
    return -1;
}

// An integer in 0..max from obj: a Python or numpy integer (a bool is 0
// or 1). Else GF_ERR_ARG's exception naming `name` and -1.
static int read_count(PyObject *obj, const char *name, unsigned long max,
                      unsigned long *out)
{
    if (PyLong_Check(obj) || PyArray_IsScalar(obj, Integer)) {
        PyObject *i = PyNumber_Index(obj);
        int over = 0;
        long long v = i ? PyLong_AsLongLongAndOverflow(i, &over) : -1;
        Py_XDECREF(i);
        if (PyErr_Occurred()) {
            return -1;
        }
        if (!over && v >= 0 && (unsigned long long)v <= max) {
            *out = (unsigned long)v;
            return 0;
        }
        bad_arg("%s must be in 0..%lu", name, max);
        return -1;
    }
    char tn[96];
    bad_arg("%s: not an integer (%s)", name, type_name(obj, tn, sizeof tn));
    return -1;
}

// read_count of an unsigned (0..UINT_MAX): a mask, a size, an index; 0
// when obj is NULL (not given).
static int read_unsigned(PyObject *obj, const char *name, unsigned *out)
{
    unsigned long v = 0;
    if (obj && read_count(obj, name, 0xFFFFFFFFul, &v) < 0) {
        return -1;
    }
    *out = (unsigned)v;
    return 0;
}

// A chi-square gate from obj (NULL: 0, no gate): a number >= 0 (a NaN is
// left to the library, which refuses it); else GF_ERR_ARG's exception
// naming who's gate and -1.
static int read_gate(PyObject *obj, const char *who, gf_real *gate)
{
    char name[64];
    double g = 0.0;
    PyOS_snprintf(name, sizeof name, "%s: gate", who);
    if (obj && read_number(obj, name, &g) < 0) {
        return -1;
    }
    if (g < 0.0) {
        bad_arg("%s must be >= 0 (0: no gate), got %g", name, g);
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

static PyTypeObject *Builtin_Type;

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

// inspect.signature() of a built-in model: (mu, u, /) for a motion,
// (mu_bar, /) for a measurement, as Builtin_call takes them.
static PyObject *Builtin_signature(PyObject *self, void *unused)
{
    static const char *const motion[] = {"mu", "u"};
    static const char *const meas[] = {"mu_bar"};
    const int is_motion = ((BuiltinObj *)self)->g != NULL;
    const char *const *names = is_motion ? motion : meas;
    PyObject *inspect, *param = NULL, *kind = NULL, *params = NULL;
    PyObject *sig = NULL;
    (void)unused;
    inspect = PyImport_ImportModule("inspect");
    if (!inspect) {
        return NULL;
    }
    param = PyObject_GetAttrString(inspect, "Parameter");
    kind = param ? PyObject_GetAttrString(param, "POSITIONAL_ONLY") : NULL;
    params = kind ? PyList_New(0) : NULL;
    for (int i = 0; params && i < (is_motion ? 2 : 1); i++) {
        PyObject *p = PyObject_CallFunction(param, "sO", names[i], kind);
        if (!p || PyList_Append(params, p) < 0) {
            Py_CLEAR(params);
        }
        Py_XDECREF(p);
    }
    if (params) {
        sig = PyObject_CallMethod(inspect, "Signature", "O", params);
    }
    Py_XDECREF(params);
    Py_XDECREF(kind);
    Py_XDECREF(param);
    Py_DECREF(inspect);
    return sig;
}

static PyGetSetDef Builtin_getset[] = {
    {"__signature__", Builtin_signature, NULL, NULL, NULL},
    {NULL, NULL, NULL, NULL, NULL},
};

// Made only by the module (new_builtin): Builtin() from Python raises.
static PyObject *Builtin_new(PyTypeObject *t, PyObject *args, PyObject *kw)
{
    (void)t;
    (void)args;
    (void)kw;
    return PyErr_Format(PyExc_TypeError,
                        "cannot create 'gaussfilt.%s.Builtin' instances",
                        GF_PREC_NAME);
}

static void free_obj(PyObject *self);

static PyType_Slot Builtin_slots[] = {
    {Py_tp_doc,
     (void *)"One of the library's built-in EKF3 models, as a C function.\n\n"
             "Passed as g or h to EKF3Motion / EKF3Meas, the library calls it "
             "directly (no Python in the step). Callable from Python as well: "
             "a motion as g(mu, u) -> (mu_bar, G), a measurement as h(mu_bar) "
             "-> (z_hat, H)."},
    {Py_tp_new, (void *)Builtin_new},
    {Py_tp_call, (void *)Builtin_call},
    {Py_tp_repr, (void *)Builtin_repr},
    {Py_tp_getset, Builtin_getset},
    {Py_tp_dealloc, (void *)free_obj},
    {0, NULL},
};

static PyType_Spec Builtin_spec = {"gaussfilt." GF_PREC_NAME ".Builtin",
                                   sizeof(BuiltinObj), 0, Py_TPFLAGS_DEFAULT,
                                   Builtin_slots};

static PyObject *new_builtin(gf_ekf3_motion_fn g, gf_ekf3_meas_fn h, unsigned m,
                             const char *name)
{
    BuiltinObj *b = PyObject_New(BuiltinObj, Builtin_Type);
    if (b) {
        b->g = g;
        b->h = h;
        b->m = m;
        b->name = name;
    }
    return (PyObject *)b;
}

// ---- what the filters and models share -----------------------------------

// The argument o is given (present and not None).
static int given(PyObject *o)
{
    return o && o != Py_None;
}

// 0 when st is GF_OK; else st's exception, named `where`, and -1.
static int check(gf_status st, const char *where)
{
    if (st == GF_OK) {
        return 0;
    }
    raise_status(st, where, NULL, NULL, 0, 0);
    return -1;
}

// 0 when o is a t; else GF_ERR_ARG's exception "who: arg must be a T, not
// <o's type>" ("who: arg must be a T or None" when or_none) and -1.
static int check_type(PyObject *o, PyTypeObject *t, const char *who,
                      const char *arg, int or_none)
{
    if (PyObject_TypeCheck(o, t)) {
        return 0;
    }
    char tn[96], on[96];
    const char *name = strrchr(class_name((PyObject *)t, tn, sizeof tn), '.');
    name = name ? name + 1 : tn;
    const char *an = strchr("AEIOU", name[0]) ? "an" : "a";
    if (or_none) {
        bad_arg("%s: %s must be %s %s or None", who, arg, an, name);
    } else {
        bad_arg("%s: %s must be %s %s, not %s", who, arg, an, name,
                type_name(o, on, sizeof on));
    }
    return -1;
}

// 0 when a model or measurement (what) for got states fits a filter of n;
// else GF_ERR_ARG's exception and -1.
static int check_n(const char *who, const char *what, unsigned got, unsigned n)
{
    if (got == n) {
        return 0;
    }
    bad_arg("%s: the %s is for %u states, the filter has %u", who, what, got,
            n);
    return -1;
}

// A workspace for a model's prepare call, zeroed (the library needs no
// set-up of it; zeroed memory keeps every run of the package the same).
// NULL with MemoryError; free with PyMem_Free.
static gf_kf_work *new_work(void)
{
    gf_kf_work *w = PyMem_Calloc(1, sizeof *w);
    if (!w) {
        PyErr_NoMemory();
    }
    return w;
}

// Frees the workspace w of a prepare call that returned st: check(st, who).
static int prepared(gf_status st, gf_kf_work *w, const char *who)
{
    PyMem_Free(w);
    return check(st, who);
}

// An EKF model's Python side, first in EKF3Motion, EKF3Meas, EKFMotion and
// EKFMeas: the callable g or h (a Builtin: its C function is in the
// prepared model) and, for a motion, the step's u while the step runs.
typedef struct {
    PyObject_HEAD PyObject *fn;
    PyObject *cur_u;
    PyObject *capsule; // an EKF model's C function (c_function_of), or NULL
    const void *cfn;   // what the capsule holds (a CFunction)
} CallbackObj;

static int Callback_traverse(PyObject *self, visitproc visit, void *arg)
{
    Py_VISIT(Py_TYPE(self)); // an instance of a heap type holds its class
    Py_VISIT(((CallbackObj *)self)->fn);
    Py_VISIT(((CallbackObj *)self)->capsule);
    return 0;
}
static int Callback_clear(PyObject *self)
{
    Py_CLEAR(((CallbackObj *)self)->fn);
    ((CallbackObj *)self)->cfn = NULL;
    Py_CLEAR(((CallbackObj *)self)->capsule);
    return 0;
}
// The end of every deallocation here: the object's memory freed, then
// the reference it held to its class (a heap type) dropped.
static void free_obj(PyObject *self)
{
    PyTypeObject *t = Py_TYPE(self);
    ((freefunc)PyType_GetSlot(t, Py_tp_free))(self);
    Py_DECREF(t);
}

static void Callback_dealloc(PyObject *self)
{
    PyObject_GC_UnTrack(self);
    PyObject_ClearWeakRefs(self);
    Callback_clear(self);
    free_obj(self);
}

// The deallocation of the classes without references of their own: the
// weak references to the object cleared first.
static void Obj_dealloc(PyObject *self)
{
    PyObject_ClearWeakRefs(self);
    free_obj(self);
}

// The getter of g or h.
static PyObject *Callback_fn(PyObject *self, void *unused)
{
    PyObject *fn = ((CallbackObj *)self)->fn;
    (void)unused;
    if (!fn) {
        Py_RETURN_NONE;
    }
    Py_INCREF(fn);
    return fn;
}

// Keeps fn as the model's callable (after a successful prepare).
static void set_fn(CallbackObj *self, PyObject *fn)
{
    PyObject *old = self->fn;
    Py_INCREF(fn);
    self->fn = fn;
    Py_XDECREF(old);
}

// 0 when fn is callable; else GF_ERR_ARG's exception and -1.
static int check_callable(PyObject *fn, const char *who, const char *arg)
{
    if (PyCallable_Check(fn)) {
        return 0;
    }
    bad_arg("%s: %s must be callable", who, arg);
    return -1;
}

// ---- C functions of gf_ekf, handed over in a capsule ----------------------

// A gf_ekf motion or measurement function in C with its context, as
// _c_function makes it (gaussfilt.codegen's built models carry one as
// their callables' gf_capsule): EKFMotion and EKFMeas call it directly, no
// Python in the step. The capsule's name says the kind and the precision
// ("gaussfilt.float32.ekf_motion"); it holds what keeps ctx valid.
typedef struct {
    gf_ekf_motion_fn g; // a motion's, or NULL
    gf_ekf_meas_fn h;   // a measurement's, or NULL
    void *ctx;
    unsigned n; // states
    unsigned k; // a motion: u's entries (0: u not read); a measurement: m
    PyObject *owner;
    char name[64];
} CFunction;

static const char c_motion_name[] = "gaussfilt." GF_PREC_NAME ".ekf_motion";
static const char c_meas_name[] = "gaussfilt." GF_PREC_NAME ".ekf_meas";

static void CFunction_free(PyObject *cap)
{
    CFunction *cf = PyCapsule_GetPointer(cap, PyCapsule_GetName(cap));
    if (cf) {
        Py_XDECREF(cf->owner);
        PyMem_Free(cf);
    }
}

// _c_function(kind, name, address, ctx, n, k, owner): the capsule of the C
// function at address (a gf_ekf_motion_fn when kind is "motion", else a
// gf_ekf_meas_fn) with context ctx (an address, 0: NULL), for n states and
// k (u's entries of a motion, m of a measurement); owner is kept alive
// with it. The caller vouches for the address: nothing here can check it.
static PyObject *py_c_function(PyObject *mod, PyObject *args)
{
    const char *kind, *name;
    unsigned long long fn, ctx;
    unsigned n, k;
    PyObject *owner, *cap;
    (void)mod;
    if (!PyArg_ParseTuple(args, "ssKKIIO:_c_function", &kind, &name, &fn, &ctx,
                          &n, &k, &owner)) {
        return NULL;
    }
    const int motion = strcmp(kind, "motion") == 0;
    if (!motion && strcmp(kind, "meas") != 0) {
        return bad_arg(
            "_c_function: kind must be 'motion' or 'meas', not %.40s", kind);
    }
    if (!fn || n < 1u || n > NMAX || k > NMAX || (!motion && k < 1u)) {
        return bad_arg("_c_function: %.40s: no address, or n = %u, k = %u out "
                       "of range",
                       name, n, k);
    }
    CFunction *cf = PyMem_Calloc(1, sizeof *cf);
    if (!cf) {
        return PyErr_NoMemory();
    }
    if (motion) {
        cf->g = (gf_ekf_motion_fn)(uintptr_t)fn;
    } else {
        cf->h = (gf_ekf_meas_fn)(uintptr_t)fn;
    }
    cf->ctx = (void *)(uintptr_t)ctx;
    cf->n = n;
    cf->k = k;
    PyOS_snprintf(cf->name, sizeof cf->name, "%s", name);
    cap =
        PyCapsule_New(cf, motion ? c_motion_name : c_meas_name, CFunction_free);
    if (!cap) {
        PyMem_Free(cf);
        return NULL;
    }
    Py_INCREF(owner);
    cf->owner = owner;
    return cap;
}

// The C function of an EKF model's callable fn (who's arg: "EKFMotion",
// "g"): *cap a new reference to its gf_capsule and *cf what it holds when
// it carries one made for this module's precision and kind (motion or not);
// *cap NULL when it carries none (a Python function). 0, or -1 with
// BadArgument naming it (a capsule of the other precision or kind, or not
// one of this package's).
static int c_function_of(PyObject *fn, int motion, const char *who,
                         const char *arg, PyObject **cap, const CFunction **cf)
{
    PyObject *c = PyObject_GetAttrString(fn, "gf_capsule");
    *cap = NULL;
    *cf = NULL;
    if (!c) {
        if (!PyErr_ExceptionMatches(PyExc_AttributeError)) {
            return -1;
        }
        PyErr_Clear();
        return 0;
    }
    const char *name = PyCapsule_CheckExact(c) ? PyCapsule_GetName(c) : NULL;
    const char *want = motion ? c_motion_name : c_meas_name;
    if (!name || strncmp(name, "gaussfilt.float", 15) != 0 ||
        (strcmp(name + 17, ".ekf_motion") != 0 &&
         strcmp(name + 17, ".ekf_meas") != 0)) {
        char tn[96];
        bad_arg("%s: %s.gf_capsule is not a capsule of gaussfilt's C "
                "functions (%s)",
                who, arg, name ? name : type_name(c, tn, sizeof tn));
        Py_DECREF(c);
        return -1;
    }
    const CFunction *f = PyCapsule_GetPointer(c, name);
    if (!f) {
        Py_DECREF(c);
        return -1;
    }
    if (strcmp(name, want) != 0) {
        if (strncmp(name, want, 17) != 0) {
            bad_arg("%s: %s's C function %s is in %.7s, this module is %s", who,
                    arg, f->name, name + 10, GF_PREC_NAME);
        } else {
            bad_arg("%s: %s's C function %s is a %s, not a %s", who, arg,
                    f->name, f->g ? "motion" : "measurement",
                    motion ? "motion" : "measurement");
        }
        Py_DECREF(c);
        return -1;
    }
    *cap = c;
    *cf = f;
    return 0;
}

// The name of the C function an EKF3 or EKF motion calls (a built-in's,
// or a capsule's).
static const char *c_function_name(const CallbackObj *cb)
{
    if (cb->cfn) {
        return ((const CFunction *)cb->cfn)->name;
    }
    return ((const BuiltinObj *)cb->fn)->name;
}

// Keeps cap (a new reference, or NULL: none) as the model's C function
// and cf as what it holds (after a successful prepare).
static void set_c_function(CallbackObj *self, PyObject *cap,
                           const CFunction *cf)
{
    PyObject *old = self->capsule;
    self->cfn = cf;
    self->capsule = cap;
    Py_XDECREF(old);
}

// Calls a Python model of an EKF of the family ("EKF3" or "EKF") on x (n
// entries, handed over as a fresh array): a motion g(x, u) (u NULL: None)
// when motion, else a measurement h(x). Reads what it returns, (value,
// Jacobian), into out (rows,) and J (rows, n). GF_ERR_MODEL, with the
// exception set, when it raises or returns anything else.
static gf_status call_model(PyObject *fn, int motion, PyObject *u,
                            const gf_real *x, unsigned n, unsigned rows,
                            gf_real *out, gf_real *J, const char *family)
{
    PyObject *x_a = new_array(n, 0, x), *r, *seq;
    if (!x_a) {
        return GF_ERR_MODEL;
    }
    r = motion ? PyObject_CallFunctionObjArgs(fn, x_a, u ? u : Py_None, NULL)
               : PyObject_CallFunctionObjArgs(fn, x_a, NULL);
    Py_DECREF(x_a);
    if (!r) {
        return GF_ERR_MODEL;
    }
    seq = PySequence_Check(r) && PySequence_Size(r) == 2 ? r : NULL;
    if (!seq) {
        Py_DECREF(r);
        PyErr_Clear();
        if (motion) {
            bad_arg("%s motion g must return (mu_bar, G)", family);
        } else {
            bad_arg("%s measurement h must return (z_hat, H)", family);
        }
        return GF_ERR_MODEL;
    }
    PyObject *r0 = PySequence_GetItem(seq, 0);
    PyObject *r1 = r0 ? PySequence_GetItem(seq, 1) : NULL;
    Py_DECREF(seq);
    int bad =
        !r1 ||
        read_real(r0, motion ? "g's mu_bar" : "h's z_hat", 0, rows, out) < 0 ||
        read_real(r1, motion ? "g's G" : "h's H", rows, n, J) < 0;
    Py_XDECREF(r0);
    Py_XDECREF(r1);
    return bad ? GF_ERR_MODEL : GF_OK;
}

// The head of every belief object (KF2, EKF3, KF, EKF): the last accepted
// update's innovation, and whether a step is running: BUSY_STEP, with the
// GIL held (its callback may not step this filter), or BUSY_NOGIL, a run()
// with no Python in it, the GIL released (no other thread may step or
// re-initialise the filter meanwhile). An entry checks that the filter is
// idle (check_idle) and marks it busy with nothing between that could run
// Python or release the GIL: its arguments are converted before.
enum { BUSY_STEP = 1, BUSY_NOGIL = 2 };

// What S, K and the log-likelihood of an accepted update are computed from
// when they are read (nothing of them is computed in the step): the belief
// before the update, as the library's struct, and the update's H (a KF's
// C; m rows of n) and Q (m x m). m = 0: no record. The header of a block
// (rec_new) that holds them after it, sized for the family's largest n:
// a KF2's is some 150 bytes, a KF's 3 KB.
typedef struct {
    unsigned m, n;
    gf_real *H; // cap x cap
    gf_real *Q; // cap x cap
    union {
        gf_kf2 *kf2;
        gf_ekf3 *ekf3;
        gf_kf *kf;
        void *p;
    } prior;
} UpdateRec;

typedef struct {
    PyObject_HEAD gf_kf_innovation last;
    int has_last;
    int busy;
    // the last accepted update's record, rec[cur], when has_last; an
    // update fills rec[!cur] (the prior first) and an accepted one flips
    // cur: nothing is copied twice. Both NULL until the first update
    // (recs_ready), one block, freed with the filter (Filter_dealloc).
    UpdateRec *rec[2];
    int cur;
} FilterObj;

// The size of a record block for a belief of belief_size bytes and at most
// cap states, every part on a multiple of 8 bytes (the prior's struct and
// the gf_reals aligned after it).
static size_t rec_size(size_t belief_size, unsigned cap)
{
    const size_t a = 8u;
    const size_t head = (sizeof(UpdateRec) + a - 1) / a * a;
    const size_t prior = (belief_size + a - 1) / a * a;
    const size_t hq = (2u * cap * cap * sizeof(gf_real) + a - 1) / a * a;
    return head + prior + hq;
}

// Points the header at b (a block of rec_size bytes) to its parts.
static UpdateRec *rec_bind(char *b, size_t belief_size, unsigned cap)
{
    UpdateRec *r = (UpdateRec *)b;
    const size_t head = rec_size(0, 0);
    r->m = r->n = 0;
    r->prior.p = b + head;
    r->H = (gf_real *)(void *)(b + rec_size(belief_size, 0));
    r->Q = r->H + (size_t)cap * cap;
    return r;
}

// Copies the record src of a belief of belief_size bytes into dst: its
// used entries only (the rest of dst is not read).
static void rec_copy(UpdateRec *dst, const UpdateRec *src, size_t belief_size)
{
    dst->m = src->m;
    dst->n = src->n;
    memcpy(dst->H, src->H, (size_t)src->m * src->n * sizeof(gf_real));
    memcpy(dst->Q, src->Q, (size_t)src->m * src->m * sizeof(gf_real));
    memcpy(dst->prior.p, src->prior.p, belief_size);
}

// Empties f's records (when n may change: the priors' unused entries back
// to zero, as the library keeps a belief's).
static void recs_clear(FilterObj *f, size_t belief_size)
{
    for (int i = 0; f->rec[0] && i < 2; i++) {
        f->rec[i]->m = f->rec[i]->n = 0;
        memset(f->rec[i]->prior.p, 0, belief_size);
    }
    f->cur = 0;
}

// The deallocation of a belief: its records, then as Obj_dealloc.
static void Filter_dealloc(PyObject *self)
{
    PyMem_Free(((FilterObj *)self)->rec[0]);
    Obj_dealloc(self);
}

// The rows x cols block at the top left of src (rows of src_cols) into dst,
// packed (rows of cols).
static void block_copy(gf_real *dst, const gf_real *src, unsigned src_cols,
                       unsigned rows, unsigned cols)
{
    for (unsigned i = 0; i < rows; i++) {
        memcpy(dst + (size_t)cols * i, src + (size_t)src_cols * i,
               cols * sizeof(gf_real));
    }
}

// RuntimeError's messages for a filter stepped or initialised from its own
// callback (check_idle's fmt).
static const char called_back[] = "%s called from this filter's own callback";
static const char reinit_back[] = "%s: re-initialised from its own callback";

// 0 when no step of f runs; else RuntimeError (fmt naming who, or the run
// in another thread) and -1.
static int check_idle(const FilterObj *f, const char *fmt, const char *who)
{
    if (!f->busy) {
        return 0;
    }
    if (f->busy == BUSY_NOGIL) {
        PyErr_Format(PyExc_RuntimeError,
                     "%s: a run() of this filter is in progress in another "
                     "thread",
                     who);
    } else {
        PyErr_Format(PyExc_RuntimeError, fmt, who);
    }
    return -1;
}

// 0 unless a run() of f is on without the GIL (in another thread: its
// belief changes under the reader); else RuntimeError naming who and -1.
// A step's own callback may read its filter.
static int check_readable(const FilterObj *f, const char *who)
{
    return f->busy == BUSY_NOGIL ? check_idle(f, NULL, who) : 0;
}

// KF2's and EKF3's innovation (in) as the filters keep it (out).
static void innovation_of(const gf_innovation *in, gf_kf_innovation *out)
{
    out->m = in->m;
    memcpy(out->y, in->y, in->m * sizeof(gf_real));
    out->nis = in->nis;
}

// The getters of nis and innovation.
static PyObject *Filter_nis(PyObject *self_, void *unused)
{
    FilterObj *self = (FilterObj *)self_;
    (void)unused;
    if (check_readable(self, "nis") < 0) {
        return NULL;
    }
    return PyFloat_FromDouble(self->has_last ? (double)self->last.nis
                                             : (double)NAN);
}

static PyObject *Filter_innovation(PyObject *self_, void *unused)
{
    FilterObj *self = (FilterObj *)self_;
    (void)unused;
    if (check_readable(self, "innovation") < 0) {
        return NULL;
    }
    if (!self->has_last) {
        Py_RETURN_NONE;
    }
    return new_array(self->last.m, 0, self->last.y);
}

// ---- the last update's S, K and log-likelihood ---------------------------

// Which library belief a record's prior is (the getters' closure).
enum { REC_KF2 = 1, REC_EKF3 = 2, REC_KF = 3, REC_UKF3 = 4 };

// S, K and log det S of a record, in double.
typedef struct {
    unsigned m, n;
    double S[NMAX * NMAX]; // m x m
    double K[NMAX * NMAX]; // n x m
    double logdet;         // NaN when S is not positive definite as computed
} LastUpdate;

// Computes out from f's record, from the prior's covariance (the library's
// accessor, then in double):
//   S = H Sigma_bar H^T + Q,   K = Sigma_bar H^T S^-1 = (S^-1 H Sigma_bar)^T,
// S^-1 applied and det S taken by Gaussian elimination with partial
// pivoting. A UKF3 record holds S and (Sigma^xz)^T themselves (in Q and H:
// ukf3_update), and K = Sigma^xz S^-1 is taken the same way. 1 when done,
// 0 when there is no accepted update to read, -1 with RuntimeError during
// another thread's run (who named).
static int last_update(PyObject *self_, void *kind, const char *who,
                       LastUpdate *out)
{
    const FilterObj *f = (const FilterObj *)self_;
    const UpdateRec *r = f->rec[f->cur];
    gf_real sg[NMAX * NMAX];
    double P[NMAX * NMAX], HP[NMAX * NMAX], LU[NMAX * NMAX];
    if (check_readable(f, who) < 0) {
        return -1;
    }
    if (!f->has_last || !r || r->m < 1u || r->m > r->n || r->n > NMAX) {
        return 0;
    }
    const unsigned m = r->m, n = r->n;
    if ((int)(size_t)kind == REC_UKF3) {
        for (unsigned i = 0; i < m * n; i++) {
            HP[i] = (double)r->H[i];
        }
        for (unsigned i = 0; i < m * m; i++) {
            out->S[i] = (double)r->Q[i];
        }
    } else {
        switch ((int)(size_t)kind) {
        case REC_KF2:
            gf_kf2_cov(r->prior.kf2, (gf_mat2 *)sg);
            break;
        case REC_EKF3:
            gf_ekf3_cov(r->prior.ekf3, (gf_mat3 *)sg);
            break;
        default:
            gf_kf_cov(r->prior.kf, sg);
        }
        for (unsigned i = 0; i < n * n; i++) {
            P[i] = (double)sg[i];
        }
        // HP = H Sigma_bar (m x n), S = HP H^T + Q
        for (unsigned i = 0; i < m; i++) {
            for (unsigned j = 0; j < n; j++) {
                double a = 0.0;
                for (unsigned k = 0; k < n; k++) {
                    a += (double)r->H[n * i + k] * P[n * k + j];
                }
                HP[n * i + j] = a;
            }
        }
        for (unsigned i = 0; i < m; i++) {
            for (unsigned j = 0; j < m; j++) {
                double a = 0.0;
                for (unsigned k = 0; k < n; k++) {
                    a += HP[n * i + k] * (double)r->H[n * j + k];
                }
                out->S[m * i + j] = a + (double)r->Q[m * i + j];
            }
        }
    }
    // LU = S with partial pivoting (rows swapped in piv); HP overwritten
    // by S^-1 HP, row swaps applied to it alongside
    memcpy(LU, out->S, (size_t)m * m * sizeof(double));
    double logdet = 0.0;
    int sign = 1;
    for (unsigned c = 0; c < m; c++) {
        unsigned p = c;
        for (unsigned i = c + 1; i < m; i++) {
            if (fabs(LU[m * i + c]) > fabs(LU[m * p + c])) {
                p = i;
            }
        }
        if (p != c) {
            sign = -sign;
            for (unsigned j = 0; j < m; j++) {
                double t = LU[m * c + j];
                LU[m * c + j] = LU[m * p + j];
                LU[m * p + j] = t;
            }
            for (unsigned j = 0; j < n; j++) {
                double t = HP[n * c + j];
                HP[n * c + j] = HP[n * p + j];
                HP[n * p + j] = t;
            }
        }
        const double d = LU[m * c + c];
        if (d < 0.0) {
            sign = -sign;
        }
        logdet += log(fabs(d));
        for (unsigned i = c + 1; i < m; i++) {
            const double l = d != 0.0 ? LU[m * i + c] / d : 0.0;
            for (unsigned j = c; j < m; j++) {
                LU[m * i + j] -= l * LU[m * c + j];
            }
            for (unsigned j = 0; j < n; j++) {
                HP[n * i + j] -= l * HP[n * c + j];
            }
        }
    }
    for (unsigned c = m; c-- > 0;) {
        const double d = LU[m * c + c];
        for (unsigned j = 0; j < n; j++) {
            double a = HP[n * c + j];
            for (unsigned k = c + 1; k < m; k++) {
                a -= LU[m * c + k] * HP[n * k + j];
            }
            HP[n * c + j] = a / d;
        }
    }
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = 0; j < m; j++) {
            out->K[m * i + j] = HP[n * j + i];
        }
    }
    out->m = m;
    out->n = n;
    out->logdet = sign > 0 && isfinite(logdet) ? logdet : (double)NAN;
    return 1;
}

// A new gf_real array of shape (d0, d1) from the doubles src, each rounded
// once.
static PyObject *new_array_of(npy_intp d0, npy_intp d1, const double *src)
{
    PyObject *a = new_array(d0, d1, NULL);
    if (a) {
        gf_real *d = (gf_real *)PyArray_DATA((PyArrayObject *)a);
        for (npy_intp i = 0; i < d0 * d1; i++) {
            d[i] = (gf_real)src[i];
        }
    }
    return a;
}

// The getters of S, K and loglik (closure: the belief's REC_ kind); S
// and K are None before the first accepted update.
static PyObject *last_matrix(PyObject *self, void *kind, const char *name)
{
    LastUpdate u;
    const int gain = name[0] == 'K';
    int got = last_update(self, kind, name, &u);
    if (got <= 0) {
        if (got < 0) {
            return NULL;
        }
        Py_RETURN_NONE;
    }
    return gain ? new_array_of(u.n, u.m, u.K) : new_array_of(u.m, u.m, u.S);
}

static PyObject *Filter_S(PyObject *self, void *kind)
{
    return last_matrix(self, kind, "S");
}

static PyObject *Filter_K(PyObject *self, void *kind)
{
    return last_matrix(self, kind, "K");
}

// loglik = log N(y; 0, S) = -(NIS + log det S + m log 2 pi) / 2, the NIS
// the library's.
static PyObject *Filter_loglik(PyObject *self, void *kind)
{
    LastUpdate u;
    int got = last_update(self, kind, "loglik", &u);
    if (got <= 0) {
        return got < 0 ? NULL : PyFloat_FromDouble((double)NAN);
    }
    const double nis = (double)((FilterObj *)self)->last.nis;
    return PyFloat_FromDouble(
        -0.5 * (nis + u.logdet + u.m * log(2.0 * 3.14159265358979323846)));
}

// One family of filters (KF2, EKF3, KF or EKF) as the shared entries
// predict_entry, update_entry and run_entry step it.
typedef struct {
    const char *name;                       // "KF2": messages' prefix
    const char *predict_name, *u_name;      // "KF2.predict", "KF2.predict: u"
    const char *update_name, *z_name;       // "KF2.update", "KF2.update: z"
    const char *run_name;                   // "KF2.run"
    PyTypeObject **model_type, **meas_type; // predict's and update's
    int ekf;             // the model is a motion g, u handed to it as given
    int u_min_nd;        // run's u: 2 dimensions, or 1 as well (one column)
    const char *u_shape; // run's u in messages: "(N, 2)"
    size_t belief_offset, belief_size; // the library's belief in the object
    unsigned (*states)(PyObject *f);
    // model: its states n, u's entries nu (0: any or none; NULL model: the
    // family's u without one), and whether g is a Python function
    void (*model_size)(PyObject *model, unsigned *n, npy_intp *nu,
                       int *python_g);
    void (*meas_size)(PyObject *meas, unsigned *n, npy_intp *m);
    // a prediction with u (NULL: none); u_obj is u as an array for a
    // Python g (NULL: None)
    gf_status (*predict)(PyObject *f, PyObject *model, const gf_real *u,
                         PyObject *u_obj);
    // an update with z (meas's m entries); info: its innovation when
    // accepted or gated; rec: the belief before it, and its m, n, H and Q
    // when accepted
    gf_status (*update)(PyObject *f, PyObject *meas, const gf_real *z,
                        gf_kf_innovation *info, UpdateRec *rec);
    // mu (n,) and Sigma (n, n) into mu and sigma
    void (*record)(PyObject *f, gf_real *mu, gf_real *sigma);
    // whether meas's update calls Python (NULL: never)
    int (*meas_python)(PyObject *meas);
} Family;

// The most states a belief of fam has: a record's capacity.
static unsigned rec_cap(const Family *fam)
{
    return fam->belief_size == sizeof(gf_kf) ? (unsigned)NMAX : 3u;
}

// A record block of fam's size, bound (free with PyMem_Free); NULL with
// MemoryError.
static UpdateRec *rec_new(const Family *fam)
{
    const size_t size = rec_size(fam->belief_size, rec_cap(fam));
    char *b = PyMem_Calloc(1, size);
    if (!b) {
        PyErr_NoMemory();
        return NULL;
    }
    return rec_bind(b, fam->belief_size, rec_cap(fam));
}

// f's two records, made at its first update (one block). 0, or -1 with
// MemoryError.
static int recs_ready(FilterObj *f, const Family *fam)
{
    if (f->rec[0]) {
        return 0;
    }
    const size_t size = rec_size(fam->belief_size, rec_cap(fam));
    char *b = PyMem_Calloc(2, size);
    if (!b) {
        PyErr_NoMemory();
        return -1;
    }
    f->rec[0] = rec_bind(b, fam->belief_size, rec_cap(fam));
    f->rec[1] = rec_bind(b + size, fam->belief_size, rec_cap(fam));
    f->cur = 0;
    return 0;
}

// predict(model, u=None) of any family, see the methods' docstrings. An
// EKF's u goes to g as a fresh array (a built-in motion's entries
// checked); a KF's is read as the model's nu entries.
static PyObject *predict_entry(const Family *fam, PyObject *self_,
                               PyObject *const *args, Py_ssize_t nargs,
                               PyObject *kwnames)
{
    static const char *const kf_names[] = {"model", "u"};
    static const char *const ekf_names[] = {"motion", "u"};
    const char *what = fam->ekf ? "motion" : "model";
    FilterObj *self = (FilterObj *)self_;
    PyObject *a[2], *U = NULL;
    gf_real u[NMAX];
    const gf_real *up = NULL;
    unsigned n;
    npy_intp nu;
    int python_g;
    if (get_args("predict", args, nargs, kwnames,
                 fam->ekf ? ekf_names : kf_names, 1, 2, a) < 0 ||
        check_type(a[0], *fam->model_type, fam->predict_name, what, 0) < 0) {
        return NULL;
    }
    fam->model_size(a[0], &n, &nu, &python_g);
    if (check_n(fam->predict_name, what, n, fam->states(self_)) < 0) {
        return NULL;
    }
    if (fam->ekf) {
        if (given(a[1])) {
            if (numbers_only(a[1], fam->u_name) < 0) {
                return NULL;
            }
            U = PyArray_FROMANY(a[1], NPY_GF, 0, 1,
                                NPY_ARRAY_CARRAY | NPY_ARRAY_FORCECAST |
                                    NPY_ARRAY_ENSURECOPY);
            if (!U) {
                PyErr_Clear();
                return bad_arg("%s: u must be a vector of numbers",
                               fam->predict_name);
            }
            up = (const gf_real *)PyArray_DATA((PyArrayObject *)U);
        }
        if (nu && (!U || PyArray_SIZE((PyArrayObject *)U) != nu)) {
            Py_XDECREF(U);
            return bad_arg("%s: u must have %ld entries for %s",
                           fam->predict_name, (long)nu,
                           c_function_name((CallbackObj *)a[0]));
        }
    } else if (given(a[1])) {
        if (!nu) {
            return bad_arg("%s: u given, the model has no B",
                           fam->predict_name);
        }
        if (read_real(a[1], fam->u_name, 0, nu, u) < 0) {
            return NULL;
        }
        up = u;
    }
    if (check_idle(self, called_back, fam->predict_name) < 0) {
        Py_XDECREF(U);
        return NULL;
    }
    self->busy = BUSY_STEP;
    gf_status st = fam->predict(self_, a[0], up, U);
    self->busy = 0;
    Py_XDECREF(U);
    if (st != GF_OK) {
        if (PyErr_Occurred()) {
            return NULL;
        }
        return raise_status(st, fam->predict_name, NULL, NULL, 0, 0);
    }
    Py_RETURN_NONE;
}

// update(meas, z) of any family, see the methods' docstrings.
static PyObject *update_entry(const Family *fam, PyObject *self_,
                              PyObject *const *args, Py_ssize_t nargs,
                              PyObject *kwnames)
{
    static const char *const names[] = {"meas", "z"};
    FilterObj *self = (FilterObj *)self_;
    PyObject *a[2];
    gf_real z[NMAX];
    gf_kf_innovation info;
    unsigned n;
    npy_intp m;
    if (get_args("update", args, nargs, kwnames, names, 2, 2, a) < 0 ||
        check_type(a[0], *fam->meas_type, fam->update_name, "meas", 0) < 0) {
        return NULL;
    }
    fam->meas_size(a[0], &n, &m);
    if (check_n(fam->update_name, "measurement", n, fam->states(self_)) < 0 ||
        read_real(a[1], fam->z_name, 0, m, z) < 0 ||
        check_idle(self, called_back, fam->update_name) < 0 ||
        recs_ready(self, fam) < 0) {
        return NULL;
    }
    self->busy = BUSY_STEP;
    gf_status st = fam->update(self_, a[0], z, &info, self->rec[!self->cur]);
    self->busy = 0;
    if (st != GF_OK) {
        if (PyErr_Occurred()) {
            return NULL;
        }
        return raise_status(st, fam->update_name, NULL,
                            st == GF_ERR_GATED && info.m ? info.y : NULL,
                            info.m, info.nis);
    }
    self->last = info;
    self->has_last = 1;
    self->cur = !self->cur;
    Py_RETURN_NONE;
}

// The arrays of a batch: u (N, k), or (N,) as (N, 1) when min_nd is 1; k =
// nu when nu > 0; N from u, z or steps. u_required: u must be given (a
// built-in motion); u_refused (a message): u may not be. z (N, m) or, when
// m is 1, (N,); m = 0: no measurement, z refused. 0, or -1 with
// GF_ERR_ARG's exception and nothing held.
static int run_arrays(const Family *fam, PyObject *u_o, PyObject *z_o,
                      PyObject *steps_o, npy_intp nu, int u_required,
                      const char *u_refused, npy_intp m, PyObject **U,
                      PyObject **Z, npy_intp *N, npy_intp *k)
{
    const char *who = fam->run_name;
    *U = *Z = NULL;
    *N = -1;
    *k = 0;
    if (given(steps_o)) {
        char sn[80];
        unsigned long steps;
        PyOS_snprintf(sn, sizeof sn, "%s: steps", who);
        if (read_count(steps_o, sn, (unsigned long)NPY_MAX_INTP, &steps) < 0) {
            return -1;
        }
        *N = (npy_intp)steps;
    }
    if (given(u_o)) {
        if (u_refused) {
            bad_arg("%s: %s", who, u_refused);
            return -1;
        }
        char un[80];
        PyOS_snprintf(un, sizeof un, "%s: u", who);
        if (numbers_only(u_o, un) < 0) {
            return -1;
        }
        *U = PyArray_FROMANY(u_o, NPY_GF, fam->u_min_nd, 2,
                             NPY_ARRAY_CARRAY_RO | NPY_ARRAY_FORCECAST);
        if (!*U) {
            PyErr_Clear();
            bad_arg("%s: u must be an %s array", who, fam->u_shape);
            return -1;
        }
        PyArrayObject *a = (PyArrayObject *)*U;
        *k = PyArray_NDIM(a) == 2 ? PyArray_DIM(a, 1) : 1;
        if ((nu && *k != nu) || (*N >= 0 && PyArray_DIM(a, 0) != *N)) {
            Py_CLEAR(*U);
            if (nu) {
                bad_arg("%s: u must have shape (steps, %ld)", who, (long)nu);
            } else {
                bad_arg("%s: u must have steps rows", who);
            }
            return -1;
        }
        *N = PyArray_DIM(a, 0);
    } else if (u_required) {
        bad_arg("%s: u must have shape (steps, %ld) for a built-in motion", who,
                (long)nu);
        return -1;
    }
    if (given(z_o)) {
        if (!m) {
            Py_CLEAR(*U);
            bad_arg("%s: z without meas", who);
            return -1;
        }
        char zn[80];
        PyOS_snprintf(zn, sizeof zn, "%s: z", who);
        if (numbers_only(z_o, zn) < 0) {
            Py_CLEAR(*U);
            return -1;
        }
        *Z = PyArray_FROMANY(z_o, NPY_GF, 1, 2,
                             NPY_ARRAY_CARRAY_RO | NPY_ARRAY_FORCECAST);
        if (!*Z) {
            PyErr_Clear();
            Py_CLEAR(*U);
            bad_arg("%s: z must be an (N, m) array", who);
            return -1;
        }
        PyArrayObject *a = (PyArrayObject *)*Z;
        npy_intp zc = PyArray_NDIM(a) == 2 ? PyArray_DIM(a, 1) : 1;
        if (zc != m || (*N >= 0 && PyArray_DIM(a, 0) != *N)) {
            Py_CLEAR(*U);
            Py_CLEAR(*Z);
            bad_arg("%s: z must have shape (steps, %ld)", who, (long)m);
            return -1;
        }
        *N = PyArray_DIM(a, 0);
    }
    if (*N < 0) {
        bad_arg("%s: give u, z or steps", who);
        return -1;
    }
    return 0;
}

// The outputs of a batch of N steps of n states: mu (N, n), sigma (N, n,
// n), nis (N,), status (N,). 0, or -1 with an exception and none held.
static int run_outputs(npy_intp N, npy_intp n, PyObject *out[4])
{
    npy_intp d3[3] = {N, n, n};
    out[0] = PyArray_SimpleNew(2, d3, NPY_GF);
    out[1] = PyArray_SimpleNew(3, d3, NPY_GF);
    out[2] = PyArray_SimpleNew(1, d3, NPY_GF);
    out[3] = PyArray_SimpleNew(1, d3, NPY_INT8);
    if (out[0] && out[1] && out[2] && out[3]) {
        return 0;
    }
    for (int i = 0; i < 4; i++) {
        Py_CLEAR(out[i]);
    }
    return -1;
}

// The row z[k] (m entries) holds a measurement: no NaN in it.
static int z_present(const gf_real *zk, npy_intp m)
{
    int present = 1;
    for (npy_intp i = 0; i < m; i++) {
        present &= !isnan(zk[i]);
    }
    return present;
}

// u[k] for a Python g: a fresh (k,) array (g may keep or change it);
// NULL with an exception.
static PyObject *u_row(PyObject *U, npy_intp k, npy_intp cols)
{
    return new_array(
        cols, 0, (const gf_real *)PyArray_DATA((PyArrayObject *)U) + cols * k);
}

// The steps of a batch: N of them on self, each the model's prediction
// with u's row (when model is not NULL; a Python g gets the row as a fresh
// array) and meas's update with z's row (when z is given and the row has
// no NaN). A gated update is recorded and the run goes on; any other
// failure puts the belief back as it was, raises with exc.step and gives
// NULL. U (k columns) and Z (m) are NULL or arrays of N rows. With no
// Python model in the run the steps go without the GIL (BUSY_NOGIL keeps
// every other entry off the filter meanwhile).
static PyObject *run_steps(const Family *fam, PyObject *self_, PyObject *model,
                           PyObject *meas, int python_g, PyObject *U,
                           PyObject *Z, npy_intp N, npy_intp k, npy_intp m)
{
    FilterObj *self = (FilterObj *)self_;
    const npy_intp n = fam->states(self_);
    PyObject *o[4] = {NULL, NULL, NULL, NULL}, *out = NULL;
    char *belief = (char *)self_ + fam->belief_offset;
    const int nogil =
        !python_g && !(meas && fam->meas_python && fam->meas_python(meas));
    PyThreadState *ts = NULL;
    gf_status st = GF_OK;
    npy_intp t;
    void *saved = PyMem_Malloc(fam->belief_size);
    if (!saved) {
        PyErr_NoMemory();
        return NULL;
    }
    if (run_outputs(N, n, o) < 0) {
        PyMem_Free(saved);
        return NULL;
    }
    const gf_real *u =
        U ? (const gf_real *)PyArray_DATA((PyArrayObject *)U) : NULL;
    const gf_real *z =
        Z ? (const gf_real *)PyArray_DATA((PyArrayObject *)Z) : NULL;
    gf_real *mu_o = (gf_real *)PyArray_DATA((PyArrayObject *)o[0]);
    gf_real *sg_o = (gf_real *)PyArray_DATA((PyArrayObject *)o[1]);
    gf_real *nis_o = (gf_real *)PyArray_DATA((PyArrayObject *)o[2]);
    signed char *st_o = (signed char *)PyArray_DATA((PyArrayObject *)o[3]);
    // the records, and a copy of the current one to put back on a failure
    UpdateRec *saved_rec = NULL;
    if (check_idle(self, called_back, fam->run_name) < 0 ||
        (z && (recs_ready(self, fam) < 0 || !(saved_rec = rec_new(fam))))) {
        PyMem_Free(saved);
        for (int i = 0; i < 4; i++) {
            Py_DECREF(o[i]);
        }
        return NULL;
    }
    const gf_kf_innovation saved_last = self->last;
    const int saved_has = self->has_last;
    const int saved_cur = self->cur;
    if (saved_rec) {
        rec_copy(saved_rec, self->rec[saved_cur], fam->belief_size);
    }
    memcpy(saved, belief, fam->belief_size);
    self->busy = nogil ? BUSY_NOGIL : BUSY_STEP;
    if (nogil) {
        ts = PyEval_SaveThread();
    }
    for (t = 0; t < N; t++) {
        gf_kf_innovation info;
        st = GF_OK;
        nis_o[t] = (gf_real)NAN;
        if (model) {
            PyObject *ut = NULL;
            if (U && python_g && !(ut = u_row(U, t, k))) {
                st = GF_ERR_MODEL;
            } else {
                st = fam->predict(self_, model, u ? u + k * t : NULL, ut);
                Py_XDECREF(ut);
            }
        }
        if (st == GF_OK && z && z_present(z + m * t, m)) {
            st = fam->update(self_, meas, z + m * t, &info,
                             self->rec[!self->cur]);
            if (st == GF_OK || st == GF_ERR_GATED) {
                nis_o[t] = info.nis;
            }
            if (st == GF_OK) {
                self->last = info;
                self->has_last = 1;
                self->cur = !self->cur;
            }
        }
        if (st != GF_OK && st != GF_ERR_GATED) {
            break;
        }
        st_o[t] = (signed char)st;
        fam->record(self_, mu_o + n * t, sg_o + n * n * t);
    }
    if (ts) {
        PyEval_RestoreThread(ts);
    }
    self->busy = 0;
    if (t < N) {
        memcpy(belief, saved, fam->belief_size);
        self->last = saved_last;
        self->has_last = saved_has;
        self->cur = saved_cur;
        if (saved_rec) {
            rec_copy(self->rec[saved_cur], saved_rec, fam->belief_size);
        }
        if (!PyErr_Occurred()) {
            raise_status(st, fam->run_name, NULL, NULL, 0, 0);
        }
        set_step(t);
    } else {
        out = PyTuple_Pack(4, o[0], o[1], o[2], o[3]);
    }
    PyMem_Free(saved);
    PyMem_Free(saved_rec);
    for (int i = 0; i < 4; i++) {
        Py_XDECREF(o[i]);
    }
    return out;
}

// run(model=None, meas=None, u=None, z=None, steps=None) of any family (an
// EKF's first argument is motion), see the methods' docstrings.
static PyObject *run_entry(const Family *fam, PyObject *self_,
                           PyObject *const *args, Py_ssize_t nargs,
                           PyObject *kwnames)
{
    static const char *const kf_names[] = {"model", "meas", "u", "z", "steps"};
    static const char *const ekf_names[] = {"motion", "meas", "u", "z",
                                            "steps"};
    const char *what = fam->ekf ? "motion" : "model";
    PyObject *a[5], *U, *Z, *out;
    PyObject *model = NULL, *meas = NULL;
    const unsigned n = fam->states(self_);
    unsigned got;
    npy_intp N, k, nu = 0, m = 0;
    int python_g = 0;
    if (get_args("run", args, nargs, kwnames, fam->ekf ? ekf_names : kf_names,
                 0, 5, a) < 0) {
        return NULL;
    }
    if (given(a[0])) {
        if (check_type(a[0], *fam->model_type, fam->run_name, what, 1) < 0) {
            return NULL;
        }
        model = a[0];
        fam->model_size(model, &got, &nu, &python_g);
        if (check_n(fam->run_name, what, got, n) < 0) {
            return NULL;
        }
    } else {
        fam->model_size(NULL, &got, &nu, &python_g);
    }
    if (given(a[1])) {
        if (check_type(a[1], *fam->meas_type, fam->run_name, "meas", 1) < 0) {
            return NULL;
        }
        meas = a[1];
        fam->meas_size(meas, &got, &m);
        if (check_n(fam->run_name, "measurement", got, n) < 0) {
            return NULL;
        }
    }
    if (!model && given(a[2])) {
        return bad_arg("%s: u without %s", fam->run_name, what);
    }
    if (run_arrays(fam, a[2], a[3], a[4], nu, fam->ekf && nu,
                   !fam->ekf && !nu ? "u given, the model has no B" : NULL, m,
                   &U, &Z, &N, &k) < 0) {
        return NULL;
    }
    out = run_steps(fam, self_, model, meas, python_g, U, Z, N, k, m);
    Py_XDECREF(U);
    Py_XDECREF(Z);
    return out;
}

// ---- state, for pickle and copy ----------------------------------------

// 1 when self's class (a Python subclass) gives its objects a __dict__
// (its __dictoffset__ is not 0); else 0.
static int has_dict(PyObject *self)
{
    PyObject *off =
        PyObject_GetAttrString((PyObject *)Py_TYPE(self), "__dictoffset__");
    const long v = off ? PyLong_AsLong(off) : 0;
    Py_XDECREF(off);
    PyErr_Clear();
    return v != 0;
}

// The instance dictionary of self when its class is a Python subclass
// with one and it holds anything (a new reference); NULL otherwise, with
// an exception only when reading it failed.
static PyObject *instance_dict(PyObject *self)
{
    if (!has_dict(self)) {
        return NULL;
    }
    PyObject *d = PyObject_GetAttrString(self, "__dict__");
    if (d && PyDict_Check(d) && PyDict_Size(d) > 0) {
        return d;
    }
    Py_XDECREF(d);
    return NULL;
}

// Puts the entries of d (a dict, or None: nothing) into self's instance
// dictionary. 0, or -1 with an exception.
static int update_instance_dict(PyObject *self, PyObject *d)
{
    if (d == Py_None) {
        return 0;
    }
    PyObject *mine = PyObject_GetAttrString(self, "__dict__");
    int rc = mine ? PyDict_Update(mine, d) : -1;
    Py_XDECREF(mine);
    return rc;
}

// The factors' order perm[0..n-1] is a permutation of 0..n-1 (what the
// accessor indexes by), and n within the library's range.
static int state_sound(const unsigned char *perm, unsigned n)
{
    unsigned seen = 0;
    if (n < 1u || n > NMAX) {
        return 0;
    }
    for (unsigned i = 0; i < n; i++) {
        if (perm[i] >= n || (seen >> perm[i]) & 1u) {
            return 0;
        }
        seen |= 1u << perm[i];
    }
    return 1;
}

// The states n of a belief of the family fam as bytes (fam->belief_size)
// when it is one the library could have made (state_sound: n, the
// factors' order); else 0.
static unsigned belief_sound(const Family *fam, const char *belief)
{
    if (fam->belief_size == sizeof(gf_ukf3)) {
        // no factors: finite moments, a symmetric Sigma with its variances
        // >= 0, weights init could have made
        gf_ukf3 u;
        memcpy(&u, belief, sizeof u);
        for (size_t i = 0; i < sizeof u / sizeof(gf_real); i++) {
            if (!isfinite((double)((const gf_real *)&u)[i])) {
                return 0u;
            }
        }
        for (unsigned i = 0; i < 3u; i++) {
            for (unsigned j = 0; j < 3u; j++) {
                if (u.sigma.m[i][j] != u.sigma.m[j][i] ||
                    (i == j && u.sigma.m[i][i] < 0)) {
                    return 0u;
                }
            }
        }
        return u.gamma > 0 && u.wi > 0 ? 3u : 0u;
    }
    unsigned n = fam->belief_size == sizeof(gf_kf2)    ? 2u
                 : fam->belief_size == sizeof(gf_ekf3) ? 3u
                                                       : 0u;
    const unsigned char *perm;
    if (n == 0u) {
        gf_kf k;
        memcpy(&k, belief, sizeof k);
        n = k.n;
        perm = (const unsigned char *)belief + offsetof(gf_kf, perm);
    } else {
        perm = (const unsigned char *)belief +
               (n == 2u ? offsetof(gf_kf2, perm) : offsetof(gf_ekf3, perm));
    }
    return state_sound(perm, n) ? n : 0u;
}

// The record of the last accepted update as a state keeps it, after the
// innovation: the prior belief (belief_size bytes), H (m x n), Q (m x m).
static size_t rec_bytes(size_t belief_size, unsigned m, unsigned n)
{
    return belief_size + ((size_t)m * n + (size_t)m * m) * sizeof(gf_real);
}

// __getstate__ of a belief: (1, precision, the library's belief as bytes,
// the last accepted update as bytes (its innovation, then what S and K
// are computed from: rec_bytes), whether there is one), and the instance
// dictionary as a sixth item when a subclass's object has anything in it.
// A copy restores every bit: the factors, not Sigma recomputed. A filter
// never initialised has no state (BadArgument).
static PyObject *state_get(const Family *fam, PyObject *self_)
{
    FilterObj *f = (FilterObj *)self_;
    const char *belief = (const char *)self_ + fam->belief_offset;
    if (check_readable(f, fam->name) < 0) {
        return NULL;
    }
    if (!belief_sound(fam, belief)) {
        return bad_arg("%s.__getstate__: the filter was never initialised",
                       fam->name);
    }
    // the innovation's entries beyond m, and its padding, as zeros: equal
    // filters give equal states
    char buf[sizeof(gf_kf_innovation) + sizeof(gf_kf) +
             2 * NMAX * NMAX * sizeof(gf_real)];
    gf_kf_innovation last;
    size_t len = sizeof last;
    memset(&last, 0, sizeof last);
    if (f->has_last && f->last.m <= NMAX) {
        last.m = f->last.m;
        memcpy(last.y, f->last.y, f->last.m * sizeof(gf_real));
        last.nis = f->last.nis;
    }
    memcpy(buf, &last, sizeof last);
    const UpdateRec *r = f->rec[f->cur];
    if (f->has_last && r && r->m == f->last.m && r->n == fam->states(self_)) {
        const size_t mn = (size_t)r->m * r->n * sizeof(gf_real);
        memcpy(buf + len, r->prior.p, fam->belief_size);
        memcpy(buf + len + fam->belief_size, r->H, mn);
        memcpy(buf + len + fam->belief_size + mn, r->Q,
               (size_t)r->m * r->m * sizeof(gf_real));
        len += rec_bytes(fam->belief_size, r->m, r->n);
    }
    PyObject *d = instance_dict(self_);
    if (!d && PyErr_Occurred()) {
        return NULL;
    }
    PyObject *st = d ? Py_BuildValue("(isy#y#iN)", 1, GF_PREC_NAME, belief,
                                     (Py_ssize_t)fam->belief_size, buf,
                                     (Py_ssize_t)len, f->has_last, d)
                     : Py_BuildValue("(isy#y#i)", 1, GF_PREC_NAME, belief,
                                     (Py_ssize_t)fam->belief_size, buf,
                                     (Py_ssize_t)len, f->has_last);
    return st;
}

// __setstate__: the belief and innovation of state_get's tuple, checked
// (version, precision, sizes, the factors' order, n, a dictionary only
// for an object that has one) before anything is written; BadArgument
// otherwise, the filter unchanged.
static PyObject *state_set(const Family *fam, PyObject *self_, PyObject *st)
{
    FilterObj *f = (FilterObj *)self_;
    int version, has_last;
    const char *prec, *belief, *last;
    PyObject *d = Py_None;
    Py_ssize_t nb, nl;
    char what[64];
    snprintf(what, sizeof what, "%s.__setstate__", fam->name);
    if (!PyTuple_Check(st) ||
        !PyArg_ParseTuple(st, "isy#y#i|O", &version, &prec, &belief, &nb, &last,
                          &nl, &has_last, &d)) {
        PyErr_Clear();
        return bad_arg("%s: not a state of this package", what);
    }
    if (version != 1 || strcmp(prec, GF_PREC_NAME) != 0 ||
        (size_t)nb != fam->belief_size || (size_t)nl < sizeof f->last) {
        return bad_arg("%s: a state of version %d in %s, %zd bytes; this "
                       "filter's is version 1 in %s, %zu bytes",
                       what, version, prec, nb, GF_PREC_NAME, fam->belief_size);
    }
    if (d != Py_None && (!PyDict_Check(d) || !has_dict(self_))) {
        return bad_arg("%s: the state's attributes are not a dict for an "
                       "object with a __dict__",
                       what);
    }
    gf_kf_innovation in;
    memcpy(&in, last, sizeof in);
    const unsigned n = belief_sound(fam, belief);
    if (n == 0u || (has_last && (in.m < 1u || in.m > n))) {
        return bad_arg("%s: the state's belief is not one the library made",
                       what);
    }
    // the update's record, when the state has one: its prior a belief of
    // the same n
    const char *rec = NULL;
    if ((size_t)nl > sizeof in) {
        rec = last + sizeof in;
        if (!has_last ||
            (size_t)nl != sizeof in + rec_bytes(fam->belief_size, in.m, n) ||
            belief_sound(fam, rec) != n) {
            return bad_arg("%s: the state's last update is not one the "
                           "library made",
                           what);
        }
    }
    if (check_idle(f, reinit_back, what) < 0) {
        return NULL;
    }
    // the records and the attributes first: the parts that can fail
    // (memory)
    if ((rec && recs_ready(f, fam) < 0) || update_instance_dict(self_, d) < 0) {
        return NULL;
    }
    memcpy((char *)self_ + fam->belief_offset, belief, fam->belief_size);
    f->last = in;
    f->has_last = has_last != 0;
    recs_clear(f, fam->belief_size); // n may have changed
    if (rec) {
        UpdateRec *r = f->rec[0];
        const size_t mn = (size_t)in.m * n * sizeof(gf_real);
        r->m = in.m;
        r->n = n;
        memcpy(r->prior.p, rec, fam->belief_size);
        memcpy(r->H, rec + fam->belief_size, mn);
        memcpy(r->Q, rec + fam->belief_size + mn,
               (size_t)in.m * in.m * sizeof(gf_real));
    }
    Py_RETURN_NONE;
}

// ---- settable state ----------------------------------------------------

// The mean's setter: value read as n finite numbers (the states in `angles`
// wrapped, as init wraps them) into dst, the factors kept; BadArgument or
// NonFinite otherwise, the belief unchanged.
static int set_mean(FilterObj *f, gf_real *dst, unsigned n, unsigned angles,
                    PyObject *value, const char *who)
{
    gf_real m[NMAX];
    if (!value) {
        bad_arg("%s cannot be deleted", who);
        return -1;
    }
    if (n < 1u) {
        bad_arg("%s: the filter was never initialised", who);
        return -1;
    }
    if (read_real(value, who, 0, n, m) < 0 ||
        check_idle(f, reinit_back, who) < 0) {
        return -1;
    }
    for (unsigned i = 0; i < n; i++) {
        if (!isfinite((double)m[i])) {
            raise_status(GF_ERR_NONFINITE, who, NULL, NULL, 0, 0);
            return -1;
        }
        if (i < 32u && ((angles >> i) & 1u)) {
            m[i] = gf_angle_wrap(m[i]);
        }
    }
    memcpy(dst, m, n * sizeof(gf_real));
    return 0;
}

// 0 when value is a value for a sigma setter (not a deletion); else
// BadArgument and -1.
static int set_sigma_value(PyObject *value, const char *who)
{
    if (value) {
        return 0;
    }
    bad_arg("%s cannot be deleted", who);
    return -1;
}

// The package's class t is or derives from (a Python subclass's), or NULL.
static PyTypeObject *package_class(PyTypeObject *t);

// reset(mu, sigma[, angles]): the class's own constructor again on this
// object (a subclass's __init__ is not called), which judges and factors
// as it does; the belief unchanged when it refuses.
static PyObject *Filter_reset(PyObject *self, PyObject *args, PyObject *kw)
{
    PyTypeObject *t = package_class(Py_TYPE(self));
    initproc init = t ? (initproc)PyType_GetSlot(t, Py_tp_init) : NULL;
    if (!init || init(self, args, kw) < 0) {
        return NULL;
    }
    Py_RETURN_NONE;
}

// The family of a belief: that of the class it is or derives from.
static const Family *family_of(PyObject *self);

// The entries every belief shares, each its family's: predict(), update()
// and run() (on a failure other than a gate, run() puts the belief back as
// it was before the call), and __getstate__/__setstate__ for pickle and
// copy.
static PyObject *Filter_predict(PyObject *self, PyObject *const *args,
                                Py_ssize_t nargs, PyObject *kwnames)
{
    return predict_entry(family_of(self), self, args, nargs, kwnames);
}

static PyObject *Filter_update(PyObject *self, PyObject *const *args,
                               Py_ssize_t nargs, PyObject *kwnames)
{
    return update_entry(family_of(self), self, args, nargs, kwnames);
}

static PyObject *Filter_run(PyObject *self, PyObject *const *args,
                            Py_ssize_t nargs, PyObject *kwnames)
{
    return run_entry(family_of(self), self, args, nargs, kwnames);
}

static PyObject *Filter_getstate(PyObject *self, PyObject *unused)
{
    (void)unused;
    return state_get(family_of(self), self);
}

static PyObject *Filter_setstate(PyObject *self, PyObject *st)
{
    return state_set(family_of(self), self, st);
}

// The getter of sigma: Sigma = U D U^T (UKF3: Sigma as kept), (n, n).
static PyObject *Filter_sigma(PyObject *self, void *unused)
{
    const Family *fam = family_of(self);
    gf_real mu[NMAX];
    (void)unused;
    if (((FilterObj *)self)->busy == BUSY_NOGIL) { // refused: say whose
        char who[32];
        PyOS_snprintf(who, sizeof who, "%s.sigma", fam->name);
        if (check_readable((FilterObj *)self, who) < 0) {
            return NULL;
        }
    }
    PyObject *a = new_sigma(fam->states(self), NULL);
    if (a) {
        fam->record(self, mu, (gf_real *)PyArray_DATA((PyArrayObject *)a));
    }
    return a;
}

// ---- KF2 ------------------------------------------------------------------

typedef struct {
    PyObject_HEAD gf_kf2_pmodel pm;
    // B's columns given, u's entries: 0 (no B: B is zero, u refused), 1 (B
    // (2, 1) in the first column of the library's 2x2 B, the second zero,
    // and u's second entry 0) or 2
    int nu;
    PyObject *weakrefs; // weakref support
} KF2ModelObj;

typedef struct {
    PyObject_HEAD gf_kf2_pmeas pq;
    PyObject *weakrefs; // weakref support
} KF2MeasObj;

typedef struct {
    FilterObj f;
    gf_kf2 kf;
    PyObject *weakrefs; // weakref support
} KF2Obj;

static PyTypeObject *KF2Model_Type, *KF2Meas_Type, *KF2_Type;

static int KF2Model_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"A", "R", "B", "c", NULL};
    PyObject *A, *R, *B = Py_None, *c = Py_None;
    gf_kf2_model m;
    npy_intp br = 0, nu = 0;
    gf_real b[4];
    char got[GOT_LEN];
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|OO:KF2Model", names, &A, &R,
                                     &B, &c)) {
        return -1;
    }
    memset(&m, 0, sizeof m);
    if (read_real(A, "KF2Model: A", 2, 2, &m.A.m[0][0]) < 0 ||
        read_real(R, "KF2Model: R", 2, 2, &m.R.m[0][0]) < 0) {
        return -1;
    }
    if (B != Py_None) {
        if (shape_of(B, "KF2Model: B", 0, &br, &nu, got) < 0) {
            return -1;
        }
        if (br != 2 || nu < 1 || nu > 2) {
            bad_arg("KF2Model: B must have shape (2, 1) or (2, 2), got %s",
                    got);
            return -1;
        }
        if (read_real(B, "KF2Model: B", 2, nu, b) < 0) {
            return -1;
        }
        for (npy_intp i = 0; i < 2; i++) {
            for (npy_intp j = 0; j < nu; j++) {
                m.B.m[i][j] = b[nu * i + j];
            }
        }
    }
    if (c != Py_None && read_real(c, "KF2Model: c", 0, 2, m.c.v) < 0) {
        return -1;
    }
    if (check(gf_kf2_prepare_model(&((KF2ModelObj *)self_)->pm, &m),
              "KF2Model") < 0) {
        return -1;
    }
    ((KF2ModelObj *)self_)->nu = (int)nu;
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
    case 2: {
        const int nu = ((KF2ModelObj *)self_)->nu;
        gf_real b[4];
        if (!nu) {
            Py_RETURN_NONE;
        }
        block_copy(b, &m->B.m[0][0], 2, 2, (unsigned)nu);
        return new_array(2, nu, b);
    }
    case 4:
        return PyLong_FromLong(((KF2ModelObj *)self_)->nu);
    default:
        return new_array(2, 0, m->c.v);
    }
}

static PyGetSetDef KF2Model_getset[] = {
    {"A", KF2Model_get, NULL, "state transition (2, 2)", (void *)0},
    {"R", KF2Model_get, NULL, "process noise covariance (2, 2)", (void *)1},
    {"B", KF2Model_get, NULL, "control matrix (2, nu), or None", (void *)2},
    {"c", KF2Model_get, NULL, "constant motion term (2,)", (void *)3},
    {"nu", KF2Model_get, NULL, "controls: B's columns (0: no B)", (void *)4},
    {NULL, NULL, NULL, NULL, NULL},
};

// KF2Meas's C (m, 2) and Q (m, m), m = 1 or 2, are read into and given
// from the first m rows of the 2x2 C and Q as they are: with 2 columns
// (or m = 1), the rows of a 2x2 matrix are those of the packed one.
static int KF2Meas_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"C", "Q", "c", "gate", NULL};
    PyObject *C, *Q, *c = Py_None, *gate = NULL;
    gf_kf2_meas m;
    npy_intp rows, cols;
    char got[GOT_LEN];
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|OO:KF2Meas", names, &C, &Q,
                                     &c, &gate)) {
        return -1;
    }
    memset(&m, 0, sizeof m);
    if (shape_of(C, "KF2Meas: C", 1, &rows, &cols, got) < 0) {
        return -1;
    }
    if (rows < 1 || rows > 2 || cols != 2) {
        bad_arg("KF2Meas: C must have shape (1, 2) or (2, 2), got %s", got);
        return -1;
    }
    m.m = (unsigned)rows;
    if (read_real(C, "KF2Meas: C", rows, 2, &m.C.m[0][0]) < 0 ||
        read_real(Q, "KF2Meas: Q", rows, rows, &m.Q.m[0][0]) < 0 ||
        (c != Py_None && read_real(c, "KF2Meas: c", 0, rows, m.c.v) < 0) ||
        read_gate(gate, "KF2Meas", &m.gate) < 0) {
        return -1;
    }
    return check(gf_kf2_prepare_meas(&((KF2MeasObj *)self_)->pq, &m),
                 "KF2Meas");
}

static PyObject *KF2Meas_get(PyObject *self_, void *which)
{
    const gf_kf2_meas *m = &((KF2MeasObj *)self_)->pq.meas;
    switch ((int)(size_t)which) {
    case 0:
        return new_array(m->m, 2, &m->C.m[0][0]);
    case 1:
        return new_array(m->m, m->m, &m->Q.m[0][0]);
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
        read_real(sigma, "KF2: sigma", 2, 2, &s.m[0][0]) < 0 ||
        check_idle(&self->f, reinit_back, "KF2") < 0 ||
        check(gf_kf2_init(&self->kf, &m, &s), "KF2") < 0) {
        return -1;
    }
    self->f.has_last = 0;
    return 0;
}

// KF2's steps for the shared entries (Family).
static unsigned kf2_states(PyObject *f)
{
    (void)f;
    return 2;
}

// A model without B: no u (nu = 0).
static void kf2_model_size(PyObject *model, unsigned *n, npy_intp *nu,
                           int *python_g)
{
    *n = 2;
    *nu = model ? ((KF2ModelObj *)model)->nu : 0;
    *python_g = 0;
}

static void kf2_meas_size(PyObject *meas, unsigned *n, npy_intp *m)
{
    *n = 2;
    *m = ((KF2MeasObj *)meas)->pq.meas.m;
}

// u: the model's nu entries (NULL: none); one entry is (u, 0) to the
// library, for B's zero second column.
static gf_status kf2_predict(PyObject *f, PyObject *model, const gf_real *u,
                             PyObject *u_obj)
{
    const KF2ModelObj *mo = (const KF2ModelObj *)model;
    gf_vec2 uv;
    (void)u_obj;
    if (u) {
        uv.v[0] = u[0];
        uv.v[1] = mo->nu > 1 ? u[1] : GF_R(0.0);
    }
    return gf_kf2_predict_prepared(&((KF2Obj *)f)->kf, &mo->pm, u ? &uv : NULL);
}

static gf_status kf2_update(PyObject *f, PyObject *meas, const gf_real *z,
                            gf_kf_innovation *info, UpdateRec *rec)
{
    const gf_kf2_pmeas *pq = &((KF2MeasObj *)meas)->pq;
    const unsigned m = pq->meas.m;
    gf_vec2 zv = {{z[0], m > 1 ? z[1] : GF_R(0.0)}};
    gf_innovation in;
    *rec->prior.kf2 = ((KF2Obj *)f)->kf;
    gf_status st = gf_kf2_update_prepared(&((KF2Obj *)f)->kf, pq, &zv, &in);
    if (st == GF_OK || st == GF_ERR_GATED) {
        innovation_of(&in, info);
    }
    if (st == GF_OK) {
        rec->m = m;
        rec->n = 2;
        block_copy(rec->H, &pq->meas.C.m[0][0], 2, m, 2);
        block_copy(rec->Q, &pq->meas.Q.m[0][0], 2, m, m);
    }
    return st;
}

static void kf2_record(PyObject *f, gf_real *mu, gf_real *sigma)
{
    const gf_kf2 *kf = &((KF2Obj *)f)->kf;
    memcpy(mu, kf->mu.v, 2 * sizeof(gf_real));
    gf_kf2_cov(kf, (gf_mat2 *)sigma);
}

static const Family kf2_family = {
    "KF2",
    "KF2.predict",
    "KF2.predict: u",
    "KF2.update",
    "KF2.update: z",
    "KF2.run",
    &KF2Model_Type,
    &KF2Meas_Type,
    0,
    1,
    "(N, nu)",
    offsetof(KF2Obj, kf),
    sizeof(gf_kf2),
    kf2_states,
    kf2_model_size,
    kf2_meas_size,
    kf2_predict,
    kf2_update,
    kf2_record,
    NULL,
};

// The setter of KF2's sigma: the mean and value factored by gf_kf2_init
// into a copy of the belief, which replaces it only when that succeeds.
static int KF2_set_sigma(PyObject *self_, PyObject *value, void *unused)
{
    KF2Obj *self = (KF2Obj *)self_;
    gf_mat2 s;
    gf_kf2 fresh;
    (void)unused;
    if (set_sigma_value(value, "KF2.sigma") < 0 ||
        read_real(value, "KF2.sigma", 2, 2, &s.m[0][0]) < 0) {
        return -1;
    }
    memcpy(&fresh, &self->kf, sizeof fresh);
    const gf_vec2 m = self->kf.mu;
    if (check_idle(&self->f, reinit_back, "KF2.sigma") < 0 ||
        check(gf_kf2_init(&fresh, &m, &s), "KF2.sigma") < 0) {
        return -1;
    }
    memcpy(&self->kf, &fresh, sizeof fresh);
    return 0;
}

static int KF2_set_mu(PyObject *self_, PyObject *value, void *unused)
{
    KF2Obj *self = (KF2Obj *)self_;
    (void)unused;
    return set_mean(&self->f, self->kf.mu.v, 2, 0, value, "KF2.mu");
}

static PyObject *KF2_mu(PyObject *self, void *unused)
{
    (void)unused;
    if (check_readable((FilterObj *)self, "KF2.mu") < 0) {
        return NULL;
    }
    return new_array(2, 0, ((KF2Obj *)self)->kf.mu.v);
}

static PyMethodDef KF2_methods[] = {
    {"predict", (PyCFunction)(void (*)(void))Filter_predict,
     METH_FASTCALL | METH_KEYWORDS,
     "predict($self, /, model, u=None)\n--\n\n"
     "Prediction (Table 3.1, lines 2-3):\n"
     "    mu_bar = A mu + B u + c,   Sigma_bar = A Sigma A^T + R\n"
     "on the factors U D U^T of Sigma. u None: no control. Raises the\n"
     "status's GaussfiltError (NonFinite: u not finite); the belief is\n"
     "unchanged then."},
    {"update", (PyCFunction)(void (*)(void))Filter_update,
     METH_FASTCALL | METH_KEYWORDS,
     "update($self, /, meas, z)\n--\n\n"
     "Correction (Table 3.1, lines 4-6) with m = meas.m values z:\n"
     "    y = z - c - C mu_bar,   S = C Sigma_bar C^T + Q,\n"
     "    K = Sigma_bar C^T S^-1,  mu = mu_bar + K y,  Sigma = (I - K C) "
     "Sigma_bar\n"
     "(Bierman's scalar updates on the whitened rows), NIS = y^T S^-1 y.\n"
     "Gated (NIS > meas.gate) carries the innovation and NIS; every error\n"
     "leaves the belief unchanged."},
    {"run", (PyCFunction)(void (*)(void))Filter_run,
     METH_FASTCALL | METH_KEYWORDS,
     "run($self, /, model=None, meas=None, u=None, z=None, steps=None)\n--\n\n"
     "-> (mu (N, 2), sigma (N, 2, 2), nis (N,), status (N,))\n\n"
     "N steps in one call, each predict(model, u[k]) (when model is given)\n"
     "then update(meas, z[k]) (when z is given and z[k] has no NaN: a NaN\n"
     "row is a step without a measurement). A gated update is recorded\n"
     "(status -5 and its NIS) and the run goes on from the prediction;\n"
     "nis is NaN where no update ran. Any other failure raises with\n"
     "exc.step = k and puts the belief back as it was before the call."},
    {"__getstate__", Filter_getstate, METH_NOARGS,
     "__getstate__($self, /)\n--\n\nThe belief as pickle and copy keep it: "
     "every bit of its factors."},
    {"__setstate__", Filter_setstate, METH_O,
     "__setstate__($self, state, /)\n--\n\nRestores __getstate__'s "
     "belief (checked first)."},
    {"reset", (PyCFunction)(void (*)(void))Filter_reset,
     METH_VARARGS | METH_KEYWORDS,
     "reset($self, /, mu, sigma)\n--\n\nA new belief N(mu, sigma), judged and "
     "factored as the\n"
     "constructor does; raises as it does, the belief unchanged then."},
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef KF2_getset[] = {
    {"mu", KF2_mu, KF2_set_mu,
     "the mean, a (2,) copy; set: a new mean, the covariance kept", NULL},
    {"sigma", Filter_sigma, KF2_set_sigma,
     "the covariance, a (2, 2) array: Sigma = U D U^T, exactly symmetric;\n"
     "set: factored with the mean as the constructor does",
     NULL},
    {"nis", Filter_nis, NULL,
     "NIS = y^T S^-1 y of the last accepted update (nan before any)", NULL},
    {"innovation", Filter_innovation, NULL,
     "y = z - c - C mu_bar of the last accepted update (None before any)",
     NULL},
    {"S", Filter_S, NULL,
     "S = C Sigma_bar C^T + Q of the last accepted update, (m, m), computed\n"
     "in double from the prior's covariance when read (None before any)",
     (void *)REC_KF2},
    {"K", Filter_K, NULL,
     "the gain K = Sigma_bar C^T S^-1 of the last accepted update, (2, m)\n"
     "(None before any)",
     (void *)REC_KF2},
    {"loglik", Filter_loglik, NULL,
     "log N(y; 0, S) = -(NIS + log det S + m log 2 pi) / 2 of the last\n"
     "accepted update (nan before any)",
     (void *)REC_KF2},
    {NULL, NULL, NULL, NULL, NULL},
};

// ---- EKF3 -----------------------------------------------------------------

typedef struct {
    CallbackObj cb;
    gf_ekf3_pmotion pm;
    PyObject *weakrefs; // weakref support
} EKF3MotionObj;

typedef struct {
    CallbackObj cb;
    gf_ekf3_pmeas pq;
    PyObject *weakrefs; // weakref support
} EKF3MeasObj;

typedef struct {
    FilterObj f;
    gf_ekf3 ekf;
    PyObject *weakrefs; // weakref support
} EKF3Obj;

static PyTypeObject *EKF3Motion_Type, *EKF3Meas_Type, *EKF3_Type;

// The Python motion g(mu, u) -> (mu_bar, G) behind EKF3's C callback.
static gf_status ekf3_g_py(void *ctx, const gf_vec3 *mu, const gf_real *u,
                           gf_vec3 *mu_bar, gf_mat3 *G)
{
    CallbackObj *cb = (CallbackObj *)ctx;
    (void)u;
    return call_model(cb->fn, 1, cb->cur_u, mu->v, 3, 3, mu_bar->v, &G->m[0][0],
                      "EKF3");
}

// The Python measurement h(mu_bar) -> (z_hat, H) behind EKF3's callback;
// H's m rows of 3 are the first rows of the 3x3 H.
static gf_status ekf3_h_py(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                           gf_mat3 *H)
{
    EKF3MeasObj *me = (EKF3MeasObj *)ctx;
    return call_model(me->cb.fn, 0, NULL, mu_bar->v, 3, me->pq.meas.m, z_hat->v,
                      &H->m[0][0], "EKF3");
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
    if (check_callable(g, "EKF3Motion", "g") < 0) {
        return -1;
    }
    memset(&mo, 0, sizeof mo);
    if (read_real(R, "EKF3Motion: R", 3, 3, &mo.R.m[0][0]) < 0) {
        return -1;
    }
    if (PyObject_TypeCheck(g, Builtin_Type)) {
        if (!((BuiltinObj *)g)->g) {
            bad_arg("EKF3Motion: %s is a measurement", ((BuiltinObj *)g)->name);
            return -1;
        }
        mo.g = ((BuiltinObj *)g)->g;
    } else {
        mo.g = ekf3_g_py;
        mo.ctx = self;
    }
    if (check(gf_ekf3_prepare_motion(&self->pm, &mo), "EKF3Motion") < 0) {
        return -1;
    }
    set_fn(&self->cb, g);
    return 0;
}

// Q (m, m) packed row by row to or from the m x m block of a 3x3 matrix.
static void q3_copy(gf_real *dst, unsigned dst_cols, const gf_real *src,
                    unsigned src_cols, unsigned m)
{
    for (unsigned i = 0; i < m; i++) {
        for (unsigned j = 0; j < m; j++) {
            dst[dst_cols * i + j] = src[src_cols * i + j];
        }
    }
}

static int EKF3Meas_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"h", "Q", "angle_mask", "gate", NULL};
    EKF3MeasObj *self = (EKF3MeasObj *)self_;
    PyObject *h, *Q, *mask = NULL, *gate = NULL;
    unsigned angle_mask = 0;
    gf_ekf3_meas me;
    npy_intp rows, cols;
    gf_real Qv[9];
    char got[GOT_LEN];
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|OO:EKF3Meas", names, &h, &Q,
                                     &mask, &gate) ||
        read_unsigned(mask, "EKF3Meas: angle_mask", &angle_mask) < 0) {
        return -1;
    }
    if (check_callable(h, "EKF3Meas", "h") < 0) {
        return -1;
    }
    memset(&me, 0, sizeof me);
    if (shape_of(Q, "EKF3Meas: Q", 1, &rows, &cols, got) < 0) {
        return -1;
    }
    if (rows != cols || rows < 1 || rows > 3) {
        bad_arg("EKF3Meas: Q must have shape (m, m), m = 1..3, got %s", got);
        return -1;
    }
    me.m = (unsigned)rows;
    if (read_real(Q, "EKF3Meas: Q", rows, rows, Qv) < 0 ||
        read_gate(gate, "EKF3Meas", &me.gate) < 0) {
        return -1;
    }
    q3_copy(&me.Q.m[0][0], 3, Qv, me.m, me.m);
    me.angle_mask = angle_mask;
    if (PyObject_TypeCheck(h, Builtin_Type)) {
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
    if (check(gf_ekf3_prepare_meas(&self->pq, &me), "EKF3Meas") < 0) {
        return -1;
    }
    set_fn(&self->cb, h);
    return 0;
}

static PyObject *EKF3Motion_R(PyObject *self, void *unused)
{
    (void)unused;
    return new_array(3, 3, &((EKF3MotionObj *)self)->pm.motion.R.m[0][0]);
}

static PyObject *EKF3Meas_get(PyObject *self_, void *which)
{
    const gf_ekf3_meas *me = &((EKF3MeasObj *)self_)->pq.meas;
    gf_real v[9];
    switch ((int)(size_t)which) {
    case 1:
        q3_copy(v, me->m, &me->Q.m[0][0], 3, me->m);
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
    {"g", Callback_fn, NULL, "the motion g(mu, u) -> (mu_bar, G)", NULL},
    {"R", EKF3Motion_R, NULL, "process noise covariance (3, 3)", NULL},
    {NULL, NULL, NULL, NULL, NULL},
};

static PyGetSetDef EKF3Meas_getset[] = {
    {"h", Callback_fn, NULL, "the measurement h(mu_bar) -> (z_hat, H)", NULL},
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
    if (read_real(mu, "EKF3: mu", 0, 3, m.v) < 0 ||
        read_real(sigma, "EKF3: sigma", 3, 3, &s.m[0][0]) < 0 ||
        check_idle(&self->f, reinit_back, "EKF3") < 0 ||
        check(gf_ekf3_init(&self->ekf, &m, &s), "EKF3") < 0) {
        return -1;
    }
    self->f.has_last = 0;
    return 0;
}

// EKF3's steps for the shared entries (Family).
static unsigned ekf3_states(PyObject *f)
{
    (void)f;
    return 3;
}

// A built-in motion takes u = (d, phi).
static void ekf3_model_size(PyObject *model, unsigned *n, npy_intp *nu,
                            int *python_g)
{
    int builtin = model && ((EKF3MotionObj *)model)->pm.motion.g != ekf3_g_py;
    *n = 3;
    *nu = builtin ? 2 : 0;
    *python_g = model && !builtin;
}

static void ekf3_meas_size(PyObject *meas, unsigned *n, npy_intp *m)
{
    *n = 3;
    *m = ((EKF3MeasObj *)meas)->pq.meas.m;
}

// An EKF3 motion's u for its Python g during one prediction: u_obj in the
// model's cur_u, the one before returned for motion_u_leave. A built-in g
// takes no Python and nothing of the model is written (a run without the
// GIL may share it with another thread's).
static PyObject *motion_u_enter(EKF3MotionObj *mo, PyObject *u_obj)
{
    PyObject *prev = mo->cb.cur_u;
    if (mo->pm.motion.g == ekf3_g_py) {
        mo->cb.cur_u = u_obj;
    }
    return prev;
}

static void motion_u_leave(EKF3MotionObj *mo, PyObject *prev)
{
    if (mo->pm.motion.g == ekf3_g_py) {
        mo->cb.cur_u = prev;
    }
}

static gf_status ekf3_predict(PyObject *f, PyObject *model, const gf_real *u,
                              PyObject *u_obj)
{
    EKF3MotionObj *mo = (EKF3MotionObj *)model;
    PyObject *prev = motion_u_enter(mo, u_obj);
    const gf_status st =
        gf_ekf3_predict_prepared(&((EKF3Obj *)f)->ekf, &mo->pm, u);
    motion_u_leave(mo, prev);
    return st;
}

// EKF3's h as an update calls it, its H kept in rec: the model's own h
// and ctx called through a copy of the prepared model (the model itself,
// which other filters and threads may be using, is not written).
typedef struct {
    gf_ekf3_meas_fn h;
    void *ctx;
    UpdateRec *rec;
} Ekf3KeptH;

static gf_status ekf3_h_kept(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                             gf_mat3 *H)
{
    const Ekf3KeptH *k = (const Ekf3KeptH *)ctx;
    gf_status st = k->h(k->ctx, mu_bar, z_hat, H);
    if (st == GF_OK) {
        memcpy(k->rec->H, &H->m[0][0], 3 * k->rec->m * sizeof(gf_real));
    }
    return st;
}

static gf_status ekf3_update(PyObject *f, PyObject *meas, const gf_real *z,
                             gf_kf_innovation *info, UpdateRec *rec)
{
    gf_ekf3_pmeas pq = ((EKF3MeasObj *)meas)->pq;
    const unsigned m = pq.meas.m;
    gf_vec3 zv = {{z[0], m > 1 ? z[1] : GF_R(0.0), m > 2 ? z[2] : GF_R(0.0)}};
    gf_innovation in;
    Ekf3KeptH kept = {pq.meas.h, pq.meas.ctx, rec};
    rec->m = m;
    *rec->prior.ekf3 = ((EKF3Obj *)f)->ekf;
    pq.meas.h = ekf3_h_kept;
    pq.meas.ctx = &kept;
    gf_status st = gf_ekf3_update_prepared(&((EKF3Obj *)f)->ekf, &pq, &zv, &in);
    if (st == GF_OK || st == GF_ERR_GATED) {
        innovation_of(&in, info);
    }
    if (st == GF_OK) {
        rec->n = 3;
        block_copy(rec->Q, &pq.meas.Q.m[0][0], 3, m, m);
    }
    return st;
}

static void ekf3_record(PyObject *f, gf_real *mu, gf_real *sigma)
{
    const gf_ekf3 *ekf = &((EKF3Obj *)f)->ekf;
    memcpy(mu, ekf->mu.v, 3 * sizeof(gf_real));
    gf_ekf3_cov(ekf, (gf_mat3 *)sigma);
}

static int ekf3_meas_python(PyObject *meas)
{
    return ((EKF3MeasObj *)meas)->pq.meas.h == ekf3_h_py;
}

static const Family ekf3_family = {
    "EKF3",
    "EKF3.predict",
    "EKF3.predict: u",
    "EKF3.update",
    "EKF3.update: z",
    "EKF3.run",
    &EKF3Motion_Type,
    &EKF3Meas_Type,
    1,
    1,
    "(N, k)",
    offsetof(EKF3Obj, ekf),
    sizeof(gf_ekf3),
    ekf3_states,
    ekf3_model_size,
    ekf3_meas_size,
    ekf3_predict,
    ekf3_update,
    ekf3_record,
    ekf3_meas_python,
};

// The setter of EKF3's sigma, as KF2's.
static int EKF3_set_sigma(PyObject *self_, PyObject *value, void *unused)
{
    EKF3Obj *self = (EKF3Obj *)self_;
    gf_mat3 s;
    gf_ekf3 fresh;
    (void)unused;
    if (set_sigma_value(value, "EKF3.sigma") < 0 ||
        read_real(value, "EKF3.sigma", 3, 3, &s.m[0][0]) < 0) {
        return -1;
    }
    memcpy(&fresh, &self->ekf, sizeof fresh);
    const gf_vec3 m = self->ekf.mu;
    if (check_idle(&self->f, reinit_back, "EKF3.sigma") < 0 ||
        check(gf_ekf3_init(&fresh, &m, &s), "EKF3.sigma") < 0) {
        return -1;
    }
    memcpy(&self->ekf, &fresh, sizeof fresh);
    return 0;
}

static int EKF3_set_mu(PyObject *self_, PyObject *value, void *unused)
{
    EKF3Obj *self = (EKF3Obj *)self_;
    (void)unused;
    return set_mean(&self->f, self->ekf.mu.v, 3, 4u, value, "EKF3.mu");
}

static PyObject *EKF3_mu(PyObject *self, void *unused)
{
    (void)unused;
    if (check_readable((FilterObj *)self, "EKF3.mu") < 0) {
        return NULL;
    }
    return new_array(3, 0, ((EKF3Obj *)self)->ekf.mu.v);
}

static PyMethodDef EKF3_methods[] = {
    {"predict", (PyCFunction)(void (*)(void))Filter_predict,
     METH_FASTCALL | METH_KEYWORDS,
     "predict($self, /, motion, u=None)\n--\n\n"
     "Prediction (Table 3.3, lines 2-3), G = dg/dx at mu:\n"
     "    mu_bar = g(u, mu),   Sigma_bar = G Sigma G^T + R\n"
     "on the factors; the heading mu[2] is kept in (-pi, pi]. u is handed\n"
     "to g as is (forward_turn: u = (d, phi)). A callback's exception\n"
     "propagates; every failure leaves the belief unchanged."},
    {"update", (PyCFunction)(void (*)(void))Filter_update,
     METH_FASTCALL | METH_KEYWORDS,
     "update($self, /, meas, z)\n--\n\n"
     "Correction (Table 3.3, lines 4-6), H = dh/dx at mu_bar:\n"
     "    y = z - h(mu_bar) (angles in meas.angle_mask wrapped),\n"
     "    S = H Sigma_bar H^T + Q,  K = Sigma_bar H^T S^-1,\n"
     "    mu = mu_bar + K y,  Sigma = (I - K H) Sigma_bar,  NIS = y^T S^-1 y.\n"
     "Gated carries the innovation and NIS; every failure leaves the\n"
     "belief unchanged."},
    {"run", (PyCFunction)(void (*)(void))Filter_run,
     METH_FASTCALL | METH_KEYWORDS,
     "run($self, /, motion=None, meas=None, u=None, z=None, steps=None)\n--\n\n"
     "-> (mu (N, 3), sigma (N, 3, 3), nis (N,), status (N,))\n\n"
     "N steps in one call, as KF2.run: predict(motion, u[k]) (when motion\n"
     "is given; u (N, k), a row a step: a built-in motion takes k = 2, a\n"
     "Python g gets u[k] as a fresh (k,) array, or None without u) then\n"
     "update(meas, z[k]) unless z[k] has a NaN. A gated update is recorded\n"
     "(status -5 and its NIS) and the run goes on; any other failure, a\n"
     "callback's exception included, raises with exc.step = k and puts\n"
     "the belief back as it was before the call."},
    {"__getstate__", Filter_getstate, METH_NOARGS,
     "__getstate__($self, /)\n--\n\nThe belief as pickle and copy keep it: "
     "every bit of its factors."},
    {"__setstate__", Filter_setstate, METH_O,
     "__setstate__($self, state, /)\n--\n\nRestores __getstate__'s "
     "belief (checked first)."},
    {"reset", (PyCFunction)(void (*)(void))Filter_reset,
     METH_VARARGS | METH_KEYWORDS,
     "reset($self, /, mu, sigma)\n--\n\nA new belief N(mu, sigma), judged and "
     "factored as the\n"
     "constructor does; raises as it does, the belief unchanged then."},
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef EKF3_getset[] = {
    {"mu", EKF3_mu, EKF3_set_mu,
     "the mean (x, y, theta), a (3,) copy; set: a new mean (theta\n"
     "wrapped), the covariance kept",
     NULL},
    {"sigma", Filter_sigma, EKF3_set_sigma,
     "the covariance, a (3, 3) array: Sigma = U D U^T, exactly symmetric;\n"
     "set: factored with the mean as the constructor does",
     NULL},
    {"nis", Filter_nis, NULL,
     "NIS = y^T S^-1 y of the last accepted update (nan before any)", NULL},
    {"innovation", Filter_innovation, NULL,
     "y = z - h(mu_bar) of the last accepted update (None before any)", NULL},
    {"S", Filter_S, NULL,
     "S = H Sigma_bar H^T + Q of the last accepted update, (m, m), computed\n"
     "in double from the prior's covariance when read (None before any)",
     (void *)REC_EKF3},
    {"K", Filter_K, NULL,
     "the gain K = Sigma_bar H^T S^-1 of the last accepted update, (3, m)\n"
     "(None before any)",
     (void *)REC_EKF3},
    {"loglik", Filter_loglik, NULL,
     "log N(y; 0, S) = -(NIS + log det S + m log 2 pi) / 2 of the last\n"
     "accepted update (nan before any)",
     (void *)REC_EKF3},
    {NULL, NULL, NULL, NULL, NULL},
};

// ---- UKF3 -----------------------------------------------------------------

// The unscented filter over (x, y, theta), with EKF3's models (their
// Jacobians unread: a Python g or h still returns one, of any values).
typedef struct {
    FilterObj f;
    gf_ukf3 ukf;
    PyObject *weakrefs; // weakref support
} UKF3Obj;

static PyTypeObject *UKF3_Type;

// The parameters of Table 3.4 from the constructor's or reset's alpha,
// beta and kappa (NULL: 1, 2, 0).
static int ukf3_params(PyObject *a, PyObject *b, PyObject *k, gf_ukf3_params *p)
{
    double v[3] = {1.0, 2.0, 0.0};
    if ((a && read_number(a, "UKF3: alpha", &v[0]) < 0) ||
        (b && read_number(b, "UKF3: beta", &v[1]) < 0) ||
        (k && read_number(k, "UKF3: kappa", &v[2]) < 0)) {
        return -1;
    }
    p->alpha = (gf_real)v[0];
    p->beta = (gf_real)v[1];
    p->kappa = (gf_real)v[2];
    return 0;
}

static int UKF3_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"mu", "sigma", "alpha", "beta", "kappa", NULL};
    PyObject *mu, *sigma, *a = NULL, *b = NULL, *k = NULL;
    gf_vec3 m;
    gf_mat3 s;
    gf_ukf3_params p;
    UKF3Obj *self = (UKF3Obj *)self_;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|OOO:UKF3", names, &mu,
                                     &sigma, &a, &b, &k)) {
        return -1;
    }
    if (read_real(mu, "UKF3: mu", 0, 3, m.v) < 0 ||
        read_real(sigma, "UKF3: sigma", 3, 3, &s.m[0][0]) < 0 ||
        ukf3_params(a, b, k, &p) < 0 ||
        check_idle(&self->f, reinit_back, "UKF3") < 0 ||
        check(gf_ukf3_init(&self->ukf, &m, &s, &p), "UKF3") < 0) {
        return -1;
    }
    self->f.has_last = 0;
    return 0;
}

static gf_status ukf3_predict(PyObject *f, PyObject *model, const gf_real *u,
                              PyObject *u_obj)
{
    EKF3MotionObj *mo = (EKF3MotionObj *)model;
    PyObject *prev = motion_u_enter(mo, u_obj);
    const gf_status st =
        gf_ukf3_predict(&((UKF3Obj *)f)->ukf, &mo->pm.motion, u);
    motion_u_leave(mo, prev);
    return st;
}

// The UKF's S and Sigma^xz as an update forms them (ukf3.h), summed in
// double from the images Z_j = h(chi_j) of the seven sigma points as the
// library's calls of h give them (the centre first), the offsets chi_j -
// mu_bar = +-gamma L_i from L L^T = Sigma_bar taken in double: with dz_j
// = Z_j - Z_0 (the angle_mask entries wrapped) and w_i the points' weight,
//   m_z = sum_{j>0} w_i dz_j,  S = sum_{j>0} w_i dz_j dz_j^T
//   + (beta - alpha^2) m_z m_z^T + Q,  Sigma^xz = sum_{j>0} w_i off_j dz_j^T.
// The model's own h and ctx are called through a copy of the prepared
// model (the model itself is not written).
typedef struct {
    gf_ekf3_meas_fn h;
    void *ctx;
    unsigned j, m, mask;
    double wi;
    double off[3][3]; // off[i]: gamma L_i, column i of L
    double z0[3], mz[3], s[3][3], pxz[3][3];
} Ukf3KeptZ;

static double wrap_pi(double a)
{
    const double pi = 3.14159265358979323846;
    double w = fmod(a, 2.0 * pi);
    if (w > pi) {
        w -= 2.0 * pi;
    } else if (w <= -pi) {
        w += 2.0 * pi;
    }
    return w;
}

static gf_status ukf3_h_kept(void *ctx, const gf_vec3 *chi, gf_vec3 *z_hat,
                             gf_mat3 *H)
{
    Ukf3KeptZ *k = (Ukf3KeptZ *)ctx;
    gf_status st = k->h(k->ctx, chi, z_hat, H);
    if (st != GF_OK || k->j > 6u) {
        return st;
    }
    const unsigned j = k->j++;
    double dz[3];
    for (unsigned a = 0; a < k->m; a++) {
        if (j == 0u) {
            k->z0[a] = (double)z_hat->v[a];
            continue;
        }
        dz[a] = (double)z_hat->v[a] - k->z0[a];
        dz[a] = (k->mask >> a) & 1u ? wrap_pi(dz[a]) : dz[a];
    }
    if (j == 0u) {
        return st;
    }
    const double *o = k->off[(j - 1u) % 3u];
    const double sign = j > 3u ? -1.0 : 1.0;
    for (unsigned a = 0; a < k->m; a++) {
        const double wz = k->wi * dz[a];
        k->mz[a] += wz;
        for (unsigned b = 0; b <= a; b++) {
            k->s[a][b] += wz * dz[b];
        }
        for (unsigned x = 0; x < 3u; x++) {
            k->pxz[x][a] += sign * o[x] * wz;
        }
    }
    return st;
}

// An update of the library's, its S and (Sigma^xz)^T kept in rec (in Q
// and H, rounded once to the precision; ukf3_h_kept) with the prior.
static gf_status ukf3_update(PyObject *f, PyObject *meas, const gf_real *z,
                             gf_kf_innovation *info, UpdateRec *rec)
{
    gf_ekf3_meas me = ((EKF3MeasObj *)meas)->pq.meas;
    gf_ukf3 *ukf = &((UKF3Obj *)f)->ukf;
    const unsigned m = me.m;
    gf_vec3 zv = {{z[0], m > 1 ? z[1] : GF_R(0.0), m > 2 ? z[2] : GF_R(0.0)}};
    gf_innovation in;
    Ukf3KeptZ kept;
    memset(&kept, 0, sizeof kept);
    kept.h = me.h;
    kept.ctx = me.ctx;
    kept.m = m <= 3u ? m : 3u;
    kept.mask = me.angle_mask;
    kept.wi = (double)ukf->wi;
    // L L^T = Sigma_bar (symmetrised) in double, a zero column where the
    // pivot is not positive; off[i] = gamma L_i
    double L[3][3] = {{0.0}};
    for (unsigned c = 0; c < 3u; c++) {
        double d = (double)ukf->sigma.m[c][c];
        for (unsigned k = 0; k < c; k++) {
            d -= L[c][k] * L[c][k];
        }
        if (!(d > 0.0)) {
            continue;
        }
        L[c][c] = sqrt(d);
        for (unsigned i = c + 1; i < 3u; i++) {
            double v = 0.5 * (double)ukf->sigma.m[i][c] +
                       0.5 * (double)ukf->sigma.m[c][i];
            for (unsigned k = 0; k < c; k++) {
                v -= L[i][k] * L[c][k];
            }
            L[i][c] = v / L[c][c];
        }
    }
    for (unsigned i = 0; i < 3u; i++) {
        for (unsigned x = 0; x < 3u; x++) {
            kept.off[i][x] = (double)ukf->gamma * L[x][i];
        }
    }
    rec->m = m;
    memcpy(rec->prior.p, ukf, sizeof *ukf);
    me.h = ukf3_h_kept;
    me.ctx = &kept;
    gf_status st = gf_ukf3_update(ukf, &me, &zv, &in);
    if (st == GF_OK || st == GF_ERR_GATED) {
        innovation_of(&in, info);
    }
    if (st == GF_OK) {
        const double wfold = (double)((const gf_ukf3 *)rec->prior.p)->wfold;
        rec->n = 3;
        for (unsigned a = 0; a < kept.m; a++) {
            for (unsigned b = 0; b < kept.m; b++) {
                const double q =
                    0.5 * (double)me.Q.m[a][b] + 0.5 * (double)me.Q.m[b][a];
                const double sab = b <= a ? kept.s[a][b] : kept.s[b][a];
                rec->Q[kept.m * a + b] =
                    (gf_real)(sab + wfold * kept.mz[a] * kept.mz[b] + q);
            }
            for (unsigned x = 0; x < 3u; x++) {
                rec->H[3u * a + x] = (gf_real)kept.pxz[x][a];
            }
        }
    }
    return st;
}

static void ukf3_record(PyObject *f, gf_real *mu, gf_real *sigma)
{
    const gf_ukf3 *u = &((UKF3Obj *)f)->ukf;
    memcpy(mu, u->mu.v, 3 * sizeof(gf_real));
    memcpy(sigma, &u->sigma.m[0][0], 9 * sizeof(gf_real));
}

static const Family ukf3_family = {
    "UKF3",
    "UKF3.predict",
    "UKF3.predict: u",
    "UKF3.update",
    "UKF3.update: z",
    "UKF3.run",
    &EKF3Motion_Type,
    &EKF3Meas_Type,
    1,
    1,
    "(N, k)",
    offsetof(UKF3Obj, ukf),
    sizeof(gf_ukf3),
    ekf3_states,
    ekf3_model_size,
    ekf3_meas_size,
    ukf3_predict,
    ukf3_update,
    ukf3_record,
    ekf3_meas_python,
};

static PyObject *UKF3_mu(PyObject *self, void *unused)
{
    (void)unused;
    if (check_readable((FilterObj *)self, "UKF3.mu") < 0) {
        return NULL;
    }
    return new_array(3, 0, ((UKF3Obj *)self)->ukf.mu.v);
}

static int UKF3_set_mu(PyObject *self_, PyObject *value, void *unused)
{
    UKF3Obj *self = (UKF3Obj *)self_;
    (void)unused;
    return set_mean(&self->f, self->ukf.mu.v, 3, 4u, value, "UKF3.mu");
}

// UKF3 keeps Sigma itself (no factors): the getter's copy of it.
// The setter of sigma: judged and symmetrised by gf_ukf3_init (with the
// mean, into a copy; its weights discarded), the filter's weights kept.
static int UKF3_set_sigma(PyObject *self_, PyObject *value, void *unused)
{
    UKF3Obj *self = (UKF3Obj *)self_;
    const gf_ukf3_params p = {GF_R(1.0), GF_R(2.0), GF_R(0.0)};
    gf_mat3 s;
    gf_ukf3 fresh;
    (void)unused;
    if (set_sigma_value(value, "UKF3.sigma") < 0 ||
        read_real(value, "UKF3.sigma", 3, 3, &s.m[0][0]) < 0) {
        return -1;
    }
    const gf_vec3 m = self->ukf.mu;
    if (check_idle(&self->f, reinit_back, "UKF3.sigma") < 0 ||
        check(gf_ukf3_init(&fresh, &m, &s, &p), "UKF3.sigma") < 0) {
        return -1;
    }
    self->ukf.sigma = fresh.sigma;
    return 0;
}

static PyMethodDef UKF3_methods[] = {
    {"predict", (PyCFunction)(void (*)(void))Filter_predict,
     METH_FASTCALL | METH_KEYWORDS,
     "predict($self, /, motion, u=None)\n--\n\n"
     "Prediction (Table 3.4, lines 2-5): the 7 sigma points\n"
     "    chi = (mu, mu +- gamma sqrt(Sigma)_i)\n"
     "through g, mu_bar and Sigma_bar their weighted moments plus R; the\n"
     "heading kept in (-pi, pi]. motion: an EKF3Motion (its G unread).\n"
     "GF_ERR_UNDEFINED (Undefined) when the points are too close for the\n"
     "precision (a larger alpha resolves them). A callback's exception\n"
     "propagates; every failure leaves the belief unchanged."},
    {"update", (PyCFunction)(void (*)(void))Filter_update,
     METH_FASTCALL | METH_KEYWORDS,
     "update($self, /, meas, z)\n--\n\n"
     "Correction (Table 3.4, lines 6-13): Z_i = h(chi_bar_i),\n"
     "    z_hat, S, Sigma^xz their weighted moments (+ Q in S),\n"
     "    K = Sigma^xz S^-1,  mu = mu_bar + K (z - z_hat),\n"
     "    Sigma = Sigma_bar - K S K^T,  NIS = y^T S^-1 y.\n"
     "meas: an EKF3Meas (its H unread). Gated carries the innovation and\n"
     "NIS; every failure leaves the belief unchanged."},
    {"run", (PyCFunction)(void (*)(void))Filter_run,
     METH_FASTCALL | METH_KEYWORDS,
     "run($self, /, motion=None, meas=None, u=None, z=None, steps=None)\n--\n\n"
     "-> (mu (N, 3), sigma (N, 3, 3), nis (N,), status (N,))\n\n"
     "N steps in one call, as EKF3.run."},
    {"__getstate__", Filter_getstate, METH_NOARGS,
     "__getstate__($self, /)\n--\n\nThe belief as pickle and copy keep it: "
     "every bit of its mean, Sigma and weights."},
    {"__setstate__", Filter_setstate, METH_O,
     "__setstate__($self, state, /)\n--\n\nRestores __getstate__'s "
     "belief (checked first)."},
    {"reset", (PyCFunction)(void (*)(void))Filter_reset,
     METH_VARARGS | METH_KEYWORDS,
     "reset($self, /, mu, sigma, alpha=1.0, beta=2.0, kappa=0.0)\n--\n\n"
     "A new belief N(mu, sigma), judged as the constructor does; raises\n"
     "as it does, the belief unchanged then."},
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef UKF3_getset[] = {
    {"mu", UKF3_mu, UKF3_set_mu,
     "the mean (x, y, theta), a (3,) copy; set: a new mean (theta\n"
     "wrapped), the covariance kept",
     NULL},
    {"sigma", Filter_sigma, UKF3_set_sigma,
     "the covariance, a (3, 3) copy; set: judged and symmetrised as the\n"
     "constructor does, the weights kept",
     NULL},
    {"nis", Filter_nis, NULL,
     "NIS = y^T S^-1 y of the last accepted update (nan before any)", NULL},
    {"innovation", Filter_innovation, NULL,
     "y = z - z_hat of the last accepted update (None before any)", NULL},
    {"S", Filter_S, NULL,
     "the unscented S = sum_i w_c,i (Z_i - z_hat)(Z_i - z_hat)^T + Q of the\n"
     "last accepted update, (m, m), summed in double from its sigma points'\n"
     "images (None before any)",
     (void *)REC_UKF3},
    {"K", Filter_K, NULL,
     "the gain K = Sigma^xz S^-1 of the last accepted update, (3, m)\n"
     "(None before any)",
     (void *)REC_UKF3},
    {"loglik", Filter_loglik, NULL,
     "log N(y; 0, S) = -(NIS + log det S + m log 2 pi) / 2 of the last\n"
     "accepted update (nan before any)",
     (void *)REC_UKF3},
    {NULL, NULL, NULL, NULL, NULL},
};

// ---- PF3 ------------------------------------------------------------------

// The particle filter over (x, y, theta), with EKF3's models (Jacobians
// unread). The particles are the object's (PyMem), the generator the
// library's gf_rng in the belief.
typedef struct {
    FilterObj f;
    gf_pf3 pf;
    double loglik;      // of the last accepted update (pf3_update); NaN: none
    PyObject *weakrefs; // weakref support
} PF3Obj;

static PyTypeObject *PF3_Type;

static void PF3_dealloc(PyObject *self)
{
    PyMem_Free(((PF3Obj *)self)->pf.p);
    Filter_dealloc(self);
}

// PF3's belief is its particles: a filter made with __new__ and never
// initialised has none. 0, or BadArgument naming who and -1.
static int pf3_ready(const PF3Obj *self, const char *who)
{
    if (self->pf.p && self->pf.n) {
        return 0;
    }
    bad_arg("%s: the filter was never initialised", who);
    return -1;
}

static int PF3_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"mu", "sigma", "n", "seed", NULL};
    PyObject *mu, *sigma, *n_o, *seed_o = NULL;
    unsigned long n = 0, seed = 0;
    gf_vec3 m;
    gf_mat3 s;
    gf_pf3 fresh;
    PF3Obj *self = (PF3Obj *)self_;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OOO|O:PF3", names, &mu, &sigma,
                                     &n_o, &seed_o)) {
        return -1;
    }
    if (read_real(mu, "PF3: mu", 0, 3, m.v) < 0 ||
        read_real(sigma, "PF3: sigma", 3, 3, &s.m[0][0]) < 0 ||
        read_count(n_o, "PF3: n", GF_PF3_MAX_N, &n) < 0 ||
        (seed_o && read_count(seed_o, "PF3: seed", 0xFFFFFFFFul, &seed) < 0)) {
        return -1;
    }
    if (n < 1) {
        bad_arg("PF3: n must be in 1..%lu", (unsigned long)GF_PF3_MAX_N);
        return -1;
    }
    gf_pf3_particle *p = PyMem_Calloc(n, sizeof *p);
    if (!p) {
        PyErr_NoMemory();
        return -1;
    }
    if (check_idle(&self->f, reinit_back, "PF3") < 0 ||
        check(gf_pf3_init(&fresh, p, (unsigned)n, (uint32_t)seed, &m, &s),
              "PF3") < 0) {
        PyMem_Free(p);
        return -1;
    }
    PyMem_Free(self->pf.p);
    self->pf = fresh;
    self->f.has_last = 0;
    self->loglik = (double)NAN;
    return 0;
}

static gf_status pf3_predict(PyObject *f, PyObject *model, const gf_real *u,
                             PyObject *u_obj)
{
    EKF3MotionObj *mo = (EKF3MotionObj *)model;
    PyObject *prev = motion_u_enter(mo, u_obj);
    const gf_status st = gf_pf3_predict(&((PF3Obj *)f)->pf, &mo->pm.motion, u);
    motion_u_leave(mo, prev);
    return st;
}

// The particle filter's likelihood of an update's z, summed in double as
// the library's dry run over the particles calls h (particle k's state
// x_k passed as &p[k].x, the first n calls; the commit's calls after them
// are not read): with W the prior weights' total, d2_k = r_k^T Q^-1 r_k
// (r_k = z - h(x_k), the angle_mask entries wrapped) and L L^T = Q (its
// lower triangle, as the library reads it),
//   loglik = log sum_k (w_k / W) N(z; h(x_k), Q)
//          = log sum_k w_k exp(-(d2_k - d2_min) / 2) - d2_min / 2 - log W
//            - (m log 2 pi + log det Q) / 2.
// The model's own h and ctx are called through a copy of the model.
typedef struct {
    gf_ekf3_meas_fn h;
    void *ctx;
    const gf_pf3 *pf;
    unsigned calls, m, mask;
    int ok, seen;
    double z[3], L[3][3];
    double dmin, sum;
} Pf3KeptLik;

static gf_status pf3_h_kept(void *ctx, const gf_vec3 *x, gf_vec3 *z_hat,
                            gf_mat3 *H)
{
    Pf3KeptLik *k = (Pf3KeptLik *)ctx;
    gf_status st = k->h(k->ctx, x, z_hat, H);
    const unsigned j = k->calls++;
    if (st != GF_OK || j >= k->pf->n) {
        return st;
    }
    if (x != &k->pf->p[j].x) { // not the dry run's order: no estimate
        k->ok = 0;
        return st;
    }
    const double w = (double)k->pf->p[j].w;
    if (!(w > 0.0)) {
        return st;
    }
    // d2 = |L^-1 r|^2
    double y[3], d2 = 0.0;
    for (unsigned i = 0; i < k->m; i++) {
        double r = k->z[i] - (double)z_hat->v[i];
        r = (k->mask >> i) & 1u ? wrap_pi(r) : r;
        for (unsigned c = 0; c < i; c++) {
            r -= k->L[i][c] * y[c];
        }
        y[i] = r / k->L[i][i];
        d2 += y[i] * y[i];
    }
    if (!isfinite(d2)) {
        return st;
    }
    if (!k->seen || d2 < k->dmin) {
        k->sum = k->seen ? k->sum * exp(-0.5 * (k->dmin - d2)) : 0.0;
        k->dmin = d2;
        k->seen = 1;
    }
    k->sum += w * exp(-0.5 * (d2 - k->dmin));
    return st;
}

// The library's PF update gives no innovation: info holds none (m = 0,
// NIS nan), rec no record. An accepted update's likelihood (Pf3KeptLik)
// goes to the filter's loglik (NaN when it could not be formed).
static gf_status pf3_update(PyObject *f, PyObject *meas, const gf_real *z,
                            gf_kf_innovation *info, UpdateRec *rec)
{
    const double pi = 3.14159265358979323846;
    PF3Obj *self = (PF3Obj *)f;
    gf_ekf3_meas me = ((EKF3MeasObj *)meas)->pq.meas;
    const unsigned m = me.m;
    gf_vec3 zv = {{z[0], m > 1 ? z[1] : GF_R(0.0), m > 2 ? z[2] : GF_R(0.0)}};
    Pf3KeptLik kept;
    memset(&kept, 0, sizeof kept);
    kept.h = me.h;
    kept.ctx = me.ctx;
    kept.pf = &self->pf;
    kept.m = m <= 3u ? m : 3u;
    kept.mask = me.angle_mask;
    kept.ok = 1;
    double logdet = 0.0, total = 0.0;
    for (unsigned i = 0; i < kept.m; i++) {
        kept.z[i] = (double)zv.v[i];
        for (unsigned c = 0; c <= i; c++) {
            double v = (double)me.Q.m[i][c];
            for (unsigned t = 0; t < c; t++) {
                v -= kept.L[i][t] * kept.L[c][t];
            }
            if (c < i) {
                kept.L[i][c] = v / kept.L[c][c];
            } else if (v > 0.0) {
                kept.L[i][i] = sqrt(v);
                logdet += 2.0 * log(kept.L[i][i]);
            } else {
                kept.ok = 0; // the library refuses such a Q
                kept.L[i][i] = 1.0;
            }
        }
    }
    for (unsigned j = 0; j < self->pf.n; j++) {
        total += (double)self->pf.p[j].w;
    }
    info->m = 0;
    info->nis = (gf_real)NAN;
    rec->m = 0;
    me.h = pf3_h_kept;
    me.ctx = &kept;
    gf_status st = gf_pf3_update(&self->pf, &me, &zv);
    if (st == GF_OK) {
        self->loglik = kept.ok && kept.seen && kept.sum > 0.0 && total > 0.0
                           ? log(kept.sum) - 0.5 * kept.dmin - log(total) -
                                 0.5 * (m * log(2.0 * pi) + logdet)
                           : (double)NAN;
    }
    return st;
}

// The steps as predict_entry and update_entry take them (PF3 has no run:
// its belief is not one block to put back).
static const Family pf3_family = {
    "PF3",
    "PF3.predict",
    "PF3.predict: u",
    "PF3.update",
    "PF3.update: z",
    "PF3.run",
    &EKF3Motion_Type,
    &EKF3Meas_Type,
    1,
    1,
    "(N, k)",
    offsetof(PF3Obj, pf),
    sizeof(gf_pf3),
    ekf3_states,
    ekf3_model_size,
    ekf3_meas_size,
    pf3_predict,
    pf3_update,
    NULL,
    ekf3_meas_python,
};

static PyObject *PF3_predict(PyObject *self, PyObject *const *args,
                             Py_ssize_t nargs, PyObject *kwnames)
{
    if (pf3_ready((PF3Obj *)self, "PF3.predict") < 0) {
        return NULL;
    }
    return predict_entry(&pf3_family, self, args, nargs, kwnames);
}

static PyObject *PF3_update(PyObject *self, PyObject *const *args,
                            Py_ssize_t nargs, PyObject *kwnames)
{
    if (pf3_ready((PF3Obj *)self, "PF3.update") < 0) {
        return NULL;
    }
    return update_entry(&pf3_family, self, args, nargs, kwnames);
}

static PyObject *PF3_resample(PyObject *self_, PyObject *unused)
{
    PF3Obj *self = (PF3Obj *)self_;
    (void)unused;
    if (pf3_ready(self, "PF3.resample") < 0 ||
        check_idle(&self->f, called_back, "PF3.resample") < 0 ||
        check(gf_pf3_resample(&self->pf), "PF3.resample") < 0) {
        return NULL;
    }
    Py_RETURN_NONE;
}

// run(motion=None, meas=None, u=None, z=None, steps=None, resample=True):
// N steps, each predict(motion, u[k]) (when motion is given), then
// update(meas, z[k]) unless z[k] has a NaN, then resample() after an
// accepted update when resample is true (Table 4.3's loop). Returns the
// estimate after each step, mu (N, 3) and sigma (N, 3, 3) (NaN where the
// headings cancel out), neff (N,) and status (N,); a gated update is
// recorded (-5) and the run goes on; any other failure raises with
// exc.step and puts the particles and the generator back as they were.
// With no Python model in the run the steps go without the GIL, as
// run_steps' do (BUSY_NOGIL).
static PyObject *PF3_run(PyObject *self_, PyObject *const *args,
                         Py_ssize_t nargs, PyObject *kwnames)
{
    static const char *const names[] = {"motion", "meas",  "u",
                                        "z",      "steps", "resample"};
    PF3Obj *self = (PF3Obj *)self_;
    PyObject *a[6], *U = NULL, *Z = NULL, *o[4] = {NULL, NULL, NULL, NULL};
    PyObject *model = NULL, *meas = NULL, *out = NULL;
    unsigned got;
    npy_intp N, k, nu = 0, m = 0, t = 0;
    int python_g = 0, resample = 1;
    gf_status st = GF_OK;
    if (pf3_ready(self, "PF3.run") < 0 ||
        get_args("run", args, nargs, kwnames, names, 0, 6, a) < 0) {
        return NULL;
    }
    if (given(a[0])) {
        if (check_type(a[0], EKF3Motion_Type, "PF3.run", "motion", 1) < 0) {
            return NULL;
        }
        model = a[0];
        ekf3_model_size(model, &got, &nu, &python_g);
    }
    if (given(a[1])) {
        if (check_type(a[1], EKF3Meas_Type, "PF3.run", "meas", 1) < 0) {
            return NULL;
        }
        meas = a[1];
        ekf3_meas_size(meas, &got, &m);
    }
    if (a[5] && (resample = PyObject_IsTrue(a[5])) < 0) {
        return NULL;
    }
    if (!model && given(a[2])) {
        return bad_arg("PF3.run: u without motion");
    }
    if (check_idle(&self->f, called_back, "PF3.run") < 0 ||
        recs_ready(&self->f, &pf3_family) < 0 ||
        run_arrays(&pf3_family, a[2], a[3], a[4], nu, nu != 0, NULL, m, &U, &Z,
                   &N, &k) < 0) {
        return NULL;
    }
    const size_t bytes = self->pf.n * sizeof *self->pf.p;
    gf_pf3_particle *saved = PyMem_Malloc(bytes ? bytes : 1);
    if (!saved || run_outputs(N, 3, o) < 0) {
        PyMem_Free(saved);
        Py_XDECREF(U);
        Py_XDECREF(Z);
        return saved ? NULL : PyErr_NoMemory();
    }
    memcpy(saved, self->pf.p, bytes);
    const gf_rng saved_rng = self->pf.rng;
    const double saved_loglik = self->loglik;
    const gf_real *u =
        U ? (const gf_real *)PyArray_DATA((PyArrayObject *)U) : NULL;
    const gf_real *z =
        Z ? (const gf_real *)PyArray_DATA((PyArrayObject *)Z) : NULL;
    gf_real *mu_o = (gf_real *)PyArray_DATA((PyArrayObject *)o[0]);
    gf_real *sg_o = (gf_real *)PyArray_DATA((PyArrayObject *)o[1]);
    gf_real *neff_o = (gf_real *)PyArray_DATA((PyArrayObject *)o[2]);
    signed char *st_o = (signed char *)PyArray_DATA((PyArrayObject *)o[3]);
    const int nogil = !python_g && !(meas && ekf3_meas_python(meas));
    PyThreadState *ts = NULL;
    self->f.busy = nogil ? BUSY_NOGIL : BUSY_STEP;
    if (nogil) {
        ts = PyEval_SaveThread();
    }
    for (t = 0; t < N; t++) {
        gf_kf_innovation info;
        UpdateRec *rec = self->f.rec[!self->f.cur];
        st = GF_OK;
        if (model) {
            PyObject *ut = NULL;
            if (U && python_g && !(ut = u_row(U, t, k))) {
                st = GF_ERR_MODEL;
            } else {
                st = pf3_predict(self_, model, u ? u + k * t : NULL, ut);
                Py_XDECREF(ut);
            }
        }
        if (st == GF_OK && z && z_present(z + m * t, m)) {
            st = pf3_update(self_, meas, z + m * t, &info, rec);
            if (st == GF_OK && resample) {
                st = gf_pf3_resample(&self->pf);
            }
        }
        if (st != GF_OK && st != GF_ERR_GATED) {
            break;
        }
        st_o[t] = (signed char)st;
        gf_vec3 em;
        gf_mat3 es;
        if (gf_pf3_estimate(&self->pf, &em, &es) != GF_OK) {
            for (int i = 0; i < 3; i++) {
                em.v[i] = (gf_real)NAN;
            }
            for (int i = 0; i < 9; i++) {
                (&es.m[0][0])[i] = (gf_real)NAN;
            }
        }
        memcpy(mu_o + 3 * t, em.v, 3 * sizeof(gf_real));
        memcpy(sg_o + 9 * t, &es.m[0][0], 9 * sizeof(gf_real));
        if (gf_pf3_neff(&self->pf, &neff_o[t]) != GF_OK) {
            neff_o[t] = (gf_real)NAN;
        }
    }
    if (ts) {
        PyEval_RestoreThread(ts);
    }
    self->f.busy = 0;
    if (t < N) {
        memcpy(self->pf.p, saved, bytes);
        self->pf.rng = saved_rng;
        self->loglik = saved_loglik;
        if (!PyErr_Occurred()) {
            raise_status(st, "PF3.run", NULL, NULL, 0, 0);
        }
        set_step(t);
    } else {
        out = PyTuple_Pack(4, o[0], o[1], o[2], o[3]);
    }
    PyMem_Free(saved);
    Py_XDECREF(U);
    Py_XDECREF(Z);
    for (int i = 0; i < 4; i++) {
        Py_XDECREF(o[i]);
    }
    return out;
}

// The getters of the estimate: mu (which 0) and sigma (1), from
// gf_pf3_estimate (Undefined when the weights or headings allow none).
static PyObject *PF3_estimate(PyObject *self_, void *which)
{
    PF3Obj *self = (PF3Obj *)self_;
    const int sg = which != NULL;
    const char *who = sg ? "PF3.sigma" : "PF3.mu";
    gf_vec3 m;
    gf_mat3 s;
    if (check_readable(&self->f, who) < 0 || pf3_ready(self, who) < 0) {
        return NULL;
    }
    gf_status st = gf_pf3_estimate(&self->pf, &m, &s);
    if (st != GF_OK) {
        return raise_status(st, who, NULL, NULL, 0, 0);
    }
    return sg ? new_sigma(3, &s.m[0][0]) : new_array(3, 0, m.v);
}

// The getters of particles (n, 3), weights (n,), n and neff.
static PyObject *PF3_get(PyObject *self_, void *which)
{
    PF3Obj *self = (PF3Obj *)self_;
    const gf_pf3 *pf = &self->pf;
    const int w = (int)(size_t)which;
    if (w == 2) {
        return PyLong_FromUnsignedLong(pf->p ? pf->n : 0u);
    }
    if (check_readable(&self->f, "PF3") < 0 || pf3_ready(self, "PF3") < 0) {
        return NULL;
    }
    if (w == 4) {
        return PyFloat_FromDouble(self->loglik);
    }
    if (w == 3) {
        gf_real neff;
        gf_status st = gf_pf3_neff(pf, &neff);
        if (st != GF_OK) {
            return raise_status(st, "PF3.neff", NULL, NULL, 0, 0);
        }
        return PyFloat_FromDouble((double)neff);
    }
    PyObject *a = new_array(pf->n, w == 0 ? 3 : 0, NULL);
    if (a) {
        gf_real *d = (gf_real *)PyArray_DATA((PyArrayObject *)a);
        for (unsigned k = 0; k < pf->n; k++) {
            if (w == 0) {
                memcpy(d + 3 * k, pf->p[k].x.v, 3 * sizeof(gf_real));
            } else {
                d[k] = pf->p[k].w;
            }
        }
    }
    return a;
}

// __getstate__: (2, precision, the particles as bytes, the generator as
// bytes, loglik's double as bytes), and a subclass object's attributes as
// a sixth item. (Version 1, without loglik, is still read.)
static PyObject *PF3_getstate(PyObject *self_, PyObject *unused)
{
    PF3Obj *self = (PF3Obj *)self_;
    gf_rng rng;
    (void)unused;
    if (check_readable(&self->f, "PF3") < 0 ||
        pf3_ready(self, "PF3.__getstate__") < 0) {
        return NULL;
    }
    // the generator's padding as zeros: equal filters give equal states
    memset(&rng, 0, sizeof rng);
    memcpy(rng.s, self->pf.rng.s, sizeof rng.s);
    rng.spare = self->pf.rng.spare;
    rng.has_spare = self->pf.rng.has_spare;
    PyObject *d = instance_dict(self_);
    if (!d && PyErr_Occurred()) {
        return NULL;
    }
    const char *p = (const char *)self->pf.p;
    const Py_ssize_t np = (Py_ssize_t)(self->pf.n * sizeof *self->pf.p);
    const char *ll = (const char *)&self->loglik;
    const Py_ssize_t nll = (Py_ssize_t)sizeof self->loglik;
    return d ? Py_BuildValue("(isy#y#y#N)", 2, GF_PREC_NAME, p, np,
                             (const char *)&rng, (Py_ssize_t)sizeof rng, ll,
                             nll, d)
             : Py_BuildValue("(isy#y#y#)", 2, GF_PREC_NAME, p, np,
                             (const char *)&rng, (Py_ssize_t)sizeof rng, ll,
                             nll);
}

// __setstate__: __getstate__'s particles, generator and loglik, checked
// first (the sizes; every particle finite, its heading in (-pi, pi], its
// weight >= 0, the weights' sum positive; the generator's state not all
// zero, its spare finite); BadArgument otherwise, the filter unchanged. A
// state of version 1 (no loglik) gives loglik nan.
static PyObject *PF3_setstate(PyObject *self_, PyObject *st)
{
    PF3Obj *self = (PF3Obj *)self_;
    int version;
    const char *prec, *parts, *rng_b;
    Py_ssize_t np, nr;
    PyObject *d = Py_None, *a4 = NULL, *a5 = NULL;
    gf_rng rng;
    double loglik = (double)NAN;
    const char *what = "PF3.__setstate__";
    if (!PyTuple_Check(st) ||
        !PyArg_ParseTuple(st, "isy#y#|OO", &version, &prec, &parts, &np, &rng_b,
                          &nr, &a4, &a5)) {
        PyErr_Clear();
        return bad_arg("%s: not a state of this package", what);
    }
    if (version == 2) { // loglik's bytes, then the attributes
        if (!a4 || !PyBytes_Check(a4) ||
            PyBytes_Size(a4) != (Py_ssize_t)sizeof loglik) {
            return bad_arg("%s: not a state of this package", what);
        }
        memcpy(&loglik, PyBytes_AsString(a4), sizeof loglik);
        d = a5 ? a5 : Py_None;
    } else if (a5) {
        return bad_arg("%s: not a state of this package", what);
    } else {
        d = a4 ? a4 : Py_None;
    }
    const size_t ps = sizeof(gf_pf3_particle);
    if ((version != 1 && version != 2) || strcmp(prec, GF_PREC_NAME) != 0 ||
        np <= 0 || (size_t)np % ps != 0 || (size_t)np / ps > GF_PF3_MAX_N ||
        (size_t)nr != sizeof rng) {
        return bad_arg("%s: a state of version %d in %s with %zd and %zd "
                       "bytes, not one of this filter's (version 2 in %s)",
                       what, version, prec, np, nr, GF_PREC_NAME);
    }
    if (d != Py_None && (!PyDict_Check(d) || !has_dict(self_))) {
        return bad_arg("%s: the state's attributes are not a dict for an "
                       "object with a __dict__",
                       what);
    }
    const unsigned n = (unsigned)((size_t)np / ps);
    memcpy(&rng, rng_b, sizeof rng);
    gf_pf3_particle *p = PyMem_Malloc((size_t)np);
    if (!p) {
        return PyErr_NoMemory();
    }
    memcpy(p, parts, (size_t)np);
    double total = 0.0;
    int sound = (rng.s[0] | rng.s[1] | rng.s[2] | rng.s[3]) != 0 &&
                isfinite((double)rng.spare) &&
                (rng.has_spare == 0 || rng.has_spare == 1);
    for (unsigned k = 0; sound && k < n; k++) {
        const gf_real *x = p[k].x.v;
        sound = isfinite((double)x[0]) && isfinite((double)x[1]) &&
                x[2] > -GF_PI && x[2] <= GF_PI && p[k].w >= 0 &&
                isfinite((double)p[k].w);
        total += (double)p[k].w;
    }
    if (!sound || !(total > 0.0)) {
        PyMem_Free(p);
        return bad_arg("%s: the state's particles are not ones the library "
                       "made",
                       what);
    }
    if (check_idle(&self->f, reinit_back, what) < 0 ||
        update_instance_dict(self_, d) < 0) {
        PyMem_Free(p);
        return NULL;
    }
    PyMem_Free(self->pf.p);
    self->pf.p = p;
    self->pf.n = n;
    self->pf.rng = rng;
    self->f.has_last = 0;
    self->loglik = loglik;
    Py_RETURN_NONE;
}

static PyMethodDef PF3_methods[] = {
    {"predict", (PyCFunction)(void (*)(void))PF3_predict,
     METH_FASTCALL | METH_KEYWORDS,
     "predict($self, /, motion, u=None)\n--\n\n"
     "Prediction by sampling (Table 4.3, line 4): each particle\n"
     "    x^[k] = g(u, x^[k]) + eps^[k],  eps^[k] ~ N(0, R)\n"
     "(the filter's own generator), heading wrapped, weights kept.\n"
     "motion: an EKF3Motion (its G unread); g is called twice a particle\n"
     "(a dry run first) and must be a pure function. Every failure\n"
     "leaves the particles and the generator unchanged."},
    {"update", (PyCFunction)(void (*)(void))PF3_update,
     METH_FASTCALL | METH_KEYWORDS,
     "update($self, /, meas, z)\n--\n\n"
     "Correction by importance weights (Table 4.3, line 5):\n"
     "    w^[k] <- w^[k] exp(-r_k^T Q^-1 r_k / 2),  r_k = z - h(x^[k]),\n"
     "then normalised. Gated when even the closest particle's r^T Q^-1 r\n"
     "exceeds meas.gate; Singular when Q is not positive definite. Every\n"
     "failure leaves the particles unchanged."},
    {"run", (PyCFunction)(void (*)(void))PF3_run, METH_FASTCALL | METH_KEYWORDS,
     "run($self, /, motion=None, meas=None, u=None, z=None, steps=None, "
     "resample=True)\n--\n\n"
     "-> (mu (N, 3), sigma (N, 3, 3), neff (N,), status (N,))\n\n"
     "N steps in one call: predict(motion, u[k]) (when motion is given),\n"
     "update(meas, z[k]) unless z[k] has a NaN, then resample() after an\n"
     "accepted update when resample is true (Table 4.3's loop). mu and\n"
     "sigma are the estimate after each step (NaN where the headings\n"
     "cancel out). A gated update is recorded (status -5) and the run\n"
     "goes on; any other failure raises with exc.step = k and puts the\n"
     "particles and the generator back as they were."},
    {"resample", PF3_resample, METH_NOARGS,
     "resample($self, /)\n--\n\n"
     "Low-variance resampling (Table 4.4), in place; the weights become\n"
     "1/n. Undefined when the weights' total is not positive."},
    {"__getstate__", PF3_getstate, METH_NOARGS,
     "__getstate__($self, /)\n--\n\nThe particles and the generator, every "
     "bit, as pickle and copy keep them."},
    {"__setstate__", PF3_setstate, METH_O,
     "__setstate__($self, state, /)\n--\n\nRestores __getstate__'s "
     "particles and generator (checked first)."},
    {"reset", (PyCFunction)(void (*)(void))Filter_reset,
     METH_VARARGS | METH_KEYWORDS,
     "reset($self, /, mu, sigma, n, seed=0)\n--\n\n"
     "New particles drawn as the constructor draws them; raises as it\n"
     "does, the filter unchanged then."},
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef PF3_getset[] = {
    {"mu", PF3_estimate, NULL,
     "the particles' weighted mean (x, y, theta), the heading averaged on\n"
     "the circle (a summary: a multimodal belief's mean may lie where no\n"
     "particle is); Undefined when the headings cancel out",
     NULL},
    {"sigma", PF3_estimate, NULL,
     "the particles' weighted covariance (3, 3), heading residuals wrapped",
     (void *)1},
    {"particles", PF3_get, NULL, "the particles' states, an (n, 3) copy",
     (void *)0},
    {"weights", PF3_get, NULL, "the particles' weights, an (n,) copy (sum 1)",
     (void *)1},
    {"n", PF3_get, NULL, "particles", (void *)2},
    {"loglik", PF3_get, NULL,
     "log sum_k w_k N(z; h(x_k), Q) of the last accepted update, the prior\n"
     "weights w_k normalised: the particle filter's estimate of log p(z)\n"
     "(in double from the dry run's h; nan before any)",
     (void *)4},
    {"neff", PF3_get, NULL, "effective sample size 1 / sum (w_k / W)^2, 1..n",
     (void *)3},
    {NULL, NULL, NULL, NULL, NULL},
};

// ---- KF and EKF: n states -------------------------------------------------

typedef struct {
    PyObject_HEAD gf_kf_pmodel pm;
    gf_real A[NMAX * NMAX], B[NMAX * NMAX], R[NMAX * NMAX], c[NMAX];
    PyObject *weakrefs; // weakref support
} KFModelObj;

typedef struct {
    PyObject_HEAD gf_kf_pmeas pq;
    gf_real C[NMAX * NMAX], Q[NMAX * NMAX], c[NMAX];
    PyObject *weakrefs; // weakref support
} KFMeasObj;

typedef struct {
    CallbackObj cb;
    gf_ekf_pmotion pm;
    gf_real R[NMAX * NMAX];
    PyObject *weakrefs; // weakref support
} EKFMotionObj;

typedef struct {
    CallbackObj cb;
    gf_ekf_pmeas pq;
    gf_real Q[NMAX * NMAX];
    PyObject *weakrefs; // weakref support
} EKFMeasObj;

// KF and EKF share it: the belief and the workspace its steps use (its
// own, so that a callback may step another filter).
typedef struct {
    FilterObj f;
    gf_kf kf;
    gf_kf_work work;
    PyObject *weakrefs; // weakref support
} KFObj;

typedef KFObj EKFObj;

static PyTypeObject *KFModel_Type, *KFMeas_Type, *KF_Type;
static PyTypeObject *EKFMotion_Type, *EKFMeas_Type, *EKF_Type;

// An n x n (or m x m) square matrix's size, 1..NMAX.
static int square_size(PyObject *obj, const char *name, npy_intp *n)
{
    npy_intp r, c;
    char got[GOT_LEN];
    if (shape_of(obj, name, 1, &r, &c, got) < 0) {
        return -1;
    }
    if (r != c || r < 1 || r > NMAX) {
        bad_arg("%s must have shape (n, n), n = 1..%d, got %s", name, NMAX,
                got);
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
    char got[GOT_LEN];
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
        if (shape_of(B, "KFModel: B", 0, &br, &nu, got) < 0) {
            return -1;
        }
        if (br != n || nu < 1 || nu > NMAX) {
            bad_arg("KFModel: B must have shape (%ld, nu), nu = 1..%d, got %s",
                    (long)n, NMAX, got);
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
    gf_kf_work *w = new_work();
    return w ? prepared(gf_kf_prepare_model(&self->pm, (unsigned)n, &m, w), w,
                        "KFModel")
             : -1;
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
    char got[GOT_LEN];
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|OO:KFMeas", names, &C, &Q,
                                     &c, &gate)) {
        return -1;
    }
    if (shape_of(C, "KFMeas: C", 1, &m, &n, got) < 0) {
        return -1;
    }
    if (n < 1 || n > NMAX || m < 1 || m > n) {
        bad_arg("KFMeas: C must have shape (m, n), 1 <= m <= n <= %d, got %s",
                NMAX, got);
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
    gf_kf_work *w = new_work();
    return w ? prepared(gf_kf_prepare_meas(&self->pq, (unsigned)n, &me, w), w,
                        "KFMeas")
             : -1;
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
    CallbackObj *cb = (CallbackObj *)ctx;
    (void)u;
    return call_model(cb->fn, 1, cb->cur_u, mu, n, n, mu_bar, G, "EKF");
}

// The Python measurement h(mu_bar) -> (z_hat, H) behind gf_ekf's callback.
static gf_status ekf_h_py(void *ctx, unsigned n, unsigned m,
                          const gf_real *mu_bar, gf_real *z_hat, gf_real *H)
{
    CallbackObj *cb = (CallbackObj *)ctx;
    return call_model(cb->fn, 0, NULL, mu_bar, n, m, z_hat, H, "EKF");
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
    PyObject *cap;
    const CFunction *cf;
    if (check_callable(g, "EKFMotion", "g") < 0 ||
        square_size(R, "EKFMotion: R", &n) < 0 ||
        c_function_of(g, 1, "EKFMotion", "g", &cap, &cf) < 0) {
        return -1;
    }
    if (cf && cf->n != (unsigned)n) {
        bad_arg("EKFMotion: g's C function %s is for %u states, R is %ld x %ld",
                cf->name, cf->n, (long)n, (long)n);
        Py_DECREF(cap);
        return -1;
    }
    if (read_real(R, "EKFMotion: R", n, n, self->R) < 0) {
        Py_XDECREF(cap);
        return -1;
    }
    mo.g = cf ? cf->g : ekf_g_py;
    mo.ctx = cf ? cf->ctx : self;
    mo.R = self->R;
    gf_kf_work *w = new_work();
    if (!w || prepared(gf_ekf_prepare_motion(&self->pm, (unsigned)n, &mo, w), w,
                       "EKFMotion") < 0) {
        Py_XDECREF(cap);
        return -1;
    }
    set_fn(&self->cb, g);
    set_c_function(&self->cb, cap, cf);
    return 0;
}

static int EKFMeas_init(PyObject *self_, PyObject *args, PyObject *kw)
{
    static char *names[] = {"h", "Q", "n", "angle_mask", "gate", NULL};
    EKFMeasObj *self = (EKFMeasObj *)self_;
    PyObject *h, *Q, *n_o, *mask = NULL, *gate = NULL;
    unsigned n, angle_mask = 0;
    gf_ekf_meas me;
    npy_intp m;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OOO|OO:EKFMeas", names, &h, &Q,
                                     &n_o, &mask, &gate) ||
        read_unsigned(n_o, "EKFMeas: n", &n) < 0 ||
        read_unsigned(mask, "EKFMeas: angle_mask", &angle_mask) < 0) {
        return -1;
    }
    PyObject *cap;
    const CFunction *cf;
    if (check_callable(h, "EKFMeas", "h") < 0 ||
        square_size(Q, "EKFMeas: Q", &m) < 0 ||
        c_function_of(h, 0, "EKFMeas", "h", &cap, &cf) < 0) {
        return -1;
    }
    if (cf && (cf->n != n || cf->k != (unsigned)m)) {
        if (cf->n != n) {
            bad_arg("EKFMeas: h's C function %s is for %u states, n is %u",
                    cf->name, cf->n, n);
        } else {
            bad_arg("EKFMeas: h's C function %s measures %u quantities, Q is "
                    "%ld x %ld",
                    cf->name, cf->k, (long)m, (long)m);
        }
        Py_DECREF(cap);
        return -1;
    }
    if (read_real(Q, "EKFMeas: Q", m, m, self->Q) < 0 ||
        read_gate(gate, "EKFMeas", &me.gate) < 0) {
        Py_XDECREF(cap);
        return -1;
    }
    me.m = (unsigned)m;
    me.h = cf ? cf->h : ekf_h_py;
    me.ctx = cf ? cf->ctx : self;
    me.Q = self->Q;
    me.angle_mask = angle_mask;
    gf_kf_work *w = new_work();
    if (!w ||
        prepared(gf_ekf_prepare_meas(&self->pq, n, &me, w), w, "EKFMeas") < 0) {
        Py_XDECREF(cap);
        return -1;
    }
    set_fn(&self->cb, h);
    set_c_function(&self->cb, cap, cf);
    return 0;
}

static PyObject *EKFMotion_get(PyObject *self_, void *which)
{
    EKFMotionObj *self = (EKFMotionObj *)self_;
    if (which) {
        return PyLong_FromUnsignedLong(self->pm.n);
    }
    return new_array(self->pm.n, self->pm.n, self->R);
}

static PyObject *EKFMeas_get(PyObject *self_, void *which)
{
    EKFMeasObj *self = (EKFMeasObj *)self_;
    const gf_ekf_meas *me = &self->pq.meas;
    switch ((int)(size_t)which) {
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
    {"g", Callback_fn, NULL, "the motion g(mu, u) -> (mu_bar, G)", NULL},
    {"R", EKFMotion_get, NULL, "process noise covariance (n, n)", NULL},
    {"n", EKFMotion_get, NULL, "states", (void *)1},
    {NULL, NULL, NULL, NULL, NULL},
};

static PyGetSetDef EKFMeas_getset[] = {
    {"h", Callback_fn, NULL, "the measurement h(mu_bar) -> (z_hat, H)", NULL},
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
    char name[64], got[GOT_LEN];
    PyOS_snprintf(name, sizeof name, "%s: mu", who);
    if (shape_of(mu, name, 0, &n, &r, got) < 0) {
        return -1;
    }
    if (r != 1 || n < 1 || n > NMAX) {
        bad_arg("%s: mu must have shape (n,), n = 1..%d, got %s", who, NMAX,
                got);
        return -1;
    }
    if (read_real(mu, name, 0, n, m) < 0) {
        return -1;
    }
    PyOS_snprintf(name, sizeof name, "%s: sigma", who);
    if (read_real(sigma, name, n, n, s) < 0 ||
        check_idle(&self->f, reinit_back, who) < 0) {
        return -1;
    }
    gf_status st =
        ekf ? gf_ekf_init(&self->kf, (unsigned)n, m, s, angles, &self->work)
            : gf_kf_init(&self->kf, (unsigned)n, m, s, &self->work);
    if (check(st, who) < 0) {
        return -1;
    }
    self->f.has_last = 0;
    recs_clear(&self->f, sizeof(gf_kf)); // n may have changed
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
    PyObject *mu, *sigma, *angles_o = NULL;
    unsigned angles = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|O:EKF", names, &mu, &sigma,
                                     &angles_o) ||
        read_unsigned(angles_o, "EKF: angles", &angles) < 0) {
        return -1;
    }
    return KF_init_common((KFObj *)self_, mu, sigma, angles, 1, "EKF");
}

// KF's and EKF's steps for the shared entries (Family).
static unsigned kf_states(PyObject *f)
{
    return ((KFObj *)f)->kf.n;
}

// No model: no u.
static void kf_model_size(PyObject *model, unsigned *n, npy_intp *nu,
                          int *python_g)
{
    const gf_kf_pmodel *pm = model ? &((KFModelObj *)model)->pm : NULL;
    *n = pm ? pm->n : 0;
    *nu = pm ? pm->model.nu : 0;
    *python_g = 0;
}

static void kf_meas_size(PyObject *meas, unsigned *n, npy_intp *m)
{
    *n = ((KFMeasObj *)meas)->pq.n;
    *m = ((KFMeasObj *)meas)->pq.meas.m;
}

static gf_status kf_predict(PyObject *f, PyObject *model, const gf_real *u,
                            PyObject *u_obj)
{
    KFObj *self = (KFObj *)f;
    (void)u_obj;
    return gf_kf_predict_prepared(&self->kf, &((KFModelObj *)model)->pm, u,
                                  &self->work);
}

// The parts of the belief src an n-state belief uses (n, angles, the
// mean's n entries, the factors' n (n + 1) / 2, the order) into dst, a
// record's prior: a copy of what the filter has, not of NMAX states. The
// rest of dst stays zero (as the library keeps a belief's), the records
// being cleared whenever n may change (init, __setstate__).
static void kf_prior_copy(gf_kf *dst, const gf_kf *src)
{
    const unsigned n = src->n;
    dst->n = n;
    dst->angles = src->angles;
    memcpy(dst->mu, src->mu, n * sizeof(gf_real));
    memcpy(dst->ud, src->ud, GF_KF_TRI(n) * sizeof(gf_real));
    memcpy(dst->perm, src->perm, sizeof dst->perm);
}

static gf_status kf_update(PyObject *f, PyObject *meas, const gf_real *z,
                           gf_kf_innovation *info, UpdateRec *rec)
{
    KFObj *self = (KFObj *)f;
    const gf_kf_pmeas *pq = &((KFMeasObj *)meas)->pq;
    kf_prior_copy(rec->prior.kf, &self->kf);
    gf_status st = gf_kf_update_prepared(&self->kf, pq, z, info, &self->work);
    if (st == GF_OK) {
        rec->m = pq->meas.m;
        rec->n = pq->n;
        memcpy(rec->H, pq->meas.C, (size_t)rec->m * rec->n * sizeof(gf_real));
        memcpy(rec->Q, pq->meas.Q, (size_t)rec->m * rec->m * sizeof(gf_real));
    }
    return st;
}

static void kf_record(PyObject *f, gf_real *mu, gf_real *sigma)
{
    const gf_kf *kf = &((KFObj *)f)->kf;
    memcpy(mu, kf->mu, kf->n * sizeof(gf_real));
    gf_kf_cov(kf, sigma);
}

// g's u as given to a Python g; a C g's (a capsule's) has its entries.
static void ekf_model_size(PyObject *model, unsigned *n, npy_intp *nu,
                           int *python_g)
{
    const CallbackObj *cb = model ? &((EKFMotionObj *)model)->cb : NULL;
    const CFunction *cf = cb ? cb->cfn : NULL;
    *n = model ? ((EKFMotionObj *)model)->pm.n : 0;
    *nu = cf ? (npy_intp)cf->k : 0;
    *python_g = model && !cf;
}

static void ekf_meas_size(PyObject *meas, unsigned *n, npy_intp *m)
{
    *n = ((EKFMeasObj *)meas)->pq.n;
    *m = ((EKFMeasObj *)meas)->pq.meas.m;
}

static gf_status ekf_predict(PyObject *f, PyObject *model, const gf_real *u,
                             PyObject *u_obj)
{
    KFObj *self = (KFObj *)f;
    EKFMotionObj *mo = (EKFMotionObj *)model;
    PyObject *prev_u = mo->cb.cur_u;
    mo->cb.cur_u = u_obj;
    gf_status st = gf_ekf_predict_prepared(&self->kf, &mo->pm, u, &self->work);
    mo->cb.cur_u = prev_u;
    return st;
}

// EKF's h as an update calls it, its H kept in rec, as EKF3's.
typedef struct {
    gf_ekf_meas_fn h;
    void *ctx;
    UpdateRec *rec;
} EkfKeptH;

static gf_status ekf_h_kept(void *ctx, unsigned n, unsigned m,
                            const gf_real *mu_bar, gf_real *z_hat, gf_real *H)
{
    const EkfKeptH *k = (const EkfKeptH *)ctx;
    gf_status st = k->h(k->ctx, n, m, mu_bar, z_hat, H);
    if (st == GF_OK) {
        memcpy(k->rec->H, H, (size_t)m * n * sizeof(gf_real));
    }
    return st;
}

static gf_status ekf_update(PyObject *f, PyObject *meas, const gf_real *z,
                            gf_kf_innovation *info, UpdateRec *rec)
{
    KFObj *self = (KFObj *)f;
    gf_ekf_pmeas pq = ((EKFMeasObj *)meas)->pq;
    EkfKeptH kept = {pq.meas.h, pq.meas.ctx, rec};
    pq.meas.h = ekf_h_kept;
    pq.meas.ctx = &kept;
    kf_prior_copy(rec->prior.kf, &self->kf);
    gf_status st = gf_ekf_update_prepared(&self->kf, &pq, z, info, &self->work);
    if (st == GF_OK) {
        rec->m = pq.meas.m;
        rec->n = pq.n;
        memcpy(rec->Q, pq.meas.Q, (size_t)rec->m * rec->m * sizeof(gf_real));
    }
    return st;
}

static const Family kf_family = {
    "KF",
    "KF.predict",
    "KF.predict: u",
    "KF.update",
    "KF.update: z",
    "KF.run",
    &KFModel_Type,
    &KFMeas_Type,
    0,
    1,
    "(N, nu)",
    offsetof(KFObj, kf),
    sizeof(gf_kf),
    kf_states,
    kf_model_size,
    kf_meas_size,
    kf_predict,
    kf_update,
    kf_record,
    NULL,
};

// An EKFMeas's h is Python's to call unless it is a C function (a
// capsule's).
static int ekf_meas_python(PyObject *meas)
{
    return ((EKFMeasObj *)meas)->cb.cfn == NULL;
}

static const Family ekf_family = {
    "EKF",
    "EKF.predict",
    "EKF.predict: u",
    "EKF.update",
    "EKF.update: z",
    "EKF.run",
    &EKFMotion_Type,
    &EKFMeas_Type,
    1,
    1,
    "(N, k)",
    offsetof(KFObj, kf),
    sizeof(gf_kf),
    kf_states,
    ekf_model_size,
    ekf_meas_size,
    ekf_predict,
    ekf_update,
    kf_record,
    ekf_meas_python,
};

// "KF.name" or "EKF.name" (self an EKF, or a subclass of it), for
// messages.
static const char *kf_who(PyObject *self, const char *kf, const char *ekf)
{
    return PyObject_TypeCheck(self, EKF_Type) ? ekf : kf;
}

// The setter of KF's and EKF's sigma: gf_kf_init (gf_ekf_init, with the
// filter's angles) into a copy of the belief, as KF2's.
static int KF_set_sigma(PyObject *self_, PyObject *value, void *unused)
{
    KFObj *self = (KFObj *)self_;
    const int ekf = PyObject_TypeCheck(self_, EKF_Type);
    const char *who = ekf ? "EKF.sigma" : "KF.sigma";
    const unsigned n = self->kf.n;
    gf_real m[NMAX], s[NMAX * NMAX];
    gf_kf fresh;
    (void)unused;
    if (set_sigma_value(value, who) < 0) {
        return -1;
    }
    if (n < 1u || n > NMAX) {
        bad_arg("%s: the filter was never initialised", who);
        return -1;
    }
    if (read_real(value, who, n, n, s) < 0 ||
        check_idle(&self->f, reinit_back, who) < 0) {
        return -1;
    }
    memcpy(&fresh, &self->kf, sizeof fresh);
    memcpy(m, self->kf.mu, n * sizeof(gf_real));
    gf_status st =
        ekf ? gf_ekf_init(&fresh, n, m, s, self->kf.angles, &self->work)
            : gf_kf_init(&fresh, n, m, s, &self->work);
    if (check(st, who) < 0) {
        return -1;
    }
    memcpy(&self->kf, &fresh, sizeof fresh);
    return 0;
}

static PyObject *KF_get(PyObject *self_, void *which)
{
    KFObj *self = (KFObj *)self_;
    switch ((int)(size_t)which) {
    case 0:
        if (check_readable(&self->f, "mu") < 0) {
            return NULL;
        }
        return new_array(self->kf.n, 0, self->kf.mu);
    case 3:
        return PyLong_FromUnsignedLong(self->kf.n);
    default:
        return PyLong_FromUnsignedLong(self->kf.angles);
    }
}

static PyMethodDef KF_methods[] = {
    {"predict", (PyCFunction)(void (*)(void))Filter_predict,
     METH_FASTCALL | METH_KEYWORDS,
     "predict($self, /, model, u=None)\n--\n\n"
     "Prediction: mu_bar = A mu + B u + c,  Sigma_bar = A Sigma A^T + R,\n"
     "on the factors (Thornton's time update). u: model.nu entries, or\n"
     "None for no control. Every failure leaves the belief unchanged."},
    {"update", (PyCFunction)(void (*)(void))Filter_update,
     METH_FASTCALL | METH_KEYWORDS,
     "update($self, /, meas, z)\n--\n\n"
     "Correction with m = meas.m values z:\n"
     "    y = z - c - C mu_bar,  S = C Sigma_bar C^T + Q,  K = Sigma_bar C^T "
     "S^-1,\n"
     "    mu = mu_bar + K y,  Sigma = (I - K C) Sigma_bar,  NIS = y^T S^-1 "
     "y\n"
     "(Q whitened, Bierman's scalar updates). Gated carries the\n"
     "innovation and NIS; every failure leaves the belief unchanged."},
    {"run", (PyCFunction)(void (*)(void))Filter_run,
     METH_FASTCALL | METH_KEYWORDS,
     "run($self, /, model=None, meas=None, u=None, z=None, steps=None)\n--\n\n"
     "-> (mu (N, n), sigma (N, n, n), nis (N,), status (N,))\n\n"
     "N steps in one call, as KF2.run: predict(model, u[k]) then\n"
     "update(meas, z[k]) unless z[k] has a NaN; a gated update is recorded\n"
     "and skipped; any other failure raises with exc.step and puts the\n"
     "belief back as it was before the call."},
    {"__getstate__", Filter_getstate, METH_NOARGS,
     "__getstate__($self, /)\n--\n\nThe belief as pickle and copy keep it: "
     "every bit of its factors."},
    {"__setstate__", Filter_setstate, METH_O,
     "__setstate__($self, state, /)\n--\n\nRestores __getstate__'s "
     "belief (checked first)."},
    {"reset", (PyCFunction)(void (*)(void))Filter_reset,
     METH_VARARGS | METH_KEYWORDS,
     "reset($self, /, mu, sigma)\n--\n\nA new belief N(mu, sigma), judged and "
     "factored as the\n"
     "constructor does; raises as it does, the belief unchanged then."},
    {NULL, NULL, 0, NULL},
};

static PyMethodDef EKF_methods[] = {
    {"predict", (PyCFunction)(void (*)(void))Filter_predict,
     METH_FASTCALL | METH_KEYWORDS,
     "predict($self, /, motion, u=None)\n--\n\n"
     "Prediction (Table 3.3, lines 2-3), G = dg/dx at mu:\n"
     "    mu_bar = g(u, mu),  Sigma_bar = G Sigma G^T + R,\n"
     "on the factors; the states in `angles` kept in (-pi, pi]. g gets\n"
     "(mu, u) and returns (mu_bar, G). A callback's exception propagates;\n"
     "every failure leaves the belief unchanged."},
    {"update", (PyCFunction)(void (*)(void))Filter_update,
     METH_FASTCALL | METH_KEYWORDS,
     "update($self, /, meas, z)\n--\n\n"
     "Correction (Table 3.3, lines 4-6), H = dh/dx at mu_bar:\n"
     "    y = z - h(mu_bar),  S = H Sigma_bar H^T + Q,  K = Sigma_bar H^T "
     "S^-1,\n"
     "    mu = mu_bar + K y,  Sigma = (I - K H) Sigma_bar,  NIS = y^T S^-1 "
     "y.\n"
     "h gets mu_bar and returns (z_hat, H). Gated carries the innovation\n"
     "and NIS; every failure leaves the belief unchanged."},
    {"run", (PyCFunction)(void (*)(void))Filter_run,
     METH_FASTCALL | METH_KEYWORDS,
     "run($self, /, motion=None, meas=None, u=None, z=None, steps=None)\n--\n\n"
     "-> (mu (N, n), sigma (N, n, n), nis (N,), status (N,))\n\n"
     "N steps in one call, as EKF3.run: g gets u[k] as a fresh (k,)\n"
     "array (None without u); update unless z[k] has a NaN; a gated\n"
     "update is recorded; any other failure raises with exc.step and puts\n"
     "the belief back as it was before the call."},
    {"__getstate__", Filter_getstate, METH_NOARGS,
     "__getstate__($self, /)\n--\n\nThe belief as pickle and copy keep it: "
     "every bit of its factors."},
    {"__setstate__", Filter_setstate, METH_O,
     "__setstate__($self, state, /)\n--\n\nRestores __getstate__'s "
     "belief (checked first)."},
    {"reset", (PyCFunction)(void (*)(void))Filter_reset,
     METH_VARARGS | METH_KEYWORDS,
     "reset($self, /, mu, sigma, angles=0)\n--\n\nA new belief N(mu, sigma), "
     "judged and factored as the\n"
     "constructor does; raises as it does, the belief unchanged then."},
    {NULL, NULL, 0, NULL},
};

static int KF_set_mu(PyObject *self_, PyObject *value, void *unused)
{
    KFObj *self = (KFObj *)self_;
    (void)unused;
    return set_mean(&self->f, self->kf.mu, self->kf.n, self->kf.angles, value,
                    kf_who(self_, "KF.mu", "EKF.mu"));
}

static PyGetSetDef KF_getset[] = {
    {"mu", KF_get, KF_set_mu,
     "the mean, an (n,) copy; set: a new mean (the angle states wrapped),\n"
     "the covariance kept",
     (void *)0},
    {"sigma", Filter_sigma, KF_set_sigma,
     "the covariance, an (n, n) array: Sigma = P U D U^T P^T, exactly\n"
     "symmetric; set: factored with the mean as the constructor does",
     NULL},
    {"nis", Filter_nis, NULL,
     "NIS = y^T S^-1 y of the last accepted update (nan before any)", NULL},
    {"innovation", Filter_innovation, NULL,
     "the innovation y of the last accepted update (None before any)", NULL},
    {"S", Filter_S, NULL,
     "S = H Sigma_bar H^T + Q of the last accepted update, (m, m), computed\n"
     "in double from the prior's covariance when read (None before any)",
     (void *)REC_KF},
    {"K", Filter_K, NULL,
     "the gain K = Sigma_bar H^T S^-1 of the last accepted update, (n, m)\n"
     "(None before any)",
     (void *)REC_KF},
    {"loglik", Filter_loglik, NULL,
     "log N(y; 0, S) = -(NIS + log det S + m log 2 pi) / 2 of the last\n"
     "accepted update (nan before any)",
     (void *)REC_KF},
    {"n", KF_get, NULL, "states", (void *)3},
    {"angles", KF_get, NULL, "bit i: state i is an angle (EKF)", (void *)4},
    {NULL, NULL, NULL, NULL, NULL},
};

// ---- Sigma's 2x2 helpers (cov2.h) -----------------------------------------

static PyObject *py_ellipse(PyObject *mod, PyObject *args, PyObject *kw)
{
    static char *names[] = {"sigma", "p", NULL};
    PyObject *s_o, *p_o = NULL;
    double p = 0.68;
    gf_mat2 s;
    gf_ellipse e;
    (void)mod;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|O:ellipse", names, &s_o,
                                     &p_o) ||
        read_real(s_o, "ellipse: sigma", 2, 2, &s.m[0][0]) < 0 ||
        (p_o && read_number(p_o, "ellipse: p", &p) < 0)) {
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
    PyObject *s_o, *i_o, *j_o;
    unsigned i, j;
    gf_mat3 s;
    gf_mat2 out;
    (void)mod;
    if (!PyArg_ParseTuple(args, "OOO:marginal", &s_o, &i_o, &j_o) ||
        read_real(s_o, "marginal: sigma", 3, 3, &s.m[0][0]) < 0 ||
        read_unsigned(i_o, "marginal: i", &i) < 0 ||
        read_unsigned(j_o, "marginal: j", &j) < 0) {
        return NULL;
    }
    gf_status st = gf_cov2_marginal(&s, i, j, &out);
    if (st != GF_OK) {
        return raise_status(st, "marginal", NULL, NULL, 0, 0);
    }
    return new_array(2, 2, &out.m[0][0]);
}

static PyMethodDef module_methods[] = {
    {"_c_function", py_c_function, METH_VARARGS,
     "_c_function(kind, name, address, ctx, n, k, owner, /)\n--\n\n"
     "A capsule of a gf_ekf motion ('motion') or measurement ('meas') C\n"
     "function at address, its ctx an address, for n states and k (u's\n"
     "entries, or m), keeping owner alive. Given to EKFMotion or EKFMeas\n"
     "as its callable's gf_capsule, the C function is called directly\n"
     "(gaussfilt.codegen.build makes them)."},
    {"ellipse", (PyCFunction)(void (*)(void))py_ellipse,
     METH_VARARGS | METH_KEYWORDS,
     "ellipse(sigma, p=0.68)\n--\n\n-> (a, b, angle): "
     "The p-probability ellipse of N(mu, sigma), sigma 2x2 PSD:\n"
     "semi-axes a >= b = sqrt(k2 lambda_i), k2 = -2 ln(1 - p), lambda_i\n"
     "sigma's eigenvalues; angle of the a axis from x (gf_cov2_ellipse)."},
    {"correlation", py_correlation, METH_O,
     "correlation(sigma, /)\n--\n\nrho = sigma_xy / sqrt(sigma_xx sigma_yy)\n\n"
     "Undefined (a zero variance) raises Undefined (gf_cov2_correlation)."},
    {"marginal", py_marginal, METH_VARARGS,
     "marginal(sigma, i, j, /)\n--\n\nThe 2x2 block of states i and j of a 3x3 "
     "sigma\n(gf_cov2_marginal)."},
    {NULL, NULL, 0, NULL},
};

// ---- types and module -----------------------------------------------------

// The repr of every class here: its name (with the precision; a
// subclass's own name, then the class it derives from), n and m where it
// has them, and a belief's mean:
//   <gaussfilt.float32.KF2 n=2 mu=[4.0244 1.2195]>
//   <gaussfilt.float64.KFMeas n=4 m=2>
//   <tracks.Track gaussfilt.float64.KF2 n=2 mu=[0. 1.]>
// A belief whose run() is in progress in another thread shows no mean.
static PyObject *Obj_repr(PyObject *self)
{
    static const char *const sizes[] = {"n", "m"};
    PyObject *parts = PyList_New(0), *out = NULL, *mu = NULL, *head;
    PyTypeObject *base = package_class(Py_TYPE(self));
    char name[96];
    if (!parts) {
        return NULL;
    }
    class_name((PyObject *)(base ? base : Py_TYPE(self)), name, sizeof name);
    if (!base || base == Py_TYPE(self)) {
        head = PyUnicode_FromFormat("<%s", name);
    } else {
        PyObject *cls = (PyObject *)Py_TYPE(self);
        PyObject *mod = PyObject_GetAttrString(cls, "__module__");
        PyObject *qual =
            mod ? PyObject_GetAttrString(cls, "__qualname__") : NULL;
        head = qual ? PyUnicode_FromFormat("<%S.%S %s", mod, qual, name) : NULL;
        Py_XDECREF(mod);
        Py_XDECREF(qual);
    }
    int ok = head && PyList_Append(parts, head) == 0;
    Py_XDECREF(head);
    const int belief = PyObject_TypeCheck(self, KF2_Type) ||
                       PyObject_TypeCheck(self, EKF3_Type) ||
                       PyObject_TypeCheck(self, UKF3_Type) ||
                       PyObject_TypeCheck(self, PF3_Type) ||
                       PyObject_TypeCheck(self, KF_Type) ||
                       PyObject_TypeCheck(self, EKF_Type);
    const int running = belief && ((FilterObj *)self)->busy == BUSY_NOGIL;
    if (ok && running) {
        PyObject *t = PyUnicode_FromString("(a run in progress)");
        ok = t && PyList_Append(parts, t) == 0;
        Py_XDECREF(t);
    }
    // PF3: its particles' count, then its estimate when it has one (none
    // never initialised, Undefined when the headings cancel out)
    const int pf3 = PyObject_TypeCheck(self, PF3_Type);
    if (ok && pf3 && !running) {
        const gf_pf3 *pf = &((PF3Obj *)self)->pf;
        PyObject *t = PyUnicode_FromFormat("particles=%u", pf->p ? pf->n : 0u);
        ok = t && PyList_Append(parts, t) == 0;
        Py_XDECREF(t);
    }
    mu = ok && belief && !running ? PyObject_GetAttrString(self, "mu") : NULL;
    if (!mu && PyErr_Occurred()) {
        if (pf3 && PyErr_ExceptionMatches(PyExc_ValueError)) {
            PyErr_Clear();
        } else {
            ok = 0;
        }
    }
    if (mu && !pf3) {
        PyObject *t = PyUnicode_FromFormat(
            "n=%zd", PyArray_Check(mu) ? PyArray_SIZE((PyArrayObject *)mu)
                                       : (Py_ssize_t)0);
        ok = t && PyList_Append(parts, t) == 0;
        Py_XDECREF(t);
    }
    for (int i = 0; ok && !mu && !belief && i < 2; i++) {
        if (!PyObject_HasAttrString(self, sizes[i])) {
            continue;
        }
        PyObject *v = PyObject_GetAttrString(self, sizes[i]);
        PyObject *t = v ? PyUnicode_FromFormat("%s=%S", sizes[i], v) : NULL;
        ok = t && PyList_Append(parts, t) == 0;
        Py_XDECREF(v);
        Py_XDECREF(t);
    }
    if (ok && mu) {
        PyObject *t = PyUnicode_FromFormat("mu=%S", mu);
        ok = t && PyList_Append(parts, t) == 0;
        Py_XDECREF(t);
    }
    if (ok) {
        PyObject *sep = PyUnicode_FromString(" ");
        PyObject *body = sep ? PyUnicode_Join(sep, parts) : NULL;
        out = body ? PyUnicode_FromFormat("%U>", body) : NULL;
        Py_XDECREF(body);
        Py_XDECREF(sep);
    }
    Py_XDECREF(mu);
    Py_DECREF(parts);
    return out;
}

// ---- models: pickle and copy ---------------------------------------------

// A model class, its constructor and the arguments it is rebuilt from (its
// getters of the same names).
typedef struct {
    PyTypeObject **type;
    initproc init;
    const char *names[5];
} ModelKind;

static const ModelKind model_kinds[] = {
    {&KF2Model_Type, KF2Model_init, {"A", "R", "B", "c", NULL}},
    {&KF2Meas_Type, KF2Meas_init, {"C", "Q", "c", "gate", NULL}},
    {&EKF3Motion_Type, EKF3Motion_init, {"g", "R", NULL}},
    {&EKF3Meas_Type, EKF3Meas_init, {"h", "Q", "angle_mask", "gate", NULL}},
    {&KFModel_Type, KFModel_init, {"A", "R", "B", "c", NULL}},
    {&KFMeas_Type, KFMeas_init, {"C", "Q", "c", "gate", NULL}},
    {&EKFMotion_Type, EKFMotion_init, {"g", "R", NULL}},
    {&EKFMeas_Type, EKFMeas_init, {"h", "Q", "n", "angle_mask", "gate"}},
};

// The kind of the model self (of one of the classes or a subclass).
static const ModelKind *model_kind(PyObject *self)
{
    for (size_t i = 0; i < sizeof model_kinds / sizeof model_kinds[0]; i++) {
        if (PyObject_TypeCheck(self, *model_kinds[i].type)) {
            return &model_kinds[i];
        }
    }
    return NULL;
}

// __reduce__ of a model: (copyreg.__newobj__, (type,), (its arguments as
// the constructor takes them, its instance dictionary or None)). The
// object is made without calling a subclass's __init__, then __setstate__
// runs the model's own constructor on the arguments, which checks and
// factors them again (to the same bits).
static PyObject *Model_reduce(PyObject *self, PyObject *unused)
{
    const ModelKind *k = model_kind(self);
    PyObject *copyreg, *newobj = NULL, *args = NULL, *d = NULL, *out = NULL;
    (void)unused;
    if (!k) {
        return PyErr_Format(PyExc_TypeError, "not a gaussfilt model");
    }
    int n = 0;
    while (n < 5 && k->names[n]) {
        n++;
    }
    args = PyTuple_New(n);
    for (int i = 0; args && i < n; i++) {
        PyObject *v = PyObject_GetAttrString(self, k->names[i]);
        if (!v) {
            Py_CLEAR(args);
            break;
        }
        PyTuple_SetItem(args, i, v);
    }
    if (!args) {
        return NULL;
    }
    d = instance_dict(self);
    if (!d && PyErr_Occurred()) {
        Py_DECREF(args);
        return NULL;
    }
    copyreg = PyImport_ImportModule("copyreg");
    newobj = copyreg ? PyObject_GetAttrString(copyreg, "__newobj__") : NULL;
    Py_XDECREF(copyreg);
    if (newobj) {
        out = Py_BuildValue("(O(O)(OO))", newobj, (PyObject *)Py_TYPE(self),
                            args, d ? d : Py_None);
    }
    Py_XDECREF(newobj);
    Py_XDECREF(d);
    Py_DECREF(args);
    return out;
}

// __setstate__ of a model: __reduce__'s (arguments, dictionary or None),
// the arguments given to the model's own constructor (which refuses what
// it refuses, the model unchanged then).
static PyObject *Model_setstate(PyObject *self, PyObject *st)
{
    const ModelKind *k = model_kind(self);
    char tn[96];
    const char *name =
        k ? strrchr(class_name((PyObject *)*k->type, tn, sizeof tn), '.') + 1
          : "model";
    PyObject *args, *d;
    if (!k || !PyTuple_Check(st) || PyTuple_Size(st) != 2 ||
        !PyTuple_Check(args = PyTuple_GetItem(st, 0)) ||
        ((d = PyTuple_GetItem(st, 1)) != Py_None &&
         (!PyDict_Check(d) || !has_dict(self)))) {
        return bad_arg("%s.__setstate__: not a state of this package", name);
    }
    if (k->init(self, args, NULL) < 0 || update_instance_dict(self, d) < 0) {
        return NULL;
    }
    Py_RETURN_NONE;
}

static PyMethodDef Model_methods[] = {
    {"__reduce__", Model_reduce, METH_NOARGS,
     "__reduce__($self, /)\n--\n\nFor pickle and copy: the model rebuilt "
     "from its arguments."},
    {"__setstate__", Model_setstate, METH_O,
     "__setstate__($self, state, /)\n--\n\nThe model made again from "
     "__reduce__'s state."},
    {NULL, NULL, 0, NULL},
};

static const Family *family_of(PyObject *self)
{
    PyTypeObject *t = Py_TYPE(self);
    if (t != KF2_Type && t != EKF3_Type && t != UKF3_Type && t != EKF_Type &&
        t != KF_Type) {
        t = package_class(t); // a subclass in Python
    }
    return t == KF2_Type    ? &kf2_family
           : t == EKF3_Type ? &ekf3_family
           : t == UKF3_Type ? &ukf3_family
           : t == EKF_Type  ? &ekf_family
                            : &kf_family; // the only other with these entries
}

// The classes are heap types made at import from these specs
// (PyType_FromModuleAndSpec): the stable ABI has no static type objects.
// X_Type points to class X once the module is made. Each class keeps its
// objects' weak references at the offset its __weaklistoffset__ gives.
#define GF_SPEC(T, name, flags, ...)                                           \
    static PyMemberDef T##_members[] = {                                       \
        {"__weaklistoffset__", T_PYSSIZET, offsetof(T##Obj, weakrefs),         \
         READONLY, NULL},                                                      \
        {NULL, 0, 0, 0, NULL},                                                 \
    };                                                                         \
    static PyType_Slot T##_slots[] = {                                         \
        {Py_tp_new, (void *)PyType_GenericNew},                                \
        {Py_tp_repr, (void *)Obj_repr},                                        \
        {Py_tp_members, T##_members},                                          \
        __VA_ARGS__,                                                           \
        {0, NULL},                                                             \
    };                                                                         \
    static PyType_Spec T##_spec = {                                            \
        "gaussfilt." GF_PREC_NAME "." name, sizeof(T##Obj), 0,                 \
        Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE | (flags), T##_slots}

#define GF_TYPE(T, name, doc, init, methods, getset)                           \
    GF_SPEC(T, name, 0, {Py_tp_doc, (void *)(doc)},                            \
            {Py_tp_init, (void *)(init)}, {Py_tp_methods, methods},            \
            {Py_tp_getset, getset}, {Py_tp_dealloc, (void *)Obj_dealloc})

#define GF_GC_TYPE(T, name, doc, init, getset)                                 \
    GF_SPEC(T, name, Py_TPFLAGS_HAVE_GC, {Py_tp_doc, (void *)(doc)},           \
            {Py_tp_init, (void *)(init)}, {Py_tp_methods, Model_methods},      \
            {Py_tp_getset, getset},                                            \
            {Py_tp_traverse, (void *)Callback_traverse},                       \
            {Py_tp_clear, (void *)Callback_clear},                             \
            {Py_tp_dealloc, (void *)Callback_dealloc})

GF_TYPE(KF2Model, "KF2Model",
        "KF2Model(A, R, B=None, c=None)\n--\n\n"
        "KF2's motion x_t = A x_{t-1} + B u_t + c + eps, eps ~ N(0, R)\n"
        "(book names: R is the process noise; FilterPy's F and Q). A, R\n"
        "2x2, B (2, 1) or (2, 2) (u of 1 or 2 entries), c (2,). B None: no\n"
        "control (a prediction given u raises BadArgument); c defaults to\n"
        "zero. Checked and factored once\n"
        "(gf_kf2_prepare_model): NonFinite, NotPSD (R) raise here.",
        KF2Model_init, Model_methods, KF2Model_getset);
GF_TYPE(KF2Meas, "KF2Meas",
        "KF2Meas(C, Q, c=None, gate=0.0)\n--\n\n"
        "KF2's measurement z = C x + c + delta, delta ~ N(0, Q) of m = 1 or\n"
        "2 quantities (book names: Q is the measurement noise; FilterPy's H\n"
        "and R). C (m, 2), Q (m, m), c (m,). gate: reject an update whose\n"
        "NIS exceeds it (raises Gated); 0: no gate. Checked and factored\n"
        "once (gf_kf2_prepare_meas).",
        KF2Meas_init, Model_methods, KF2Meas_getset);
GF_TYPE(KF2, "KF2",
        "KF2(mu, sigma)\n--\n\n"
        "The 2-state Kalman filter's belief N(mu, Sigma) (gf_kf2), Sigma\n"
        "kept as its factors U D U^T. sigma 2x2 symmetric PSD (zero is\n"
        "fine). Every step is the C library's; a failed one raises and\n"
        "changes nothing.",
        KF2_init, KF2_methods, KF2_getset);
GF_GC_TYPE(EKF3Motion, "EKF3Motion",
           "EKF3Motion(g, R)\n--\n\n"
           "EKF3's motion x_t = g(u_t, x_{t-1}) + eps, eps ~ N(0, R), R 3x3\n"
           "(book names). g(mu, u) -> (mu_bar (3,), G (3, 3)), G = dg/dx at\n"
           "mu; or the built-in forward_turn (C, no Python in the step).",
           EKF3Motion_init, EKF3Motion_getset);
GF_GC_TYPE(EKF3Meas, "EKF3Meas",
           "EKF3Meas(h, Q, angle_mask=0, gate=0.0)\n--\n\n"
           "EKF3's measurement z = h(x) + delta, delta ~ N(0, Q), Q m x m,\n"
           "m = 1..3. h(mu_bar) -> (z_hat (m,), H (m, 3)); or the built-in\n"
           "meas_x (m = 1) or meas_xy (m = 2). angle_mask bit i: residual i\n"
           "is an angle, wrapped into (-pi, pi].",
           EKF3Meas_init, EKF3Meas_getset);
GF_TYPE(EKF3, "EKF3",
        "EKF3(mu, sigma)\n--\n\n"
        "The EKF's belief over (x, y, theta) (gf_ekf3), the heading kept in\n"
        "(-pi, pi]. sigma 3x3 symmetric PSD.",
        EKF3_init, EKF3_methods, EKF3_getset);
GF_TYPE(UKF3, "UKF3",
        "UKF3(mu, sigma, alpha=1.0, beta=2.0, kappa=0.0)\n--\n\n"
        "The unscented Kalman filter's belief over (x, y, theta) (gf_ukf3,\n"
        "Table 3.4), stepped with EKF3's models: 7 sigma points through g\n"
        "and h, no Jacobians. alpha in [ALPHA_MIN, 1], beta >= 0, kappa >= 0\n"
        "(Julier and Uhlmann's scaling; the defaults put the points at\n"
        "sqrt(3) sigma). sigma 3x3 symmetric PSD.",
        UKF3_init, UKF3_methods, UKF3_getset);
GF_SPEC(PF3, "PF3", 0,
        {Py_tp_doc,
         (void *)"PF3(mu, sigma, n, seed=0)\n--\n\n"
                 "The particle filter over (x, y, theta) (gf_pf3, Tables 4.3 "
                 "and\n4.4), stepped with EKF3's models: n particles drawn "
                 "from N(mu,\nsigma) by the filter's own generator, seeded "
                 "with seed (0 to\n2^32 - 1): the same seed, the same run, "
                 "bit for bit."},
        {Py_tp_init, (void *)PF3_init}, {Py_tp_methods, PF3_methods},
        {Py_tp_getset, PF3_getset}, {Py_tp_dealloc, (void *)PF3_dealloc});
GF_TYPE(KFModel, "KFModel",
        "KFModel(A, R, B=None, c=None)\n--\n\n"
        "gf_kf's motion of n states: x_t = A x_{t-1} + B u_t + c + eps,\n"
        "eps ~ N(0, R). A, R (n, n); B (n, nu) or None; c (n,) or None.",
        KFModel_init, Model_methods, KFModel_getset);
GF_TYPE(KFMeas, "KFMeas",
        "KFMeas(C, Q, c=None, gate=0.0)\n--\n\n"
        "gf_kf's measurement of m quantities: z = C x + c + delta,\n"
        "delta ~ N(0, Q). C (m, n), Q (m, m), c (m,) or None.",
        KFMeas_init, Model_methods, KFMeas_getset);
GF_TYPE(KF, "KF",
        "KF(mu, sigma)\n--\n\n"
        "The linear Kalman filter of n = len(mu) states (gf_kf, n up to\n"
        "GF_KF_NMAX), Sigma kept as P U D U^T P^T.",
        KF_init, KF_methods, KF_getset);
GF_GC_TYPE(EKFMotion, "EKFMotion",
           "EKFMotion(g, R)\n--\n\n"
           "gf_ekf's motion of n states (n from R): g(mu, u) -> (mu_bar (n,),\n"
           "G (n, n)), G = dg/dx at mu; u is predict's u as given. A g\n"
           "carrying a gf_capsule (a model built by gaussfilt.codegen) is\n"
           "called in C, no Python in the step; u then has its entries.",
           EKFMotion_init, EKFMotion_getset);
GF_GC_TYPE(EKFMeas, "EKFMeas",
           "EKFMeas(h, Q, n, angle_mask=0, gate=0.0)\n--\n\n"
           "gf_ekf's measurement of m quantities (m from Q) for n states:\n"
           "h(mu_bar) -> (z_hat (m,), H (m, n)). An h carrying a gf_capsule\n"
           "(gaussfilt.codegen) is called in C, no Python in the step.",
           EKFMeas_init, EKFMeas_getset);
GF_TYPE(EKF, "EKF",
        "EKF(mu, sigma, angles=0)\n--\n\n"
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

// The classes in the order the module adds them, and their specs.
static PyTypeObject **const all_types[] = {
    &Builtin_Type,    &KF2Model_Type, &KF2Meas_Type,   &KF2_Type,
    &EKF3Motion_Type, &EKF3Meas_Type, &EKF3_Type,      &KFModel_Type,
    &KFMeas_Type,     &KF_Type,       &EKFMotion_Type, &EKFMeas_Type,
    &EKF_Type,        &UKF3_Type,     &PF3_Type};
static PyType_Spec *const all_specs[] = {
    &Builtin_spec,    &KF2Model_spec, &KF2Meas_spec,   &KF2_spec,
    &EKF3Motion_spec, &EKF3Meas_spec, &EKF3_spec,      &KFModel_spec,
    &KFMeas_spec,     &KF_spec,       &EKFMotion_spec, &EKFMeas_spec,
    &EKF_spec,        &UKF3_spec,     &PF3_spec};
#define NTYPES (sizeof all_types / sizeof all_types[0])

static PyTypeObject *package_class(PyTypeObject *t)
{
    while (t && (PyType_GetFlags(t) & Py_TPFLAGS_HEAPTYPE)) {
        for (size_t i = 0; i < NTYPES; i++) {
            if (t == *all_types[i]) {
                return t;
            }
        }
        t = (PyTypeObject *)PyType_GetSlot(t, Py_tp_base);
    }
    return NULL;
}

PyMODINIT_FUNC CAT(PyInit_, GF_PY_MODULE)(void)
{
    PyObject *m, *errors;
    PyType_Spec *beliefs[] = {&KF2_spec, &EKF3_spec, &KF_spec, &EKF_spec,
                              &UKF3_spec};
    import_array();
    for (size_t i = 0; i < sizeof beliefs / sizeof beliefs[0]; i++) {
        for (PyType_Slot *s = beliefs[i]->slots; s->slot; s++) {
            if (s->slot == Py_tp_dealloc) {
                s->pfunc = (void *)Filter_dealloc; // their update records
            }
        }
    }
    errors = PyImport_ImportModule("gaussfilt._errors");
    if (!errors) {
        return NULL;
    }
    from_status = PyObject_GetAttrString(errors, "_from_status");
    Py_DECREF(errors);
    if (!from_status) {
        return NULL;
    }
    PyObject *sigma_mod = PyImport_ImportModule("gaussfilt._sigma");
    if (!sigma_mod) {
        return NULL;
    }
    sigma_type =
        (PyTypeObject *)PyObject_GetAttrString(sigma_mod, "SigmaArray");
    Py_DECREF(sigma_mod);
    if (!sigma_type) {
        return NULL;
    }
    m = PyModule_Create(&moddef);
    if (!m) {
        return NULL;
    }
    // Each class is kept by its X_Type for the module's lifetime (the
    // module is never unloaded) and, but for Builtin, by the module.
    for (size_t i = 0; i < NTYPES; i++) {
        PyObject *t = PyType_FromModuleAndSpec(m, all_specs[i], NULL);
        if (!t) {
            goto fail;
        }
        *all_types[i] = (PyTypeObject *)t;
        if (i > 0) {
            const char *dot = strrchr(all_specs[i]->name, '.');
            Py_INCREF(t);
            if (PyModule_AddObject(m, dot + 1, t) < 0) {
                Py_DECREF(t);
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
        PyModule_AddObject(m, "UKF3_ALPHA_MIN",
                           PyFloat_FromDouble((double)GF_UKF3_ALPHA_MIN)) < 0 ||
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
