# SPDX-License-Identifier: BSD-3-Clause
"""cdprlib: the cdpr library in-process from Python (docs/python.md).

    import cdprlib
    plant = cdprlib.Plant("scenarios/paper-line.yaml")   # build and settle, as cdpr-sim does
    for k in range(100):
        rates = plant.control()          # the scenario's controller (or your own rates)
        plant.step(rates)                # one control period; CdprError on a failed step
    m = plant.measure()                  # t, position, quaternion, ..., tensions (NumPy)
    nodes = plant.nodes(0)               # cable 1's node positions, (n + 1) x 3
    y = plant.state()                    # the state vector: a view of the C memory, no copy

The model is the C library's: this package calls it through ctypes (Python's standard
foreign-function library, nothing to compile for Python) on a small C shim with plain C types
(libcdpr_py.so, built with the project and installed inside this package). Errors from the
library are raised as CdprError with the core's status name and its message, which names the
scenario key (FILE:LINE: KEY: what) where there is one.
"""
import ctypes
import math
import os

import numpy as np

__all__ = ["CdprError", "Plant", "Robot", "Measurement", "WHY_NAMES", "catenary_solve",
           "catenary_point", "RATE", "LENGTH"]

RATE = 0    # winch commands are payout rates [m/s]
LENGTH = 1  # winch commands are unstretched lengths [m]

_lib = ctypes.CDLL(os.path.join(os.path.dirname(os.path.abspath(__file__)), "libcdpr_py.so"))
_D = ctypes.POINTER(ctypes.c_double)
_I = ctypes.POINTER(ctypes.c_int)
_L = ctypes.POINTER(ctypes.c_long)


def _sig(name, res, *args):
    f = getattr(_lib, name)
    f.restype = res
    f.argtypes = list(args)
    return f


_status_name = _sig("cdpr_py_status_name", ctypes.c_char_p, ctypes.c_int)
_open = _sig("cdpr_py_open", ctypes.c_void_p, ctypes.c_char_p, _I, ctypes.c_char_p,
             ctypes.c_size_t)
_close = _sig("cdpr_py_close", None, ctypes.c_void_p)
_info = _sig("cdpr_py_info", None, ctypes.c_void_p, _L, _D)
_state = _sig("cdpr_py_state", _D, ctypes.c_void_p, _I)
_initial_pose = _sig("cdpr_py_initial_pose", None, ctypes.c_void_p, _D)
_measure = _sig("cdpr_py_measure", ctypes.c_int, ctypes.c_void_p, _D, ctypes.c_int)
_nodes = _sig("cdpr_py_nodes", ctypes.c_int, ctypes.c_void_p, ctypes.c_int, _D, ctypes.c_int)
_control = _sig("cdpr_py_control", ctypes.c_int, ctypes.c_void_p, _D)
_step = _sig("cdpr_py_step", ctypes.c_int, ctypes.c_void_p, ctypes.c_int, _D, _I)
_work = _sig("cdpr_py_work", None, ctypes.c_void_p, _L)
_ik = _sig("cdpr_py_ik", ctypes.c_int, ctypes.c_void_p, _D, _D, _D, _D, _D)
_robot_open = _sig("cdpr_py_robot_open", ctypes.c_void_p, ctypes.c_char_p, _I, ctypes.c_char_p,
                   ctypes.c_size_t)
_robot_close = _sig("cdpr_py_robot_close", None, ctypes.c_void_p)
_robot_info = _sig("cdpr_py_robot_info", ctypes.c_int, ctypes.c_void_p, _D)
_robot_ik = _sig("cdpr_py_robot_ik", ctypes.c_int, ctypes.c_void_p, _D, _D, _D, _D, _D, _D, _D,
                 _D, _D, _I, _D, _I)
_cat_solve = _sig("cdpr_py_catenary_solve", ctypes.c_int, ctypes.c_double, ctypes.c_double,
                  ctypes.c_double, ctypes.c_double, ctypes.c_double, _D, _D)
_cat_point = _sig("cdpr_py_catenary_point", None, ctypes.c_double, ctypes.c_double,
                  ctypes.c_double, ctypes.c_double, ctypes.c_double, _D, _D)

