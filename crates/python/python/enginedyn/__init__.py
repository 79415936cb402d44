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

import io as io_module
import json
import os
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
    "__version__",
]

PathLike = Union[str, "os.PathLike[str]"]


class Engine:
    """A checked engine (the engine file, TOML)."""

    __slots__ = ("_native",)

    def __init__(self, native: "_native.Engine") -> None:
        self._native = native

    @classmethod
    def from_toml(cls, path: PathLike) -> "Engine":
        """Reads and checks an engine file."""
        return cls(_native.Engine.from_toml(os.fspath(path)))

    @classmethod
    def from_str(cls, text: str, path: Optional[PathLike] = None) -> "Engine":
        """Checks engine-file text (``path``: where it was read from, for its
        name and the folder its ``diagram`` is relative to)."""
        return cls(_native.Engine.from_str(text, None if path is None else os.fspath(path)))

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
        return None if p is None else os.fspath(p)

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
        if name.startswith("_"):
            raise AttributeError(name)
        return self._kw.get(name)

    def as_dict(self) -> Dict[str, Any]:
        """The options given, by name."""
        return dict(self._kw)

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and other._kw == self._kw  # type: ignore[attr-defined]

    def __hash__(self) -> int:
        return hash((type(self).__name__, json.dumps(self._kw, sort_keys=True, default=str)))

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
    ``intake_temp_k`` and ``ivc_deg`` (with ``gamma="brunt"``)."""

    __slots__ = ()

    def __init__(
        self,
        step_deg: Optional[float] = None,
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
        )


class Reader(_Options):
    """How a diagram is read: the CLI's reader flags by name (``tdc_deg``,
    ``columns``, ``skip_lines``, ``sheet``, ``max_gap_deg``, ``gauge``,
    ``peg_bar``, ``peg``, ``gain_bar_per_v``, ``tdc_time``, ``rpm``,
    ``cylinder_axis``, ``pv_start``, ``encoder_ppr``, ``wheel``,
    ``wheel_tdc_deg``, ``compression_check`` (``False`` for
    ``--no-compression-check``), ``angle_step`` (``--angle-step``)), with
    their bounds."""

    __slots__ = ()

    def __init__(self, **kw: Any) -> None:
        super().__init__(**kw)


_CHECKS = {"Method": _native.check_method, "Reader": _native.check_reader}


def _options_from_state(kind: str, kw: Dict[str, Any]) -> _Options:
    return {"Method": Method, "Reader": Reader}[kind](**kw)


def _float64(name: str, x: Any) -> np.ndarray:
    """A 1-D C-contiguous float64 array: borrowed when it already is one,
    converted otherwise; anything else a ``TypeError``."""
    try:
        a = np.ascontiguousarray(x, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name}: not an array of numbers ({e})") from None
    if a.ndim != 1:
        raise TypeError(f"{name}: a 1-D array is needed, not {a.ndim}-D of shape {a.shape}")
    return a


class Result:
    """One operating point: the summary, notes, curves, harmonics, charts."""

    __slots__ = ("_native", "_summary")

    def __init__(self, native: "_native.Run") -> None:
        self._native = native
        self._summary: Optional[Dict[str, Any]] = None

    @property
    def summary(self) -> Dict[str, Any]:
        """``summary.json``'s keys, exactly as the CLI writes them."""
        if self._summary is None:
            self._summary = json.loads(self._native.summary_json())
        return self._summary

    def summary_json(self) -> str:
        """``summary.json``'s text, byte for byte as ``run --out`` writes it."""
        return self._native.summary_json()

    @property
    def notes(self) -> List[str]:
        """What was decided or may be wrong, as the CLI says it."""
        return list(self._native.notes)

    @property
    def cycles(self) -> Dict[str, Any]:
        """The ``cycles/2`` table's columns for this run: every measured
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
        """This run as the ``summary/2`` table's one row (``pyarrow.Table``):
        the columns, types and metadata of a campaign's parts."""
        return _read_parquet(self._native.summary_parquet())

    def to_pandas(self) -> Any:
        """This run as a one-row pandas DataFrame (the ``summary/2`` columns)."""
        return self.to_arrow().to_pandas()

    def to_polars(self) -> Any:
        """This run as a one-row polars DataFrame (the ``summary/2`` columns)."""
        import polars as pl

        return pl.read_parquet(io_module.BytesIO(self._native.summary_parquet()))

    def _repr_html_(self) -> str:
        s = self.summary
        rows = "".join(
            f"<tr><th style='text-align:left'>{k}</th><td>{_shown(s.get(k))}</td></tr>"
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
            if k in s
        )
        notes = "".join(f"<li>{_esc(n)}</li>" for n in self.notes)
        return (
            f"<div><table>{rows}</table>"
            + (f"<ul>{notes}</ul>" if notes else "")
            + self.svg("torque")
            + "</div>"
        )

    def __repr__(self) -> str:
        s = self.summary
        return f"Result(rpm={s.get('rpm')}, imep_bar={s.get('imep_bar')}, notes={len(self.notes)})"


