"""enginedyn: engine dynamics from indicator diagrams, for Python.

The same library as the ``enginedyn`` command line (its Rust session layer,
called through ``enginedyn._native``): the same reader, the same rules, the
same numbers bit for bit, the same notes. Nothing here decides a rule, a
bound or a default; this module only shapes the results for NumPy, pandas,
Arrow and polars users.

>>> import enginedyn as ed
>>> s = ed.Session(ed.Engine.bundled("vaz2108"), method=ed.Method(step_deg=0.5))
>>> r = s.analyse()
>>> round(r.summary["imep_bar"], 1) > 5
True
"""

from __future__ import annotations

import importlib as _importlib
import io as _io
import json as _json
import os as _os
import warnings as _warnings
from typing import Any, Dict, Iterable, List, Optional, Sequence, Union

import numpy as np

from . import _native
from ._native import (
    DiagramError,
    EngineFileError,
    EnginedynError,
    UsageError,
    __version__,
)

__all__ = [
    "Engine",
    "Method",
    "Reader",
    "Session",
    "Result",
    "Batch",
    "Torsion",
    "EnginedynError",
    "DiagramError",
    "EngineFileError",
    "UsageError",
    "EnginedynWarning",
    "__version__",
]

def _install_sigint() -> None:
    """Ctrl-C stops a call computing in any thread, not only the main
    thread's: Python runs its SIGINT handler in the main thread alone, so
    the package's handler (installed over Python's default, and only over
    it) asks the library to stop every call, then raises
    ``KeyboardInterrupt`` as the default does."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        return
    try:
        if signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
            return
        default = signal.default_int_handler

        def _on_sigint(signum: int, frame: Any) -> Any:
            _native.interrupt_all()
            return default(signum, frame)

        signal.signal(signal.SIGINT, _on_sigint)
    except (ValueError, OSError):
        pass


_install_sigint()

# ``enginedyn.io`` and ``enginedyn.dask`` load on first use.
_LAZY = ("io", "dask")


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        module = _importlib.import_module(f"{__name__}.{name}")
        globals()[name] = module
        return module
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> List[str]:
    return sorted(__all__ + list(_LAZY))


class EnginedynWarning(UserWarning):
    """What may mean a wrong result: the CLI's ``warning:`` lines (``python
    -W error`` stops on them; ``warnings.filterwarnings("ignore",
    category=EnginedynWarning)`` silences them)."""


def _warn(lines: Iterable[str], stacklevel: int = 3) -> None:
    for w in lines:
        _warnings.warn(w, EnginedynWarning, stacklevel=stacklevel)


def _split(notes: Iterable[str]) -> "tuple[List[str], List[str]]":
    """Notes and warnings apart, by the CLI's one rule."""
    kept: List[str] = []
    warned: List[str] = []
    for n in notes:
        (warned if _native.severity(n) == "warning" else kept).append(n)
    return kept, warned

PathLike = Union[str, "_os.PathLike[str]"]


class Engine:
    """A checked engine (the engine file, TOML)."""

    __slots__ = ("_native",)

    def __init__(self, native: "_native.Engine") -> None:
        self._native = native

    @classmethod
    def from_toml(cls, path: PathLike) -> "Engine":
        """Reads and checks an engine file."""
        return cls(_native.Engine.from_toml(_os.fspath(path)))

    @classmethod
    def from_str(cls, text: str, path: Optional[PathLike] = None) -> "Engine":
        """Checks engine-file text (``path``: where it was read from, for its
        name and the folder its ``diagram`` is relative to)."""
        return cls(_native.Engine.from_str(text, None if path is None else _os.fspath(path)))

    @classmethod
    def bundled(cls, name: str = "vaz2108") -> "Engine":
        """A bundled example (``Engine.bundled_names()`` lists them)."""
        return cls(_native.Engine.bundled(name))

    @staticmethod
    def bundled_names() -> List[str]:
        """The bundled examples' names."""
        return list(_native.Engine.bundled_names())

    @property
    def name(self) -> str:
        return self._native.name

    @property
    def cylinders(self) -> int:
        return self._native.cylinders

    @property
    def text(self) -> str:
        """The engine file's text."""
        return self._native.text

    @property
    def path(self) -> Optional[str]:
        p = self._native.path
        return None if p is None else _os.fspath(p)

    def __reduce__(self) -> Any:
        return (_engine_from_state, (self._native.text, self.path, self._native.bundled_name))

    def __repr__(self) -> str:
        return f"Engine({self.name!r}, cylinders={self.cylinders})"


def _engine_from_state(text: str, path: Optional[str], bundled: Optional[str]) -> Engine:
    if bundled is not None:
        return Engine.bundled(bundled)
    return Engine.from_str(text, path)


