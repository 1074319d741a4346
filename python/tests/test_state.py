# SPDX-License-Identifier: MIT
"""A filter's state from Python: pickle, copy and deepcopy restore every bit
of a belief (its factors, its last innovation) in both precisions, and the
copy steps on its own; models pickle and copy (built-in models by name,
Python functions as pickle can) and step as the originals do; subclasses
keep their attributes; a state that is not one of this package's, or of
the other precision, is refused with the filter unchanged; the repr shows
class, precision, n and the mean; the mean and sigma are settable (sigma
a property, factored as the constructor does) and reset() judges as the
constructor does, the belief unchanged when any refuses."""
import copy
import pickle

import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

MODS = [float32, float64]


def motion_g(mu, u):  # a module-level Python model: picklable
    return mu + 0.1, np.eye(len(mu))


def meas_h(mu):
    return mu[:1].copy(), np.eye(1, len(mu))


def stepped(gf):
    """One of each belief, stepped so that its factors are off the
    identity and it has a last innovation."""
    kf2 = gf.KF2(mu=[0, 0], sigma=[[2, 0.5], [0.5, 1]])
    car = gf.KF2Model(A=[[1, 1], [0, 1]], R=[[0.25, 0.5], [0.5, 1]])
    for z in (1.0, 2.5, 3.9):
        kf2.predict(car)
        kf2.update(gf.KF2Meas(C=[[1, 0]], Q=[[10]]), z=[z])
    ekf3 = gf.EKF3(mu=[0, 0, 3.0], sigma=np.diag([1, 1, 0.1]))
    ekf3.predict(gf.EKF3Motion(g=gf.forward_turn, R=np.eye(3) * 0.01),
                 u=[1, 0.3])
    ekf3.update(gf.EKF3Meas(h=gf.meas_xy, Q=np.eye(2)), z=[1, 0.2])
    kf = gf.KF(mu=[0, 1, 0, 1], sigma=np.eye(4))
    model = gf.KFModel(A=np.kron(np.eye(2), [[1, 1], [0, 1]]),
                       R=np.eye(4) * 0.1)
    kf.predict(model)
    kf.update(gf.KFMeas(C=[[1, 0, 0, 0], [0, 0, 1, 0]], Q=np.eye(2)),
              z=[0.5, 0.7])
    ekf = gf.EKF(mu=[0, 0, 3.1], sigma=np.eye(3), angles=4)
    ekf.predict(gf.EKFMotion(g=motion_g, R=np.eye(3) * 0.01))
    ekf.update(gf.EKFMeas(h=meas_h, Q=[[1]], n=3), z=[0.3])
    return {"KF2": kf2, "EKF3": ekf3, "KF": kf, "EKF": ekf}


def same(a, b):
    return a.__getstate__() == b.__getstate__()


@pytest.mark.parametrize("gf", MODS)
def test_pickle_and_copy_keep_every_bit(gf):
    for name, f in stepped(gf).items():
        for twin in (pickle.loads(pickle.dumps(f)),
                     pickle.loads(pickle.dumps(f, protocol=2)),
                     copy.copy(f), copy.deepcopy(f)):
            assert type(twin) is type(f) and same(twin, f), name
            assert np.array_equal(twin.mu, f.mu) and twin.nis == f.nis
            assert np.array_equal(twin.sigma, f.sigma)
            assert np.array_equal(twin.innovation, f.innovation)


@pytest.mark.parametrize("gf", MODS)
def test_a_copy_steps_on_its_own_and_as_the_original(gf):
    f = stepped(gf)["KF2"]
    twin = copy.deepcopy(f)
    car = gf.KF2Model(A=[[1, 0.5], [0, 1]], R=np.eye(2) * 0.1)
    before = f.__getstate__()
    twin.predict(car)
    assert f.__getstate__() == before  # the original untouched
    f.predict(car)
    assert same(twin, f)  # the same step, the same bits


