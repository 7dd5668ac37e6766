"""Input validation shared by every package of the project.

Its one home is here because ``common`` is the ground floor of the layers
(``common`` -> ``mdr`` -> ``meshes`` -> ``fem`` -> ``studies`` -> ``validation``): every package may import it.

Every public function checks its arguments with these helpers, so that bad
input fails early with one clear message that names the parameter and the
valid range, instead of producing NaN or a traceback deep inside a solver.
"""
from __future__ import annotations

import math

import numpy as np


class InputError(ValueError):
    """A parameter is outside its valid range (the message names it)."""


class ConvergenceError(RuntimeError):
    """An iterative solver did not converge; the message carries diagnostics."""


def show(value) -> str:
    """One-line text of a parameter value for error messages (arrays summarised), so that
    a command line can print the error as a single line."""
    if isinstance(value, np.ndarray) and value.ndim > 0:
        arr = np.asarray(value)
        if arr.size <= 4:
            return "[" + ", ".join(f"{v!r}" for v in arr.ravel().tolist()) + "]"
        try:
            bad = ~np.isfinite(arr.astype(float))
            extra = f", {int(bad.sum())} not finite" if bad.any() else ""
            good = arr.astype(float)[~bad]
            rng = f" in [{good.min():.4g}, {good.max():.4g}]" if good.size else ""
        except (TypeError, ValueError):
            extra, rng = "", ""
        return f"array of shape {arr.shape}{rng}{extra}"
    return " ".join(repr(value).split())


def _finite_array(name, value):
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a real number, got {show(value)}") from None
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} must be finite, got {show(value)}")
    return arr


def positive(name, value):
    """Return ``value`` as float (or array) after checking ``0 < value < inf``."""
    arr = _finite_array(name, value)
    if np.any(arr <= 0):
        raise InputError(f"{name} must be > 0 (finite), got {show(value)}")
    return float(arr) if arr.ndim == 0 else arr


def nonnegative(name, value):
    """Return ``value`` after checking ``0 <= value < inf``."""
    arr = _finite_array(name, value)
    if np.any(arr < 0):
        raise InputError(f"{name} must be >= 0 (finite), got {show(value)}")
    return float(arr) if arr.ndim == 0 else arr


def finite(name, value):
    """Return ``value`` after checking it is a finite real number."""
    arr = _finite_array(name, value)
    return float(arr) if arr.ndim == 0 else arr


def in_range(name, value, lo, hi, *, lo_open=False, hi_open=False):
    """Check ``lo <(=) value <(=) hi`` and name the interval in the error."""
    arr = _finite_array(name, value)
    bad_lo = np.any(arr <= lo) if lo_open else np.any(arr < lo)
    bad_hi = np.any(arr >= hi) if hi_open else np.any(arr > hi)
    if bad_lo or bad_hi:
        left = "(" if lo_open else "["
        right = ")" if hi_open else "]"
        raise InputError(f"{name} must be in {left}{lo:g}, {hi:g}{right}, got {show(value)}")
    return float(arr) if arr.ndim == 0 else arr


def positive_int(name, value, minimum=1):
    """Return ``value`` as int after checking it is an integer >= minimum."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        if isinstance(value, float) and math.isfinite(value) and value == int(value):
            value = int(value)
        else:
            raise InputError(f"{name} must be an integer >= {minimum}, got {show(value)}")
    if value < minimum:
        raise InputError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)