class _Options:
    """Keyword options checked by the library (its bounds, its messages)."""

    __slots__ = ("_kw",)

    def __init__(self, **kw: Any) -> None:
        self._kw = {k: v for k, v in kw.items() if v is not None}
        _CHECKS[type(self).__name__](self._kw)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_") or name not in _keywords(type(self)):
            raise AttributeError(f"{type(self).__name__} has no option {name!r}")
        return self._kw.get(name)

    def as_dict(self) -> Dict[str, Any]:
        """The options given, by name."""
        return dict(self._kw)

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and other._kw == self._kw  # type: ignore[attr-defined]

    def __hash__(self) -> int:
        return hash((type(self).__name__, _json.dumps(self._kw, sort_keys=True, default=str)))

    def __reduce__(self) -> Any:
        return (_options_from_state, (type(self).__name__, self._kw))

    def __repr__(self) -> str:
        inner = ", ".join(f"{k}={v!r}" for k, v in self._kw.items())
        return f"{type(self).__name__}({inner})"


class Method(_Options):
    """How the computation is done: ``step_deg``, ``kinematics``,
    ``rod_model``, ``interp``, ``integration``, ``tolerance`` (the CLI's
    method flags, with their bounds; a value out of bounds raises
    ``UsageError`` naming the argument), and the combustion analysis:
    ``burn_points`` (levels in percent, e.g. ``[5, 10, 50, 90]``),
    ``burn_window`` (``(-90, 120)`` or ``"-90:120"``), ``gamma`` (``1.32``
    or ``"brunt"``), ``smooth`` (``"SG:2"`` or ``"off"``),
    ``intake_temp_k`` and ``ivc_deg`` (with ``gamma="brunt"`` or a wall-heat
    model), ``wall_heat`` (``"woschni"``, ``"hohenberg"`` or ``"off"``),
    ``wall_temp_k``, ``knock`` (``True`` measures knock; so does any of the
    next three), ``knock_band`` (kHz, ``(4, 20)`` or ``"4:20"``),
    ``knock_window`` (``(-10, 70)``) and ``knock_threshold`` (bar)."""

    __slots__ = ()

    def __init__(
        self,
        step_deg: Optional[float] = None,
        *,
        kinematics: Optional[str] = None,
        rod_model: Optional[str] = None,
        interp: Optional[str] = None,
        integration: Optional[str] = None,
        tolerance: Optional[float] = None,
        burn_points: Optional[Union[Sequence[float], str]] = None,
        burn_window: Optional[Union[Sequence[float], str]] = None,
        gamma: Optional[Union[float, str]] = None,
        smooth: Optional[str] = None,
        intake_temp_k: Optional[float] = None,
        ivc_deg: Optional[float] = None,
        wall_heat: Optional[str] = None,
        wall_temp_k: Optional[float] = None,
        knock: Optional[bool] = None,
        knock_band: Optional[Union[Sequence[float], str]] = None,
        knock_window: Optional[Union[Sequence[float], str]] = None,
        knock_threshold: Optional[float] = None,
    ) -> None:
        super().__init__(
            step_deg=step_deg,
            kinematics=kinematics,
            rod_model=rod_model,
            interp=interp,
            integration=integration,
            tolerance=tolerance,
            burn_points=burn_points if burn_points is None or isinstance(burn_points, str) else list(burn_points),
            burn_window=burn_window if burn_window is None or isinstance(burn_window, str) else list(burn_window),
            gamma=gamma,
            smooth=smooth,
            intake_temp_k=intake_temp_k,
            ivc_deg=ivc_deg,
            wall_heat=wall_heat,
            wall_temp_k=wall_temp_k,
            knock=knock,
            knock_band=knock_band if knock_band is None or isinstance(knock_band, str) else list(knock_band),
            knock_window=knock_window if knock_window is None or isinstance(knock_window, str) else list(knock_window),
            knock_threshold=knock_threshold,
        )


class Reader(_Options):
    """How a diagram is read: the CLI's reader flags by name (``tdc_deg``,
    ``columns``, ``skip_lines``, ``sheet``, ``max_gap_deg``, ``gauge``,
    ``peg_bar``, ``peg``, ``gain_bar_per_v``, ``tdc_time``, ``rpm``,
    ``cylinder_axis``, ``pv_start``, ``encoder_ppr``, ``wheel``,
    ``wheel_tdc_deg``, ``compression_check`` (``False`` for
    ``--no-compression-check``), ``despike`` (``True`` for ``--despike``:
    each glitch replaced by the cubic through its neighbours, by the same
    library rule), ``angle_step`` (``--angle-step``)), with their bounds."""

    __slots__ = ()

    def __init__(
        self,
        *,
        tdc_deg: Optional[float] = None,
        columns: Optional[Sequence[str]] = None,
        skip_lines: Optional[int] = None,
        sheet: Optional[Union[str, int]] = None,
        group: Optional[int] = None,
        max_gap_deg: Optional[float] = None,
        gauge: Optional[bool] = None,
        peg_bar: Optional[float] = None,
        peg: Optional[str] = None,
        gain_bar_per_v: Optional[float] = None,
        tdc_time: Optional[float] = None,
        rpm: Optional[float] = None,
        cylinder_axis: Optional[str] = None,
        pv_start: Optional[str] = None,
        encoder_ppr: Optional[int] = None,
        wheel: Optional[str] = None,
        wheel_tdc_deg: Optional[float] = None,
        compression_check: Optional[bool] = None,
        despike: Optional[bool] = None,
        angle_step: Optional[float] = None,
    ) -> None:
        super().__init__(
            tdc_deg=tdc_deg,
            columns=columns if columns is None or isinstance(columns, str) else list(columns),
            skip_lines=skip_lines,
            sheet=sheet,
            group=group,
            max_gap_deg=max_gap_deg,
            gauge=gauge,
            peg_bar=peg_bar,
            peg=peg,
            gain_bar_per_v=gain_bar_per_v,
            tdc_time=tdc_time,
            rpm=rpm,
            cylinder_axis=cylinder_axis,
            pv_start=pv_start,
            encoder_ppr=encoder_ppr,
            wheel=wheel,
            wheel_tdc_deg=wheel_tdc_deg,
            compression_check=compression_check,
            despike=despike,
            angle_step=angle_step,
        )