# Flags of a period (cdpr/plant.h), as CdprError and step() report them.
FLAG_NAMES = {2: "substep_limit", 4: "node_capacity", 8: "min_length", 16: "step_failed"}


class CdprError(RuntimeError):
    """A failure reported by the library: `status` (the core's code, negative), `name`
    (CDPR_E_...) and the message (the scenario key and why, where there is one)."""

    def __init__(self, status, message):
        self.status = status
        self.name = status_name(status)
        self.message = message
        super().__init__("%s: %s" % (self.name, message) if message else self.name)


def status_name(status):
    """The core's name of a status code (CDPR_OK, CDPR_E_..., CDPR_WARN_...)."""
    return _status_name(int(status)).decode()


def _ptr(a):
    return a.ctypes.data_as(_D)


def _f64(values, n, what):
    a = np.ascontiguousarray(values, dtype=np.float64)
    if a.shape != (n,):
        raise ValueError("%s: %d values expected, got shape %s" % (what, n, a.shape))
    return a


class Measurement:
    """What a controller measures at t_k (NumPy arrays; copies)."""

    __slots__ = ("t_s", "position_m", "quaternion", "velocity_m_per_s", "rate_rad_per_s",
                 "length_m", "tension_winch_N", "tension_cabin_N")

    def __init__(self, buf, n):
        self.t_s = float(buf[0])
        self.position_m = buf[1:4].copy()
        self.quaternion = buf[4:8].copy()
        self.velocity_m_per_s = buf[8:11].copy()
        self.rate_rad_per_s = buf[11:14].copy()
        self.length_m = buf[14:14 + n].copy()
        self.tension_winch_N = buf[14 + n:14 + 2 * n].copy()
        self.tension_cabin_N = buf[14 + 2 * n:14 + 3 * n].copy()


def _open_handle(opener, path):
    """Call a shim's open function on `path`: the handle, or CdprError with its message."""
    status = ctypes.c_int(0)
    msg = ctypes.create_string_buffer(2048)
    h = opener(os.fsencode(path), ctypes.byref(status), msg, len(msg))
    if not h:
        raise CdprError(status.value, msg.value.decode(errors="replace"))
    return ctypes.c_void_p(h)