def _esc(t: str) -> str:
    return t.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


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
        return json.loads(self.json_text)

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


class Batch:
    """Many files: one row per file; a failed file is a row with ``error``.
    Its tables are the campaign's (``summary/2``, ``cycles/2``): the same
    columns, types and metadata ``enginedyn batch --parquet`` writes."""

    __slots__ = ("_native",)

    def __init__(self, native: "_native.NativeBatch") -> None:
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
        return [None if t is None else json.loads(t) for t in self._native.summaries()]

    def to_arrow(self) -> Any:
        """The ``summary/2`` table as a ``pyarrow.Table`` (one row per file)."""
        return _read_parquet(self._native.summary_parquet())

    def cycles_arrow(self) -> Any:
        """The ``cycles/2`` table as a ``pyarrow.Table``."""
        return _read_parquet(self._native.cycles_parquet())

    def to_pandas(self) -> Any:
        """The ``summary/2`` table as a pandas DataFrame."""
        return self.to_arrow().to_pandas()

    def to_polars(self) -> Any:
        """The ``summary/2`` table as a polars DataFrame."""
        import polars as pl

        return pl.read_parquet(io_module.BytesIO(self._native.summary_parquet()))

    def write_parquet(
        self, dir: PathLike, part: int = 0, parts: int = 1, traces: bool = False
    ) -> List[str]:
        """Writes part ``part`` of ``parts`` of the campaign in ``dir``: the
        files ``enginedyn batch --shard part/parts --parquet dir`` writes."""
        return [os.fspath(p) for p in self._native.write_parquet(os.fspath(dir), part, parts, traces)]

    def __repr__(self) -> str:
        failed = sum(1 for e in self.errors if e is not None)
        return f"Batch({len(self)} files, {failed} failed)"


def _read_parquet(data: bytes) -> Any:
    import pyarrow.parquet as pq

    return pq.read_table(io_module.BytesIO(data))


class Session:
    """An engine with reader and method options, checked once."""

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
        order 1..z; none: the engine's own diagram), as ``enginedyn run``."""
        return Result(self._full.analyse([os.fspath(p) for p in paths]))

    def analyse_torque(self, path: PathLike) -> Result:
        """One operating point from a turning-moment file (``run --torque``)."""
        return Result(self._full.analyse_torque(os.fspath(path)))

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
        the same reader as a file with those columns."""
        cols = {"crank_deg": angle_deg, "pressure_bar": pressure_bar, "cycle": cycle, "cylinder": cylinder}
        return self._columns(cols, rpm)

    def analyse_time_record(
        self,
        time_s: Any,
        pressure_bar: Any = None,
        tdc: Any = None,
        rpm: Optional[float] = None,
        pressure_v: Any = None,
    ) -> Result:
        """One operating point from a time record: time (s), pressure (bar,
        or volts with ``Reader(gain_bar_per_v=…)``) and a TDC pulse (or
        ``rpm`` with ``Reader(tdc_time=…)``)."""
        if (pressure_bar is None) == (pressure_v is None):
            raise TypeError("give one of pressure_bar or pressure_v")
        cols = {"time_s": time_s, "pressure_bar": pressure_bar, "pressure_v": pressure_v, "tdc": tdc}
        return self._columns(cols, rpm)

    def _columns(self, cols: Dict[str, Any], rpm: Optional[float]) -> Result:
        names = [k for k, v in cols.items() if v is not None]
        arrays = [_float64(k, cols[k]) for k in names]
        lengths = {len(a) for a in arrays}
        if len(lengths) > 1:
            raise ValueError(
                "arrays of different lengths: "
                + ", ".join(f"{k} {len(a)}" for k, a in zip(names, arrays))
            )
        return Result(self._full.analyse_columns(names, arrays, rpm))

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
        texts = self._full.torsion(rpms, None if diagram is None else os.fspath(diagram))
        return Torsion(*texts)

    def batch(self, paths: Iterable[PathLike], jobs: int = 0) -> Batch:
        """Many diagram files on ``jobs`` threads (0: one per core; use 1
        inside Dask, joblib or multiprocessing workers). A failed file is a
        row with ``error``, never an exception."""
        if self._summary_only is None:
            self._summary_only = _native.NativeSession(
                self.engine._native, self.method.as_dict(), self.reader.as_dict(), False
            )
        return Batch(self._summary_only.batch([os.fspath(p) for p in paths], jobs))

    def __repr__(self) -> str:
        return f"Session({self.engine!r}, {self.method!r}, {self.reader!r})"