_CHECKS = {"Method": _native.check_method, "Reader": _native.check_reader}


def _keywords(cls: type) -> List[str]:
    import inspect

    return [p for p in inspect.signature(cls).parameters]


def _options_from_state(kind: str, kw: Dict[str, Any]) -> _Options:
    return {"Method": Method, "Reader": Reader}[kind](**kw)


def _float64(name: str, x: Any, time: bool = False) -> np.ndarray:
    """A C-contiguous float64 array: borrowed when it already is one,
    converted otherwise. A masked array is refused (its mask would be
    lost); a ``timedelta64`` time is converted to seconds."""
    if np.ma.isMaskedArray(x):
        raise ValueError(
            f"{name}=: a masked array (its mask would be lost): fill it, "
            f"e.g. {name}.filled(np.nan), and drop the masked samples from every "
            "array alike, or give the samples' cycle= so that a dropout's cycle is left out"
        )
    raw = np.asarray(x) if not isinstance(x, np.ndarray) else x
    if raw.dtype.kind == "m":
        if not time:
            raise TypeError(f"{name}=: a timedelta64 array is a time, not a {name}")
        return np.ascontiguousarray(raw / np.timedelta64(1, "s"), dtype=np.float64)
    if raw.dtype.kind == "M":
        raise TypeError(
            f"{name}=: datetime64 values: give the time since the start, "
            f"e.g. ({name} - {name}[0]) as timedelta64 or seconds"
        )
    try:
        return np.ascontiguousarray(raw, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name}=: not an array of numbers ({e})") from None


def _vector(name: str, x: Any, time: bool = False) -> np.ndarray:
    a = _float64(name, x, time)
    if a.ndim != 1:
        raise TypeError(f"{name}=: a 1-D array is needed, not {a.ndim}-D of shape {a.shape}")
    return a


class _Frozen:
    """A result held as plain data (what a pickle or ``Result.load`` gives
    back): the same answers as the binding's run it was taken from."""

    __slots__ = ("_state",)

    def __init__(self, state: Dict[str, Any]) -> None:
        self._state = state

    @property
    def notes(self) -> List[str]:
        return list(self._state["notes"])

    def summary_json(self) -> str:
        return str(self._state["summary_json"])

    def curves(self, centered: bool = False) -> Dict[str, np.ndarray]:
        if centered:
            raise UsageError("centered curves are computed by the run itself, not kept with a saved result")
        return {k: np.array(v, dtype=np.float64) for k, v in self._state["curves"].items()}

    def harmonics(self) -> Dict[str, np.ndarray]:
        return {k: np.array(v, dtype=np.float64) for k, v in self._state["harmonics"].items()}

    def cycles(self) -> Dict[str, Any]:
        return {
            k: (np.array(v["values"], dtype=v["dtype"]) if isinstance(v, dict) else list(v))
            for k, v in self._state["cycles"].items()
        }

    def summary_parquet(self) -> bytes:
        return bytes(self._state["summary_parquet"])

    def charts(self) -> List[str]:
        return list(self._state["charts"])

    def svg(self, name: str) -> str:
        want = name[:-4] if name.endswith(".svg") else name
        for file, data in self._state["files"]:
            if file == want + ".svg":
                return bytes(data).decode()
        raise UsageError(f"no chart `{want}`: the charts are {', '.join(self.charts())}")

    def files(self, centered: bool = False) -> List[tuple]:
        if centered:
            raise UsageError("centered curves are computed by the run itself, not kept with a saved result")
        return [(n, bytes(b)) for n, b in self._state["files"]]