@pytest.mark.parametrize("gf", MODS)
def test_models_pickle(gf):
    car = gf.KF2Model(A=[[1, 1], [0, 1]], R=[[0.25, 0.5], [0.5, 1]],
                      c=[0.1, 0])
    meas = gf.KFMeas(C=[[1, 0, 0]], Q=[[2]], c=[1], gate=9)
    for m in (car, meas, gf.KFModel(A=np.eye(3), R=np.eye(3)),
              gf.KF2Meas(C=[[1, 0], [0, 1]], Q=np.eye(2), gate=4)):
        back = pickle.loads(pickle.dumps(m))
        assert type(back) is type(m)
        for attr in ("A", "R", "B", "c", "C", "Q", "gate"):
            if hasattr(m, attr):
                assert np.array_equal(getattr(back, attr), getattr(m, attr),
                                      equal_nan=False) or (
                    getattr(m, attr) is None and getattr(back, attr) is None)
    # a prediction with the copy is the original's, bit for bit
    a, b = gf.KF2(mu=[1, 2], sigma=np.eye(2)), gf.KF2(mu=[1, 2],
                                                      sigma=np.eye(2))
    a.predict(car)
    b.predict(pickle.loads(pickle.dumps(car)))
    assert same(a, b)
    for builtin in (gf.forward_turn, gf.meas_x, gf.meas_xy):
        assert pickle.loads(pickle.dumps(builtin)) is builtin
    motion = pickle.loads(pickle.dumps(gf.EKFMotion(g=motion_g, R=np.eye(2))))
    assert motion.g is motion_g and motion.n == 2
    meas3 = pickle.loads(pickle.dumps(gf.EKF3Meas(h=gf.meas_x, Q=[[1]],
                                                  angle_mask=1, gate=3)))
    assert meas3.h is gf.meas_x and meas3.angle_mask == 1 and meas3.gate == 3
    with pytest.raises((pickle.PicklingError, AttributeError)):
        pickle.dumps(gf.EKFMotion(g=lambda mu, u: (mu, np.eye(2)),
                                  R=np.eye(2)))


def test_a_foreign_state_is_refused_and_nothing_changes():
    f32, f64 = stepped(float32)["KF2"], stepped(float64)["KF2"]
    before = f32.__getstate__()
    for bad in (f64.__getstate__(), (2,) + before[1:], "x", (1, "float32"),
                before[:2] + (before[2][:-1],) + before[3:]):
        with pytest.raises(gaussfilt.BadArgument):
            f32.__setstate__(bad)
        assert f32.__getstate__() == before
    # factors whose order is not a permutation: refused, not read
    belief = bytearray(before[2])
    belief[-4] = 9
    with pytest.raises(gaussfilt.BadArgument, match="not one the library"):
        f32.__setstate__(before[:2] + (bytes(belief),) + before[3:])
    k = stepped(float64)["KF"]
    st = k.__getstate__()
    n_bad = (99).to_bytes(4, "little") + st[2][4:]
    with pytest.raises(gaussfilt.BadArgument):
        k.__setstate__(st[:2] + (n_bad,) + st[3:])
    assert k.__getstate__() == st