class _Handle:
    """A C object the package owns (`_free` releases it): freed by close(), at the end of a
    `with` block, or when the object is collected."""

    _free = None

    def close(self):
        """Free the C object (also done when the object is collected)."""
        if getattr(self, "_h", None):
            type(self)._free(self._h)
            self._h = None

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class Plant(_Handle):
    """The plant of a scenario file (robot, initial pose, integrator, period), built and settled
    as cdpr-sim builds it, with the scenario's controller beside it (control()). Step it one
    control period at a time with your own commands or the controller's."""

    _free = staticmethod(_close)

    def __init__(self, scenario):
        self._h = _open_handle(_open, scenario)
        ints = (ctypes.c_long * 5)()
        reals = (ctypes.c_double * 3)()
        _info(self._h, ints, reals)
        self.n_cables = int(ints[0])
        self.n_periods = int(ints[2])      # periods of the scenario's run.duration_s
        self.max_segments = int(ints[4])
        self.period_s = float(reals[0])
        self.duration_s = float(reals[1])
        self._meas = np.zeros(14 + 3 * self.n_cables)
        self._nodes = np.zeros(3 * (self.max_segments + 1))
        self._cmd = np.zeros(self.n_cables)

    @property
    def t_s(self):
        ints = (ctypes.c_long * 5)()
        reals = (ctypes.c_double * 3)()
        _info(self._h, ints, reals)
        return float(reals[2])

    @property
    def k(self):
        """Control periods stepped."""
        ints = (ctypes.c_long * 5)()
        reals = (ctypes.c_double * 3)()
        _info(self._h, ints, reals)
        return int(ints[3])

    def initial_pose(self):
        """The scenario's initial pose (x, y, z [m], alpha, beta, gamma [rad]): where the plant
        was built by the inverse kinematics, before it settled."""
        pose = np.zeros(6)
        _initial_pose(self._h, _ptr(pose))
        return pose

    def state(self):
        """The state vector y (cabin pose and velocities, then each cable's block; its length
        changes when a winch inserts or removes a node) as a NumPy view of the C memory: no
        copy; it reflects later steps while the layout stays the same, so take a new one after a
        node event (work()["node_insertions"]) and copy it to keep it."""
        dim = ctypes.c_int(0)
        p = _state(self._h, ctypes.byref(dim))
        return np.ctypeslib.as_array(p, shape=(dim.value,))

    def measure(self):
        """The measurements at the current time (Measurement)."""
        n = _measure(self._h, _ptr(self._meas), len(self._meas))
        if n < 0:
            raise CdprError(-1, "measurement buffer too small")
        return Measurement(self._meas, self.n_cables)

    def nodes(self, cable):
        """Cable `cable`'s (0-based) node positions now, (n + 1) x 3 [m]: row 0 the cabin
        attachment, row n the exit point (a copy)."""
        n = _nodes(self._h, int(cable), _ptr(self._nodes), self.max_segments + 1)
        if n < 0:
            raise IndexError("cable %r: the robot has %d cables" % (cable, self.n_cables))
        return self._nodes[:3 * n].reshape(n, 3).copy()

    def control(self):
        """The scenario's controller (its gains, trajectory and feed-forward) on the current
        measurements: payout-rate commands [m/s], one per cable."""
        st = _control(self._h, _ptr(self._cmd))
        if st != 0:
            raise CdprError(st, "controller step")
        return self._cmd.copy()

    def step(self, values, mode=RATE):
        """One control period with every winch commanded `values` (rates [m/s] with RATE,
        unstretched lengths [m] with LENGTH; a value a winch refuses keeps its previous
        command). Returns (status name, flags): CDPR_OK or a warning (CDPR_WARN_...) with the
        plant advanced. Raises CdprError when the period failed (the plant stays as it was)."""
        v = _f64(values, self.n_cables, "step")
        flags = ctypes.c_int(0)
        st = _step(self._h, int(mode), _ptr(v), ctypes.byref(flags))
        names = [nm for bit, nm in FLAG_NAMES.items() if flags.value & bit]
        if st < 0:
            raise CdprError(st, "period at t = %.6g s failed (flags: %s)" % (
                self.t_s, ", ".join(names) or "none"))
        return status_name(st), names

    def work(self):
        """The plant's work and events so far (dict)."""
        out = (ctypes.c_long * 6)()
        _work(self._h, out)
        keys = ("steps_accepted", "steps_rejected", "rhs_evals", "step_failures",
                "node_insertions", "node_removals")
        return {k: int(v) for k, v in zip(keys, out)}

    def ik(self, pose):
        """Sag-aware inverse kinematics of this robot at pose (x, y, z [m], alpha, beta,
        gamma [rad]) under the cabin's weight: dict of per-cable NumPy arrays length_m,
        tension_cabin_N, tension_winch_N, H_N. CdprError for a pose it cannot hold
        (CDPR_E_INFEASIBLE: a cable would have to push, or hang in a loop longer than 1.5
        chords)."""
        p = _f64(pose, 6, "pose")
        out = {k: np.zeros(self.n_cables) for k in
               ("length_m", "tension_cabin_N", "tension_winch_N", "H_N")}
        st = _ik(self._h, _ptr(p), _ptr(out["length_m"]), _ptr(out["tension_cabin_N"]),
                 _ptr(out["tension_winch_N"]), _ptr(out["H_N"]))
        if st != 0:
            raise CdprError(st, "inverse kinematics at pose %s" % list(p))
        return out


# Reasons of an infeasible pose (cdpr_statics_why_t, cdpr/statics.h).
WHY_NAMES = {1: "PUSH", 2: "NO_LIFT", 3: "SPAN", 4: "LOOP", 5: "T_MIN", 6: "T_MAX"}