def _state_of(native: Any) -> Dict[str, Any]:
    """Everything a result answers, as plain data (exact: arrays of the very
    floats; NumPy arrays pickle as their bytes, ``to_folder`` writes them
    as JSON lists)."""
    if isinstance(native, _Frozen):
        return native._state
    cycles: Dict[str, Any] = {}
    for k, v in native.cycles().items():
        cycles[k] = list(v) if isinstance(v, list) else {"dtype": str(v.dtype), "values": v.tolist()}
    return {
        "summary_json": native.summary_json(),
        "notes": list(native.notes),
        "curves": dict(native.curves(False)),
        "harmonics": dict(native.harmonics()),
        "cycles": cycles,
        "summary_parquet": native.summary_parquet(),
        "charts": list(native.charts()),
        "files": [(n, bytes(b)) for n, b in native.files(False)],
    }


# What ``Result.to_folder`` writes beside the files of ``run --out``.
_SAVED = "enginedyn-result.json"
_SAVED_PARQUET = "enginedyn-summary.parquet"


class Result:
    """One operating point: the summary, notes and warnings, curves,
    harmonics, charts. It pickles (a worker can return it) and saves
    (``to_folder``, ``Result.load``)."""

    __slots__ = ("_native", "_summary")

    def __init__(self, native: Any) -> None:
        self._native = native
        self._summary: Optional[Dict[str, Any]] = None

    @property
    def summary(self) -> Dict[str, Any]:
        """``summary.json``'s keys, exactly as the CLI writes them (its
        ``notes`` hold the notes and the warnings, in the CLI's order)."""
        if self._summary is None:
            self._summary = _json.loads(self._native.summary_json())
        return self._summary

    def summary_json(self) -> str:
        """``summary.json``'s text, byte for byte as ``run --out`` writes it."""
        return self._native.summary_json()

    @property
    def notes(self) -> List[str]:
        """What was decided or assumed: the CLI's ``note:`` lines."""
        return _split(self._native.notes)[0]

    @property
    def warnings(self) -> List[str]:
        """What may mean a wrong result: the CLI's ``warning:`` lines (each
        also issued as an ``EnginedynWarning`` when the result was made)."""
        return _split(self._native.notes)[1]

    @property
    def cycles(self) -> Dict[str, Any]:
        """The ``cycles/3`` table's columns for this run: every measured
        cycle, used or left out (``used``, ``skip_reason``), its IMEP, peak
        and speed (NumPy arrays; NaN where the table holds null)."""
        return dict(self._native.cycles())

    @property
    def curves(self) -> Dict[str, np.ndarray]:
        """``curves.csv``'s columns (NaN where its cell is empty)."""
        return dict(self._native.curves(False))

    @property
    def harmonics(self) -> Dict[str, np.ndarray]:
        """``harmonics.csv``'s columns."""
        return dict(self._native.harmonics())

    def charts(self) -> List[str]:
        """The chart names ``svg`` takes."""
        return list(self._native.charts())

    def svg(self, name: str) -> str:
        """A chart as SVG text (``torque``, ``pressure``, …)."""
        return self._native.svg(name)

    def files(self, centered: bool = False) -> List[tuple]:
        """Every file ``run --out DIR`` writes, as (name, bytes)."""
        return list(self._native.files(centered))

    def to_arrow(self) -> Any:
        """This run as the ``summary/4`` table's one row (``pyarrow.Table``):
        the columns, types and metadata of a campaign's parts."""
        return _read_parquet(self._native.summary_parquet())

    def to_pandas(self) -> Any:
        """This run as a one-row pandas DataFrame (the ``summary/4`` columns)."""
        return self.to_arrow().to_pandas()

    def to_polars(self) -> Any:
        """This run as a one-row polars DataFrame (the ``summary/4`` columns)."""
        import polars as pl

        return pl.read_parquet(_io.BytesIO(self._native.summary_parquet()))

    def __reduce__(self) -> Any:
        return (_result_from_state, (_state_of(self._native),))

    def to_folder(self, path: PathLike) -> str:
        """Writes the files of ``run --out`` into the folder ``path`` (made
        when missing), and what ``Result.load`` needs to give this result
        back (``enginedyn-result.json``, ``enginedyn-summary.parquet``).
        The folder is written as ``run --out`` writes it, by the same
        function: every file staged, then moved into place; a link, a
        folder or a read-only file in the way is refused (``UsageError``),
        never written through."""
        state = _state_of(self._native)
        folder = _os.fspath(path)
        kept = {k: v for k, v in state.items() if k not in ("files", "summary_parquet")}
        for arrays in ("curves", "harmonics"):
            kept[arrays] = {k: np.asarray(v).tolist() for k, v in state[arrays].items()}
        kept["files"] = [n for n, _ in state["files"]]
        files = [(str(n), bytes(b)) for n, b in state["files"]]
        files.append((_SAVED, _json.dumps(kept).encode("utf-8")))
        files.append((_SAVED_PARQUET, bytes(state["summary_parquet"])))
        _warn(_native.write_run_folder(folder, files))
        return folder

    @classmethod
    def load(cls, path: PathLike) -> "Result":
        """A result saved by ``to_folder``. The folder's
        ``enginedyn-result.json`` names only plain files of the folder
        itself, each a regular file (never a link), and its
        ``summary.json`` holds the saved summary; otherwise an
        ``EnginedynError`` naming the file (``path``) says what is wrong."""
        folder = _os.fspath(path)
        saved = _os.path.join(folder, _SAVED)
        if not _os.path.lexists(saved):
            raise FileNotFoundError(2, f"not a folder Result.to_folder wrote (no {_SAVED})", saved)
        raw = _native.read_run_folder(folder, [_SAVED, _SAVED_PARQUET])
        state = _saved_state(saved, raw[0][1])
        names = state["files"]
        state["files"] = [(n, b) for n, b in _native.read_run_folder(folder, names)]
        state["summary_parquet"] = raw[1][1]
        summary = dict(state["files"]).get("summary.json")
        if summary is not None and summary != state["summary_json"].encode("utf-8"):
            raise _malformed(
                _os.path.join(folder, "summary.json"),
                f"it is not the summary {_SAVED} holds (changed since the folder was written)",
            )
        return cls(_Frozen(state))

    def _repr_html_(self) -> str:
        s = self.summary
        rows = "".join(
            f"<tr><th style='text-align:left'>{label}</th><td style='text-align:right'>{_figure(s.get(k), scale, digits)}</td><td>{unit}</td></tr>"
            for k, label, unit, scale, digits in _SHOWN
            if k in s
        )
        warned = "".join(f"<li style='color:#b45309'>&#9888; warning: {_esc(w)}</li>" for w in self.warnings)
        noted = "".join(f"<li style='color:#555'>note: {_esc(n)}</li>" for n in self.notes)
        listed = f"<ul style='list-style:none;padding-left:0'>{warned}{noted}</ul>" if warned or noted else ""
        return f"<div><table>{rows}</table>{listed}{self.svg('torque')}</div>"

    def __repr__(self) -> str:
        s = self.summary
        return (
            f"Result(rpm={s.get('rpm')}, imep_bar={s.get('imep_bar')}, "
            f"warnings={len(self.warnings)}, notes={len(self.notes)})"
        )