def test_repr():
    f = float32.KF2(mu=[4.0244, 1.2195], sigma=np.eye(2))
    assert repr(f) == "<gaussfilt.float32.KF2 n=2 mu=[4.0244 1.2195]>"
    assert repr(float64.EKF(mu=[1, 2, 3], sigma=np.eye(3))) == \
        "<gaussfilt.float64.EKF n=3 mu=[1. 2. 3.]>"
    assert repr(float64.KFMeas(C=[[1, 0, 0, 0]], Q=[[1]])) == \
        "<gaussfilt.float64.KFMeas n=4 m=1>"
    assert repr(float32.EKF3Meas(h=float32.meas_xy, Q=np.eye(2))) == \
        "<gaussfilt.float32.EKF3Meas m=2>"
    sub = subclass(float32.KF2, float32).__new__(subclass(float32.KF2,
                                                          float32))
    sub.reset(mu=[1, 2], sigma=np.eye(2))
    assert repr(sub) == ("<test_state.MyKF2_float32 gaussfilt.float32.KF2 "
                         "n=2 mu=[1. 2.]>")
    model = subclass(float64.KFMeas, float64).__new__(
        subclass(float64.KFMeas, float64))
    float64.KFMeas.__init__(model, C=[[1, 0]], Q=1)
    assert repr(model) == ("<test_state.MyKFMeas_float64 "
                           "gaussfilt.float64.KFMeas n=2 m=1>")
    assert repr(float64.KF.__new__(float64.KF)) == \
        "<gaussfilt.float64.KF n=0 mu=[]>"


@pytest.mark.parametrize("gf", MODS)
def test_the_mean_is_settable_and_reset_judges(gf):
    for name, f in stepped(gf).items():
        n = len(f.mu)
        sigma = f.sigma
        before = f.__getstate__()
        for bad in ([1.0] * (n + 1), [np.nan] * n, "abc", None):
            with pytest.raises(gaussfilt.GaussfiltError):
                f.mu = bad
            assert f.__getstate__() == before, name
        f.mu = np.arange(n, dtype=float) + 0.5
        assert np.array_equal(f.mu, (np.arange(n) + 0.5).astype(gf.dtype)) \
            or name in ("EKF3", "EKF")  # an angle state is wrapped
        assert np.array_equal(f.sigma, sigma), name  # the factors kept
        kept = f.__getstate__()
        with pytest.raises(gaussfilt.NotPSD):
            f.reset(mu=np.zeros(n), sigma=-np.eye(n))
        assert f.__getstate__() == kept
        f.reset(mu=np.zeros(n), sigma=np.eye(n) * 2)
        assert np.array_equal(f.sigma, np.eye(n) * 2)
        assert f.innovation is None  # a new belief, no update yet
    ekf3 = gf.EKF3(mu=[0, 0, 0], sigma=np.eye(3))
    ekf3.mu = [0, 0, 4.0]
    assert abs(float(ekf3.mu[2]) - (4.0 - 2 * np.pi)) < 1e-6


@pytest.mark.parametrize("gf", MODS)
def test_sigma_is_a_property_and_its_setter_factors_as_init(gf):
    for name, f in stepped(gf).items():
        n = len(f.mu)
        assert isinstance(f.sigma, np.ndarray) and f.sigma.dtype == gf.dtype
        assert f.sigma.shape == (n, n) and f.sigma[0, 0] > 0
        assert f.sigma is not f.sigma  # a new array each time, as mu
        # the method it was, for one release: the same values, and a warning
        with pytest.warns(DeprecationWarning, match=r"write f\.sigma"):
            old = f.sigma()
        assert type(old) is np.ndarray and old.tobytes() == f.sigma.tobytes()
        # everything else as a plain ndarray: computed from, printed, pickled
        s = f.sigma
        for derived in (s * 2, s + s, s @ s, np.sqrt(np.abs(s)), s.T @ s):
            assert type(derived) is np.ndarray
        assert type(s.sum()) is gf.dtype.type
        assert repr(s) == repr(np.array(s)) and str(s) == str(np.array(s))
        back = pickle.loads(pickle.dumps(s))
        assert type(back) is np.ndarray and back.tobytes() == s.tobytes()
        before = f.__getstate__()
        bad = {"NotPSD": -np.eye(n), "NonFinite": np.full((n, n), np.nan),
               "BadArgument": [np.eye(n + 1), "abc", None, b"1",
                               np.eye(n) * 1j, np.eye(n, dtype=object)]}
        for exc, values in bad.items():
            for value in (values if isinstance(values, list) else [values]):
                with pytest.raises(getattr(gaussfilt, exc)) as e:
                    f.sigma = value
                assert "%s.sigma" % name in str(e.value), str(e.value)
                assert f.__getstate__() == before, (name, exc)
        with pytest.raises(gaussfilt.BadArgument, match="cannot be deleted"):
            del f.sigma
        assert f.__getstate__() == before
        new = np.diag(np.arange(1, n + 1) * 0.5)
        new[0, 1] = new[1, 0] = 0.1
        nis, y = f.nis, f.innovation
        f.sigma = new
        # the factors the constructor makes of the same mean and sigma
        twin = type(f).__new__(type(f))
        if name == "EKF":
            twin.reset(mu=f.mu, sigma=new, angles=f.angles)
        else:
            twin.reset(mu=f.mu, sigma=new)
        assert f.__getstate__()[2] == twin.__getstate__()[2], name
        assert np.array_equal(f.sigma, new.astype(gf.dtype))
        assert f.nis == nis and np.array_equal(f.innovation, y)  # kept
        # a scalar is a 1 x 1 sigma
        one = gf.KF(mu=[2.0], sigma=[[1.0]])
        one.sigma = 4
        assert one.sigma.tolist() == [[4.0]]


