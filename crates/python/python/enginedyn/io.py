"""Readers of measurement formats the Rust reader does not take as files:
MDF4 (asammdf), TDMS (npTDMS) and HDF5 (h5py). Each returns a dict of NumPy
arrays ready for ``Session.analyse_arrays`` or ``Session.analyse_time_record``
(``angle_deg`` or ``time_s``, ``pressure_bar`` or ``pressure_v``, ``tdc``,
``cycle``, ``cylinder``), the values converted from each channel's unit by
the reader's own unit tables (``enginedyn._native.canonical``: ``MPa``,
``psi``, ``rad``, ``ms`` …), so a channel reads here as the same column in
a CSV file would.

Several pressure channels (one per cylinder, in the order given) come back
as ``pressure_bar`` (or ``pressure_v``) of shape (cylinders, samples), one
row a cylinder, which ``analyse_arrays(**a)`` and
``analyse_time_record(**a)`` take as they are.

The packages are optional extras: ``pip install enginedyn[mdf]``,
``enginedyn[tdms]``, ``enginedyn[hdf5]``.
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native

__all__ = ["read_mdf", "read_tdms", "read_hdf5", "convert"]

# The canonical column each keyword of analyse_arrays / analyse_time_record takes.
_KEYWORD = {
    "crank_deg": "angle_deg",
    "time_s": "time_s",
    "pressure_bar": "pressure_bar",
    "pressure_v": "pressure_v",
    "tdc": "tdc",
    "cycle": "cycle",
    "cylinder": "cylinder",
}


def convert(name: str, unit: str, values: Any) -> Tuple[str, np.ndarray]:
    """A channel named ``name`` in ``unit`` as (keyword, values in the
    keyword's unit), by the reader's unit tables. Raises ``ValueError`` for
    a channel the reader would not take."""
    label = f"{name} [{unit}]" if unit and unit.strip() else name
    found = _native.canonical(label)
    if found is None or found[0] not in _KEYWORD:
        raise ValueError(
            f"channel {label!r}: not a crank angle, time, pressure, volt, tdc, cycle "
            "or cylinder channel as the reader names them (give its role with the "
            "keyword arguments: angle=, time=, pressure=, tdc=)"
        )
    column, factor = found
    a = np.asarray(values, dtype=np.float64)
    return _KEYWORD[column], (a * factor if factor != 1.0 else a)


def _as_role(name: str, unit: str, values: Any, role: str) -> Tuple[str, np.ndarray]:
    """A channel given a role by the caller: its unit still read by the
    reader's tables (``role`` is the canonical column it stands for)."""
    unit = (unit or "").strip()
    probes = {
        "crank_deg": f"crank angle [{unit or 'deg'}]",
        "time_s": f"time [{unit or 's'}]",
        "pressure_bar": f"pressure [{unit or 'bar'}]",
        "tdc": "tdc",
    }
    found = _native.canonical(probes[role])
    if found is None:
        raise ValueError(f"channel {name!r}: unit {unit!r} is not one the reader knows for {role}")
    column, factor = found
    a = np.asarray(values, dtype=np.float64)
    return _KEYWORD[column], (a * factor if factor != 1.0 else a)


def _collect(
    channels: Sequence[Tuple[str, str, Any]],
    pressure: Sequence[str],
    angle: Optional[str],
    time: Optional[str],
    tdc: Optional[str],
    master: Optional[Tuple[str, str, Any]],
    unit: Optional[str] = None,
) -> Dict[str, Any]:
    by_name = {c[0]: c for c in channels}
    if unit is not None:
        by_name.update({n: (n, unit, by_name[n][2]) for n in pressure if n in by_name})
    out: Dict[str, Any] = {}

    def take(name: str, role: str) -> None:
        if name not in by_name:
            raise KeyError(f"no channel {name!r}; the channels are {sorted(by_name)}")
        n, u, v = by_name[name]
        key, values = _as_role(n, u, v, role)
        out[key] = values

    if angle is not None:
        take(angle, "crank_deg")
    if time is not None:
        take(time, "time_s")
    if tdc is not None:
        take(tdc, "tdc")
    if "angle_deg" not in out and "time_s" not in out and master is not None:
        try:
            key, values = convert(*master)
        except ValueError:
            key, values = _as_role(master[0], master[1], master[2], "time_s")
        out[key] = values
    pressures: List[np.ndarray] = []
    volts = False
    for name in pressure:
        if name not in by_name:
            raise KeyError(f"no channel {name!r}; the channels are {sorted(by_name)}")
        n, u, v = by_name[name]
        try:
            key, values = convert(n, u, v)
        except ValueError:
            key, values = _as_role(n, u, v, "pressure_bar")
        if key not in ("pressure_bar", "pressure_v"):
            key, values = _as_role(n, u, v, "pressure_bar")
        volts = volts or key == "pressure_v"
        pressures.append(values)
    if not pressures:
        raise ValueError("name the pressure channel(s): pressure=[...]")
    key = "pressure_v" if volts else "pressure_bar"
    out[key] = pressures[0] if len(pressures) == 1 else np.vstack(pressures)
    return out


def _missing(names: Sequence[str], channels: Sequence[str]) -> None:
    """A ``KeyError`` naming each channel asked for that the file lacks,
    with the channels it has."""
    lacking = [n for n in names if n not in channels]
    if lacking:
        raise KeyError(
            f"no channel {', '.join(repr(n) for n in lacking)}; the channels are {', '.join(sorted(set(channels)))}"
        )


def _unitless(channels: Sequence[Tuple[str, str, Any]], pressure: Sequence[str]) -> None:
    """A pressure channel without a unit is refused, as a file's pressure
    column without one is: bar, kPa, MPa and psi differ by the factors a
    wrong guess hides."""
    for name, unit, _ in channels:
        if name in pressure and not unit.strip():
            raise ValueError(
                f"channel {name!r} has no unit: give it with unit= (bar, kPa, MPa, psi or V), "
                "as a file's column names it"
            )


def read_mdf(
    path: Any,
    pressure: Union[str, Sequence[str]],
    angle: Optional[str] = None,
    time: Optional[str] = None,
    tdc: Optional[str] = None,
    unit: Optional[str] = None,
) -> Dict[str, Any]:
    """An MDF4 (or MDF3) file through asammdf: the pressure channel(s),
    with the angle master (``angle_deg``) or the time master (``time_s``)
    unless ``angle=`` or ``time=`` names another channel, and ``tdc=``.
    A pressure channel without a unit is refused unless ``unit=`` gives it
    (``"bar"``, ``"MPa"``, ``"psi"``, ``"V"`` …)."""
    try:
        from asammdf import MDF
    except ImportError as e:  # pragma: no cover - an optional extra
        raise ImportError("read_mdf needs asammdf: pip install enginedyn[mdf]") from e
    names = [pressure] if isinstance(pressure, str) else list(pressure)
    wanted = names + [c for c in (angle, time, tdc) if c is not None]
    with MDF(path) as mdf:
        _missing(wanted, list(mdf.channels_db))
        channels = []
        master = None
        for name in wanted:
            sig = mdf.get(name)
            channels.append((name, str(sig.unit or ""), np.asarray(sig.samples, dtype=np.float64)))
            if master is None:
                group = mdf.groups[mdf.whereis(name)[0][0]]
                m_name, m_unit = "time", "s"
                for ch in group.channels:
                    if getattr(ch, "channel_type", None) in (2, 3):  # master, virtual master
                        m_name, m_unit = ch.name, str(ch.unit or "")
                        break
                master = (m_name, m_unit, np.asarray(sig.timestamps, dtype=np.float64))
    if unit is None:
        _unitless(channels, names)
    return _collect(channels, names, angle, time, tdc, master, unit)


def read_tdms(
    path: Any,
    group: str,
    pressure: Union[str, Sequence[str]],
    angle: Optional[str] = None,
    time: Optional[str] = None,
    tdc: Optional[str] = None,
) -> Dict[str, Any]:
    """A LabVIEW TDMS file through npTDMS: channels of ``group`` (units from
    each channel's ``unit_string`` property; without ``angle=``/``time=``, the
    waveform's time track)."""
    try:
        from nptdms import TdmsFile
    except ImportError as e:  # pragma: no cover - an optional extra
        raise ImportError("read_tdms needs npTDMS: pip install enginedyn[tdms]") from e
    names = [pressure] if isinstance(pressure, str) else list(pressure)
    f = TdmsFile.read(path)
    g = f[group]
    channels = []
    master = None
    for ch in g.channels():
        unit = str(ch.properties.get("unit_string", ""))
        channels.append((ch.name, unit, ch[:]))
        if master is None and ch.name in names and "wf_increment" in ch.properties:
            master = ("time", "s", ch.time_track())
    return _collect(channels, names, angle, time, tdc, master)


def read_hdf5(
    path: Any,
    pressure: Union[str, Sequence[str]],
    angle: Optional[str] = None,
    time: Optional[str] = None,
    tdc: Optional[str] = None,
) -> Dict[str, Any]:
    """An HDF5 file through h5py: datasets by path (``/bench/p_cyl1``), each
    dataset's unit from its ``unit`` or ``units`` attribute."""
    try:
        import h5py
    except ImportError as e:  # pragma: no cover - an optional extra
        raise ImportError("read_hdf5 needs h5py: pip install enginedyn[hdf5]") from e
    names = [pressure] if isinstance(pressure, str) else list(pressure)
    wanted = names + [c for c in (angle, time, tdc) if c is not None]
    channels = []
    with h5py.File(path, "r") as f:
        for name in wanted:
            d = f[name]
            unit = d.attrs.get("unit", d.attrs.get("units", ""))
            if isinstance(unit, bytes):
                unit = unit.decode()
            channels.append((name, str(unit), d[()]))
    return _collect(channels, names, angle, time, tdc, None)