def _malformed(path: str, why: str) -> EnginedynError:
    e = EnginedynError(f"{path}: not a result Result.to_folder wrote: {why}")
    e.path = path  # type: ignore[attr-defined]
    return e


# The keys of ``enginedyn-result.json`` and the type each holds.
_SAVED_KEYS = {
    "summary_json": str,
    "notes": list,
    "curves": dict,
    "harmonics": dict,
    "cycles": dict,
    "charts": list,
    "files": list,
}


def _saved_state(path: str, data: bytes) -> Dict[str, Any]:
    """``enginedyn-result.json`` read and checked: every key, each of its
    type, the names of the files plain strings (the folder's own files are
    checked by the library as they are read)."""
    try:
        state = _json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as e:
        raise _malformed(path, f"not JSON ({e})") from None
    if not isinstance(state, dict):
        raise _malformed(path, "not a JSON object")
    for key, kind in _SAVED_KEYS.items():
        if key not in state:
            raise _malformed(path, f"no `{key}`")
        if not isinstance(state[key], kind):
            raise _malformed(path, f"`{key}` is not a {kind.__name__}")
    if not all(isinstance(n, str) for n in state["files"] + state["notes"] + state["charts"]):
        raise _malformed(path, "`files`, `notes` and `charts` hold strings only")
    for arrays in ("curves", "harmonics"):
        for k, v in state[arrays].items():
            if not (isinstance(v, list) and all(isinstance(x, (int, float)) or x is None for x in v)):
                raise _malformed(path, f"`{arrays}.{k}` is not a list of numbers")
    for k, v in state["cycles"].items():
        ok = isinstance(v, list) or (
            isinstance(v, dict) and isinstance(v.get("dtype"), str) and isinstance(v.get("values"), list)
        )
        if not ok:
            raise _malformed(path, f"`cycles.{k}` is neither a list nor a dtype with values")
    try:
        for k, v in state["cycles"].items():
            if isinstance(v, dict):
                np.array(v["values"], dtype=v["dtype"])
    except (TypeError, ValueError) as e:
        raise _malformed(path, f"`cycles`: {e}") from None
    return state


def _result_from_state(state: Dict[str, Any]) -> Result:
    return Result(_Frozen(state))


# The summary's figures a notebook shows: key, then label, unit, scale and
# decimals as the CLI's readable tables give them (a key that is not a
# figure raises KeyError here, at import).
_SHOWN = tuple(
    (k, *_native.shown(k))
    for k in (
        "rpm",
        "imep_bar",
        "mean_torque_nm",
        "power_kw",
        "torque_max_nm",
        "torque_min_nm",
        "torque_nonuniformity",
        "flywheel_inertia_kg_m2",
    )
)


def _figure(v: Any, scale: float, digits: int) -> str:
    if v is None:
        return "—"
    if isinstance(v, (int, float)):
        return f"{v * scale:,.{digits}f}"
    return _esc(str(v))


def _esc(t: str) -> str:
    return (
        t.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace("'", "&#39;").replace('"', "&quot;")
    )