@pytest.mark.parametrize("gf", MODS)
def test_weak_references(gf):
    import gc
    import weakref
    objs = list(stepped(gf).values()) + [
        gf.KF2Model(A=np.eye(2), R=np.eye(2)), gf.KFMeas(C=[[1, 0]], Q=[[1]]),
        gf.EKF3Motion(g=gf.forward_turn, R=np.eye(3)),
        gf.EKFMeas(h=meas_h, Q=[[1]], n=3)]
    refs = [weakref.ref(o) for o in objs]
    cache = weakref.WeakValueDictionary(enumerate(objs))
    assert all(r() is o for r, o in zip(refs, objs)) and len(cache) == 8
    del objs
    gc.collect()
    assert all(r() is None for r in refs) and len(cache) == 0


def subclass(base, gf):
    """A subclass of base whose __init__ takes other arguments, as this
    module's global MyKF2_float32 (so that pickle finds it)."""
    name = "My%s_%s" % (base.__name__, gf.__name__.split(".")[1])
    if name not in globals():
        globals()[name] = type(name, (base,), {
            "__init__": lambda self, tag: setattr(self, "tag", tag),
            "__module__": __name__})
    return globals()[name]


def subclassed(gf):
    """A subclass of every belief and model, with an attribute of its own
    and an __init__ of another signature, and one object of each."""
    out = []
    for name, f in stepped(gf).items():
        cls = subclass(type(f), gf)
        twin = cls.__new__(cls)
        twin.__setstate__(f.__getstate__())
        twin.tag = {"name": name}
        out.append((twin, f))
    models = [
        gf.KF2Model(A=[[1, 1], [0, 1]], R=np.eye(2), B=np.eye(2), c=[1, 0]),
        gf.KF2Meas(C=[[1, 0]], Q=[[2]], c=[0.5], gate=9),
        gf.EKF3Motion(g=gf.forward_turn, R=np.eye(3) * 0.01),
        gf.EKF3Meas(h=gf.meas_xy, Q=np.eye(2), angle_mask=2, gate=5),
        gf.KFModel(A=np.eye(3), R=np.eye(3), B=np.ones((3, 1))),
        gf.KFMeas(C=[[1, 0, 0]], Q=[[1]], c=[2], gate=4),
        gf.EKFMotion(g=motion_g, R=np.eye(3)),
        gf.EKFMeas(h=meas_h, Q=[[1]], n=3, angle_mask=1, gate=3)]
    for m in models:
        cls = subclass(type(m), gf)
        twin = cls.__new__(cls)
        type(m).__init__(twin, *[getattr(m, a) for a in ARGS[type(m).__name__]])
        twin.tag = [type(m).__name__]
        out.append((twin, m))
    return out