class Robot(_Handle):
    """A robot file's statics (docs/python.md): `Robot(path)` loads and checks the file
    (CdprError naming file, line and key); `ik(pose, ...)` is the sag-aware inverse kinematics
    of any cable count from 6 to the build's capacity, with the tension distribution of a
    redundant robot (cdpr_statics_ik_dist)."""

    _free = staticmethod(_robot_close)

    def __init__(self, path):
        self._h = _open_handle(_robot_open, path)
        nominal = np.zeros(6)
        self.n_cables = int(_robot_info(self._h, _ptr(nominal)))
        self.nominal_pose = nominal

    def ik(self, pose, t_min_N=None, t_max_N=None, t_ref_N=None, f_ext_N=(0.0, 0.0, 0.0),
           tau_ext_Nm=(0.0, 0.0, 0.0)):
        """Equilibrium at pose (x, y, z [m], alpha, beta, gamma [rad]) under the weight and an
        external wrench (world axes, at and about the centre of mass). The tension
        distribution: every cable's lowest tension >= t_min_N and highest <= t_max_N, the
        lowest tensions closest to t_ref_N (default mid-range); without bounds here, the robot
        file's tension_distribution (if any). More than six cables need one of the two. Returns a dict
        of per-cable arrays length_m, tension_cabin_N, tension_winch_N, H_N, v_cabin_N (the
        vertical component at the cabin end, upwards) and `iterations`.
        An infeasible pose raises CdprError with `why` (PUSH, NO_LIFT, SPAN, LOOP, T_MIN,
        T_MAX), `cable` (0-based, -1 if none), `value` and `limit`."""
        p = _f64(pose, 6, "pose")
        f = _f64(f_ext_N, 3, "f_ext_N")
        tau = _f64(tau_ext_Nm, 3, "tau_ext_Nm")
        bounds = None
        if t_min_N is not None or t_max_N is not None:
            if t_min_N is None or t_max_N is None:
                raise ValueError("t_min_N and t_max_N go together")
            ref = 0.5 * (t_min_N + t_max_N) if t_ref_N is None else t_ref_N
            bounds = np.array([t_min_N, t_max_N, ref], dtype=np.float64)
        out = {k: np.zeros(self.n_cables) for k in
               ("length_m", "tension_cabin_N", "tension_winch_N", "H_N", "v_cabin_N")}
        verdict = (ctypes.c_int * 2)()
        values = np.zeros(2)
        it = ctypes.c_int(0)
        st = _robot_ik(self._h, _ptr(p), _ptr(f), _ptr(tau),
                       _ptr(bounds) if bounds is not None else None,
                       _ptr(out["length_m"]), _ptr(out["tension_cabin_N"]),
                       _ptr(out["tension_winch_N"]), _ptr(out["H_N"]), _ptr(out["v_cabin_N"]),
                       verdict, _ptr(values), ctypes.byref(it))
        if st != 0:
            why = WHY_NAMES.get(verdict[0], "")
            text = "inverse kinematics at pose %s" % list(p)
            if why:
                text += ": %s, cable index %d, %.6g against %.6g" % (why, verdict[1], values[0],
                                                                      values[1])
            err = CdprError(st, text)
            err.why, err.cable, err.value, err.limit = why, verdict[1], values[0], values[1]
            raise err
        out["iterations"] = it.value
        return out


def catenary_solve(w_N_per_m, ea_N, l_m, h_m, L0_m):
    """The elastic catenary (Irvine): end forces (H, V_A) [N] of a cable of weight w [N/m] per
    unstretched metre, axial stiffness EA [N] and unstretched length L0 [m] whose ends are l
    horizontally and h vertically (upwards from end A) apart."""
    H = ctypes.c_double(0.0)
    V = ctypes.c_double(0.0)
    st = _cat_solve(w_N_per_m, ea_N, l_m, h_m, L0_m, ctypes.byref(H), ctypes.byref(V))
    if st != 0:
        raise CdprError(st, "catenary: w %g N/m, EA %g N, l %g m, h %g m, L0 %g m" % (
            w_N_per_m, ea_N, l_m, h_m, L0_m))
    return H.value, V.value


def catenary_point(w_N_per_m, ea_N, H_N, va_N, s_m):
    """The point (x, z) [m] at unstretched arclength s from end A of that cable."""
    x = ctypes.c_double(0.0)
    z = ctypes.c_double(0.0)
    _cat_point(w_N_per_m, ea_N, H_N, va_N, s_m, ctypes.byref(x), ctypes.byref(z))
    if not (math.isfinite(x.value) and math.isfinite(z.value)):
        raise CdprError(-2, "catenary point not finite (H must be > 0)")
    return x.value, z.value