def _shown(v: Any) -> str:
    return "—" if v is None else _esc(str(v))


def _csv_columns(text: str) -> Dict[str, np.ndarray]:
    """A CSV the library wrote, as float64 columns (its numbers are written
    to round-trip: the arrays hold the very values)."""
    lines = text.splitlines()
    names = lines[0].split(",")
    rows = [[float(x) if x else np.nan for x in line.split(",")] for line in lines[1:]]
    data = np.array(rows, dtype=np.float64).reshape(len(rows), len(names))
    return {n: data[:, k].copy() for k, n in enumerate(names)}


class Torsion:
    """A torsion study: ``modes`` and ``response`` as NumPy columns (the
    columns of ``modes.csv`` and ``torsion.csv``), ``doc`` (``torsion.json``:
    frequencies, resonances, maxima, the chain), ``notes``, and the charts."""

    __slots__ = ("json_text", "modes_csv", "torsion_csv", "notes", "_charts")

    def __init__(
        self,
        json_text: str,
        modes_csv: str,
        torsion_csv: str,
        notes: List[str],
        charts: List[Any],
    ) -> None:
        self.json_text = json_text
        self.modes_csv = modes_csv
        self.torsion_csv = torsion_csv
        self.notes = list(notes)
        self._charts = dict(charts)

    @property
    def doc(self) -> Dict[str, Any]:
        """``torsion.json``."""
        return _json.loads(self.json_text)

    @property
    def modes(self) -> Dict[str, np.ndarray]:
        return _csv_columns(self.modes_csv)

    @property
    def response(self) -> Dict[str, np.ndarray]:
        return _csv_columns(self.torsion_csv)

    @property
    def resonances(self) -> List[Dict[str, Any]]:
        return list(self.doc.get("resonances", []))

    def svg(self, name: str) -> str:
        """``campbell`` or ``torsion``, as SVG text."""
        key = name if name.endswith(".svg") else name + ".svg"
        if key not in self._charts:
            raise UsageError(f"no chart `{name}`: the charts are {', '.join(sorted(self._charts))}")
        return self._charts[key]


class _FrozenBatch:
    """A batch held as plain data (what a pickle gives back)."""

    __slots__ = ("_state",)

    def __init__(self, state: Dict[str, Any]) -> None:
        self._state = state

    def files(self) -> List[str]:
        return list(self._state["files"])

    def errors(self) -> List[Optional[str]]:
        return list(self._state["errors"])

    def summaries(self) -> List[Optional[str]]:
        return list(self._state["summaries"])

    def summary_parquet(self) -> bytes:
        return bytes(self._state["summary_parquet"])

    def notes(self) -> "List[tuple[List[str], List[str]]]":
        return [
            ([], []) if t is None else tuple(_split(_json.loads(t).get("notes", [])))  # type: ignore[misc]
            for t in self._state["summaries"]
        ]

    def cycles_parquet(self) -> bytes:
        return bytes(self._state["cycles_parquet"])

    def write_parquet(self, dir: str, part: int, parts: int, traces: bool) -> List[str]:
        raise UsageError(
            "write_parquet writes a campaign's parts from the batch that ran them, "
            "not from a copy (a pickle): call it where the batch ran, or use "
            "enginedyn.dask.run_shard on the worker"
        )