ARGS = {"KF2Model": ("A", "R", "B", "c"), "KFModel": ("A", "R", "B", "c"),
        "KF2Meas": ("C", "Q", "c", "gate"), "KFMeas": ("C", "Q", "c", "gate"),
        "EKF3Motion": ("g", "R"), "EKFMotion": ("g", "R"),
        "EKF3Meas": ("h", "Q", "angle_mask", "gate"),
        "EKFMeas": ("h", "Q", "n", "angle_mask", "gate")}


def same_model(a, b):
    for attr in ARGS[type(b).__name__]:
        x, y = getattr(a, attr), getattr(b, attr)
        if isinstance(y, np.ndarray):
            assert x.dtype == y.dtype and x.tobytes() == y.tobytes(), attr
        else:
            assert x is y or x == y, attr
    return True


@pytest.mark.parametrize("gf", MODS)
def test_subclasses_pickle_and_copy_with_their_attributes(gf):
    for obj, plain in subclassed(gf):
        for twin in (pickle.loads(pickle.dumps(obj)), copy.copy(obj),
                     copy.deepcopy(obj)):
            assert type(twin) is type(obj) and twin.tag == obj.tag
            if hasattr(plain, "mu"):
                assert twin.__getstate__()[:5] == plain.__getstate__()
                assert twin.__getstate__()[5] == {"tag": obj.tag}
            else:
                assert same_model(twin, plain)
        deep = copy.deepcopy(obj)
        assert deep.tag is not obj.tag  # deepcopy copies the attributes
    # an object of the class itself: no attributes in its state
    assert all(len(f.__getstate__()) == 5 for f in stepped(gf).values())


@pytest.mark.parametrize("gf", MODS)
def test_models_step_as_their_copies(gf):
    """A prediction and an update with a model's pickled or copied twin
    give the original's bits (the twin factored to the same bits)."""
    kf = gf.KF(mu=[1, 2, 3], sigma=np.diag([2, 1, 0.5]))
    model = gf.KFModel(A=[[1, 0.1, 0], [0, 1, 0.1], [0, 0, 1]],
                       R=[[0.3, 0.1, 0], [0.1, 0.2, 0.05], [0, 0.05, 0.1]],
                       B=[[0.5], [1], [0]], c=[0.01, 0, 0])
    meas = gf.KFMeas(C=[[1, 0, 0], [0, 0, 1]], Q=[[2, 0.3], [0.3, 1]])
    ekf3 = gf.EKF3(mu=[0, 0, 0.5], sigma=np.eye(3))
    motion = gf.EKF3Motion(g=gf.forward_turn, R=np.diag([0.1, 0.1, 0.01]))
    for twin_of in (lambda m: pickle.loads(pickle.dumps(m)), copy.copy,
                    copy.deepcopy):
        a, b = copy.deepcopy(kf), copy.deepcopy(kf)
        a.predict(model, u=[0.5])
        b.predict(twin_of(model), u=[0.5])
        a.update(meas, z=[1, 2])
        b.update(twin_of(meas), z=[1, 2])
        assert same(a, b)
        c, d = copy.deepcopy(ekf3), copy.deepcopy(ekf3)
        c.predict(motion, u=[1, 0.2])
        d.predict(twin_of(motion), u=[1, 0.2])
        assert same(c, d)


@pytest.mark.parametrize("gf", MODS)
def test_states_refused_and_nothing_changes(gf):
    # a filter never initialised has no state to give
    for cls in (gf.KF2, gf.EKF3, gf.KF, gf.EKF):
        with pytest.raises(gaussfilt.BadArgument, match="never initialised"):
            pickle.dumps(cls.__new__(cls))
    # attributes for an object that has no __dict__, or not a dict
    f = stepped(gf)["KF"]
    st = f.__getstate__()
    for bad in (st + ({"tag": 1},), st + ([1],)):
        with pytest.raises(gaussfilt.BadArgument, match="attributes"):
            f.__setstate__(bad)
        assert f.__getstate__() == st
    # a model's state that is not one, or that its constructor refuses
    car = gf.KF2Model(A=[[1, 1], [0, 1]], R=np.eye(2))
    for bad, exc in (("x", gaussfilt.BadArgument),
                     (((np.eye(2),), None), TypeError),
                     ((np.eye(2), np.eye(2)), gaussfilt.BadArgument),
                     (((np.eye(2), -np.eye(2), None, None), None),
                      gaussfilt.NotPSD)):
        with pytest.raises(exc):
            car.__setstate__(bad)
        assert same_model(car, gf.KF2Model(A=[[1, 1], [0, 1]], R=np.eye(2)))


def test_a_pickle_loads_in_another_interpreter():
    """Checkpoints and multiprocessing: every belief and model pickled here
    loads in a fresh Python (classes found by their module, built-in
    models by name) and steps there to the bits it steps to here."""
    import subprocess
    import sys
    script = r'''
import pickle, sys
import numpy as np
objs = pickle.loads(sys.stdin.buffer.read())
out = []
for mod_name, kf, model, meas, ekf3, motion in objs:
    kf.predict(model, u=[0.5])
    kf.update(meas, z=[1.0, 2.0])
    ekf3.predict(motion, u=[1.0, 0.3])
    out.append((kf.__getstate__(), ekf3.__getstate__()))
sys.stdout.buffer.write(pickle.dumps(out))
'''
    objs, want = [], []
    for gf in MODS:
        kf = gf.KF(mu=[1, 2, 3], sigma=np.diag([2, 1, 0.5]))
        model = gf.KFModel(A=np.eye(3), R=np.eye(3) * 0.1,
                           B=[[1], [0], [0.5]], c=[0, 0.1, 0])
        meas = gf.KFMeas(C=[[1, 0, 0], [0, 1, 0]], Q=np.eye(2), gate=50)
        ekf3 = gf.EKF3(mu=[0, 0, 0.2], sigma=np.eye(3))
        motion = gf.EKF3Motion(g=gf.forward_turn, R=np.eye(3) * 0.01)
        objs.append((gf.__name__, kf, model, meas, ekf3, motion))
        k, e = copy.deepcopy(kf), copy.deepcopy(ekf3)
        k.predict(model, u=[0.5])
        k.update(meas, z=[1.0, 2.0])
        e.predict(motion, u=[1.0, 0.3])
        want.append((k.__getstate__(), e.__getstate__()))
    got = subprocess.run([sys.executable, "-c", script],
                         input=pickle.dumps(objs), capture_output=True,
                         check=True).stdout
    assert pickle.loads(got) == want


@pytest.mark.parametrize("gf", MODS)
def test_exceptions_pickle_with_what_they_carry(gf):
    """A worker's exception reaches its parent whole: Gated's innovation
    and NIS, a run's failed step."""
    kf = gf.KF2(mu=[0, 0], sigma=np.eye(2))
    with pytest.raises(gaussfilt.Gated) as gated:
        kf.update(gf.KF2Meas(C=[1, 0], Q=1, gate=1), 100)
    pushed = gf.KF2Model(A=np.eye(2), R=np.eye(2), B=np.eye(2))
    with pytest.raises(gaussfilt.NonFinite) as failed:
        kf.run(pushed, u=[[0, 0], [0, 0], [np.nan, 0]])
    for e in (gated.value, failed.value):
        back = pickle.loads(pickle.dumps(e))
        assert type(back) is type(e) and str(back) == str(e)
        assert back.step == e.step and back.status == e.status
    back = pickle.loads(pickle.dumps(gated.value))
    assert back.nis == gated.value.nis == 5000
    assert back.innovation.tobytes() == gated.value.innovation.tobytes()
    assert pickle.loads(pickle.dumps(failed.value)).step == 2