class Batch:
    """Many files: one row per file; a failed file is a row with ``error``.
    Its tables are the campaign's (``summary/4``, ``cycles/3``): the same
    columns, types and metadata ``enginedyn batch --parquet`` writes. It
    pickles (its tables and summaries; ``write_parquet`` stays with the
    batch that ran)."""

    __slots__ = ("_native",)

    def __init__(self, native: Any) -> None:
        self._native = native

    def __len__(self) -> int:
        return len(self._native.files())

    @property
    def files(self) -> List[str]:
        return list(self._native.files())

    @property
    def errors(self) -> List[Optional[str]]:
        return list(self._native.errors())

    def summaries(self) -> List[Optional[Dict[str, Any]]]:
        """Each file's ``summary.json`` keys (``None`` for a failed file)."""
        return [None if t is None else _json.loads(t) for t in self._native.summaries()]

    @property
    def warnings(self) -> List[List[str]]:
        """Each file's ``warning:`` lines (empty for a failed file)."""
        return [list(w) for _, w in self._native.notes()]

    @property
    def notes(self) -> List[List[str]]:
        """Each file's ``note:`` lines (empty for a failed file)."""
        return [list(n) for n, _ in self._native.notes()]

    def to_arrow(self) -> Any:
        """The ``summary/4`` table as a ``pyarrow.Table`` (one row per file)."""
        return _read_parquet(self._native.summary_parquet())

    def cycles_arrow(self) -> Any:
        """The ``cycles/3`` table as a ``pyarrow.Table``."""
        return _read_parquet(self._native.cycles_parquet())

    def to_pandas(self) -> Any:
        """The ``summary/4`` table as a pandas DataFrame."""
        return self.to_arrow().to_pandas()

    def to_polars(self) -> Any:
        """The ``summary/4`` table as a polars DataFrame."""
        import polars as pl

        return pl.read_parquet(_io.BytesIO(self._native.summary_parquet()))

    def write_parquet(
        self, dir: PathLike, part: int = 0, parts: int = 1, traces: bool = False
    ) -> List[str]:
        """Writes part ``part`` of ``parts`` of the campaign in ``dir``: the
        files ``enginedyn batch --shard part/parts --parquet dir`` writes."""
        return [_os.fspath(p) for p in self._native.write_parquet(_os.fspath(dir), part, parts, traces)]

    def __reduce__(self) -> Any:
        n = self._native
        if isinstance(n, _FrozenBatch):
            state = n._state
        else:
            state = {
                "files": n.files(),
                "errors": n.errors(),
                "summaries": n.summaries(),
                "summary_parquet": n.summary_parquet(),
                "cycles_parquet": n.cycles_parquet(),
            }
        return (_batch_from_state, (state,))

    def _repr_html_(self) -> str:
        summaries = self.summaries()
        head = "".join(f"<th>{label}{' (' + unit + ')' if unit else ''}</th>" for _, label, unit, _, _ in _SHOWN[:4])
        rows = []
        for f, e, s, w in zip(self.files, self.errors, summaries, self.warnings):
            if s is None:
                cells = f"<td colspan='4' style='color:#b91c1c'>error: {_esc(e or '')}</td>"
            else:
                cells = "".join(
                    f"<td style='text-align:right'>{_figure(s.get(k), sc, d)}</td>" for k, _, _, sc, d in _SHOWN[:4]
                )
            mark = f" <span style='color:#b45309' title='{_esc('; '.join(w))}'>&#9888; {len(w)}</span>" if w else ""
            rows.append(f"<tr><td>{_esc(f)}{mark}</td>{cells}</tr>")
        shown = rows if len(rows) <= 20 else rows[:10] + ["<tr><td colspan='5'>…</td></tr>"] + rows[-10:]
        return (
            f"<div><p>{_esc(repr(self))}</p><table><tr><th>file</th>{head}</tr>"
            + "".join(shown)
            + "</table></div>"
        )

    def __repr__(self) -> str:
        failed = sum(1 for e in self.errors if e is not None)
        warned = sum(1 for w in self.warnings if w)
        return f"Batch({len(self)} files, {failed} failed, {warned} with warnings)"


def _batch_from_state(state: Dict[str, Any]) -> Batch:
    return Batch(_FrozenBatch(state))


def _read_parquet(data: bytes) -> Any:
    import pyarrow.parquet as pq

    return pq.read_table(_io.BytesIO(data))


# The keyword each column is given as.
_KEYWORD_OF = {"crank_deg": "angle_deg"}


def _warned(r: Result) -> Result:
    _warn(r.warnings, stacklevel=4)
    return r


class Session:
    """An engine with reader and method options, checked once. It pickles
    (the engine file's text and the options), so that a scheduler can ship
    it, and its bound methods, to workers."""

    __slots__ = ("engine", "method", "reader", "_full", "_summary_only")

    def __init__(
        self,
        engine: Engine,
        method: Optional[Method] = None,
        reader: Optional[Reader] = None,
    ) -> None:
        if not isinstance(engine, Engine):
            raise TypeError("engine: an enginedyn.Engine is needed")
        self.engine = engine
        self.method = method if method is not None else Method()
        self.reader = reader if reader is not None else Reader()
        self._full = _native.NativeSession(
            engine._native, self.method.as_dict(), self.reader.as_dict(), True
        )
        self._summary_only: Optional[Any] = None

    def __reduce__(self) -> Any:
        return (Session, (self.engine, self.method, self.reader))

    def analyse(self, *paths: PathLike) -> Result:
        """One operating point from a diagram file (or one per cylinder, in
        order 1..z; none: the engine's own diagram), as ``enginedyn run``.
        Its warnings are issued as ``EnginedynWarning``."""
        return _warned(Result(self._full.analyse([_os.fspath(p) for p in paths])))

    def analyse_torque(self, path: PathLike) -> Result:
        """One operating point from a turning-moment file (``run --torque``)."""
        return _warned(Result(self._full.analyse_torque(_os.fspath(path))))

    def analyse_arrays(
        self,
        angle_deg: Any,
        pressure_bar: Any,
        rpm: Optional[float] = None,
        cycle: Any = None,
        cylinder: Any = None,
    ) -> Result:
        """One operating point from arrays: crank angle (deg) and absolute
        pressure (bar), optionally each sample's cycle and cylinder number;
        the same reader, and the same plausibility, as a file with those
        columns. ``pressure_bar`` 2-D is one row a cylinder."""
        cols = {"crank_deg": angle_deg, "cycle": cycle, "cylinder": cylinder}
        return _warned(self._columns(cols, ("pressure_bar", pressure_bar), rpm))

    def analyse_time_record(
        self,
        time_s: Any,
        pressure_bar: Any = None,
        tdc: Any = None,
        rpm: Optional[float] = None,
        pressure_v: Any = None,
        encoder: Any = None,
        wheel: Any = None,
        cam: Any = None,
    ) -> Result:
        """One operating point from a time record: time (s, or
        ``timedelta64``), pressure (bar, or volts with
        ``Reader(gain_bar_per_v=…)``; 2-D: one row a cylinder) and the angle
        source: a TDC pulse, an ``encoder`` (``Reader(encoder_ppr=…)``), a
        tooth ``wheel`` (``Reader(wheel="60-2")``) with an optional ``cam``,
        or ``rpm`` with ``Reader(tdc_time=…)``."""
        if (pressure_bar is None) == (pressure_v is None):
            raise TypeError("give one of pressure_bar= or pressure_v=")
        cols = {"time_s": time_s, "tdc": tdc, "encoder": encoder, "wheel": wheel, "cam": cam}
        pressure = ("pressure_bar", pressure_bar) if pressure_v is None else ("pressure_v", pressure_v)
        return _warned(self._columns(cols, pressure, rpm))

    def _columns(self, cols: Dict[str, Any], pressure: "tuple[str, Any]", rpm: Optional[float]) -> Result:
        names = [k for k, v in cols.items() if v is not None]
        arrays = [_vector(_KEYWORD_OF.get(k, k), cols[k], time=k == "time_s") for k in names]
        pname, p = pressure
        pa = _float64(pname, p)
        if pa.ndim not in (1, 2):
            raise TypeError(f"{pname}=: a 1-D array (or 2-D, one row a cylinder) is needed, not {pa.ndim}-D")
        n = pa.shape[-1]
        shown = [(_KEYWORD_OF.get(k, k), len(a)) for k, a in zip(names, arrays)] + [(pname, n)]
        if len({m for _, m in shown}) > 1:
            raise ValueError("arrays of different lengths: " + ", ".join(f"{k} {m}" for k, m in shown))
        if pa.ndim == 1:
            # The pressure second, as a file's header has it.
            native = self._full.analyse_columns(names[:1] + [pname] + names[1:], arrays[:1] + [pa] + arrays[1:], rpm)
        else:
            native = self._full.analyse_columns(names, arrays, rpm, pname, pa)
        return Result(native)

    def batch(self, paths: Iterable[PathLike], jobs: int = 0) -> Batch:
        """Many diagram files on ``jobs`` threads (0 or -1: one per core, -2:
        all but one, as in joblib; use 1 inside Dask, joblib or
        multiprocessing workers). A failed file is a row with ``error``,
        never an exception. A file named twice (``a.csv``, ``./a.csv``) is
        one row, by its canonical path, with a warning naming the names.
        Each kind of warning (what it says, not its numbers) is issued
        once, with the number of files that gave it and the range of its
        numbers, as the CLI's log groups them (``_native.grouped``)."""
        if isinstance(paths, (str, bytes, _os.PathLike)):
            raise TypeError(
                f"paths=: a list of files is needed, not one path ({paths!r}): "
                "batch([path]), or analyse(path) for one file"
            )
        if isinstance(jobs, bool) or not isinstance(jobs, int):
            raise TypeError(f"jobs=: an int is needed, not {type(jobs).__name__}")
        if jobs < 0:
            cores = _os.cpu_count() or 1
            if jobs + 1 + cores < 1:
                raise UsageError(f"jobs={jobs}: this machine has {cores} cores (-1 is all of them)")
            jobs = 0 if jobs == -1 else jobs + 1 + cores
        if self._summary_only is None:
            self._summary_only = _native.NativeSession(
                self.engine._native, self.method.as_dict(), self.reader.as_dict(), False
            )
        native = self._summary_only.batch([_os.fspath(p) for p in paths], jobs)
        _warn(native.listed())
        b = Batch(native)
        _warn(line for _, line in _native.grouped(list(zip(b.files, b.warnings)), "files"))
        return b

    def torsion(
        self,
        rpm: Optional[Union[Sequence[float], np.ndarray]] = None,
        diagram: Optional[PathLike] = None,
    ) -> "Torsion":
        """The crankshaft's torsional vibration (the engine file's
        ``[torsion]``): ``rpm`` is (FROM, TO, STEP) as ``--rpm FROM:TO:STEP``,
        or the speeds themselves; none: 20 % to 120 % of the speed."""
        if rpm is None:
            rpms = None
        elif isinstance(rpm, tuple) and len(rpm) == 3:
            rpms = _native.speeds(float(rpm[0]), float(rpm[1]), float(rpm[2]))
        else:
            rpms = [float(x) for x in rpm]
        texts = self._full.torsion(rpms, None if diagram is None else _os.fspath(diagram))
        return Torsion(*texts)

    def __repr__(self) -> str:
        return f"Session({self.engine!r}, {self.method!r}, {self.reader!r})"
